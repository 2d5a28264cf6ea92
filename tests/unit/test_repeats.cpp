// The engine leaves a rule out on a block that repeats the block before it
// moved in the plane (Rule::quiet_on_repeat) exactly when it may: the
// blocks a probe rule that says it may be left out is shown, on a program
// that breaks each condition in turn. (That the built-in rules give the
// same findings either way is test_engine.cpp's differential test.)
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "api/config.h"
#include "engine/engine.h"
#include "support/io.h"

using namespace osplint;

namespace {

constexpr RuleMeta kProbe{
    .id = "OSP999",
    .name = "probe",
    .severity = Severity::Warning,
    .summary = "Notes the blocks it is shown; reports those with M9",
};

// Notes the line of every block it is shown, and reports a block with M9.
class Probe final : public RuleBase<Probe> {
public:
    explicit Probe(std::vector<uint32_t>* lines, std::map<uint32_t, ModalState>* states = nullptr,
                   std::optional<ModalState>* final_state = nullptr)
        : lines_(lines), states_(states), final_(final_state) {}
    const RuleMeta& meta() const override { return kProbe; }
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        lines_->push_back(v.block.line);
        if (states_) states_->insert_or_assign(v.block.line, v.before);
        if (v.block.has_code("M", 9)) ctx.report(kProbe, v.block.range, "M9");
    }
    void end_program(RuleContext&, const ProgramView& p) override {
        if (final_ && p.final_state) *final_ = *p.final_state;
    }

private:
    std::vector<uint32_t>* lines_;
    std::map<uint32_t, ModalState>* states_;
    std::optional<ModalState>* final_;
};

class ProbeRules final : public RuleRegistry {
public:
    explicit ProbeRules(std::vector<uint32_t>* lines, std::map<uint32_t, ModalState>* states = nullptr,
                        std::optional<ModalState>* final_state = nullptr)
        : lines_(lines), states_(states), final_(final_state) {}
    const std::vector<RuleMeta>& all() const override { return all_; }
    std::vector<std::unique_ptr<Rule>> make_all() const override {
        std::vector<std::unique_ptr<Rule>> rules;
        rules.push_back(std::make_unique<Probe>(lines_, states_, final_));
        return rules;
    }

private:
    std::vector<uint32_t>* lines_;
    std::map<uint32_t, ModalState>* states_;
    std::optional<ModalState>* final_;
    std::vector<RuleMeta> all_{kProbe};
};

// Watches the walk, which then reads every line (no shortcut from a line's text).
class Watcher final : public BlockObserver {
public:
    bool block(const BlockView&, const LineRef&) override { return true; }
};

// The engine on `text` with the probe's rules (and `observer`).
EngineStats probe_walk(const std::string& text, ProbeRules& rules, BlockObserver* observer) {
    EngineOptions options;
    options.rules = &rules;
    options.observer = observer;
    MemorySource src(text);
    DiscardFindings sink;
    EngineStats stats;
    const Config config;
    CHECK(run_engine("probe.min", src, config, options, sink, &stats).empty());
    return stats;
}

// What the probe sees of each block's state before it, and the final state,
// in a batch walk and in a walk an observer watches.
struct States {
    std::map<uint32_t, ModalState> before;
    std::optional<ModalState> final_state;
    uint64_t from_text = 0;
};

States states_seen(const std::string& text, bool watched) {
    States out;
    std::vector<uint32_t> lines;
    ProbeRules rules(&lines, &out.before, &out.final_state);
    Watcher watcher;
    out.from_text = probe_walk(text, rules, watched ? &watcher : nullptr).text_repeats;
    return out;
}

struct Shown {
    std::vector<uint32_t> lines;
    uint64_t repeats = 0;
    uint64_t from_text = 0;  // of them, told from their text (Walk::repeat_line)
};

Shown shown(const std::string& text) {
    Shown out;
    ProbeRules rules(&out.lines);
    const EngineStats stats = probe_walk(text, rules, nullptr);
    out.repeats = stats.repeats;
    out.from_text = stats.text_repeats;
    return out;
}

// The lines from `first` to `last` that the probe was not shown.
std::vector<uint32_t> left_out(const Shown& s, uint32_t first, uint32_t last) {
    std::vector<uint32_t> out;
    for (uint32_t line = first; line <= last; ++line)
        if (std::find(s.lines.begin(), s.lines.end(), line) == s.lines.end()) out.push_back(line);
    return out;
}

// Lines 1 to 4 of the probe's programs: a program name, G15, the tool above
// the work at a known place, the spindle on.
const std::string kStart = "O1000\nG15 H1\nG0 G90 X0 Y0 Z50.\nS600 M3\n";

std::string ozagr(const std::string& x, const std::string& y, const std::string& r) {
    return "CALL OZAGR PX=" + x + " PY=" + y + " PR=" + r + " PZ=-29. PI=6. PJ=1.5 PF=50 PS=600";
}

}  // namespace

TEST_CASE("engine: a rule is left out on a block that repeats the one before moved in the plane, and only then") {
    const auto call = ozagr;
    const std::string text =
        kStart                                     // 1-4
        + call("1.", "2.", "5.") + "\n"            // 5  the first call: sets the feed and Z
        + call("2.", "2.", "5.") + "\n"            // 6  leaves the state as it found it but for X and Y
        + call("3.", "2.", "5.") + "\n"            // 7  left out
        + call("3.", "2.", "5.") + "\n"            // 8  left out: the same place
        + call("4.", "2.", "4.") + "\n"            // 9  another value of another argument
        + call("5.", "2.", "4.") + "\n"            // 10 from another Z (the end of 9 is at its R)
        + call("6.", "2.", "4.") + " M9\n"         // 11 another word, and a finding
        + call("7.", "2.", "4.") + " M9\n"         // 12 after a finding
        + call("8.", "2.", "4.") + "\n"            // 13
        + "G0 Z50.\n"                              // 14 a plain move, not shown to the rule
        + call("9.", "2.", "4.") + "\n"            // 15 from another Z
        + call("10.", "2.", "4.") + "\n"           // 16
        + call("-11.5", "2.", "4.") + "\n"         // 17 left out
        + "X20. Y20.\n"                            // 18 a plain move, which moves only in the plane
        + call("12.", "2.", "4.") + "\n"           // 19 a block came between
        + call("12.", "-3.", "4.") + "\n"          // 20 left out: PY moved
        + call("13.", "3.", "4.") + " (HOLE)\n"    // 21 a comment
        + call("14.", "4.", "4.") + " (HOLE)\n"    // 22 left out
        + "N30 " + call("14.", "2.", "4.") + "\n"  // 23 a sequence name
        + call("15.", "2.", "4.") + "\n"           // 24
        + call("16.", "2.", "4.") + "\n"           // 25 left out
        + "G81 X1. Y1. Z-10. R2. F100\n"           // 26 a fixed cycle starts
        + "X2. Y1.\n"                              // 27 a hole
        + "X3. Y2.\n"                              // 28 left out
        + "X3. Y2. Z-12.\n"                        // 29 another depth
        + "X4. Y2. Z-12.\n"                        // 30
        + "X5. Y2. Z-12.\n"                        // 31 left out
        + "G18\n"                                  // 32
        + "X5. Y2. Z-12.\n"                        // 33 Y, now the cycle axis, returns
        + "X5. Y2. Z-14.\n"                        // 34 in G18 Z and X are the plane's
        + "X6. Y2. Z-16.\n"                        // 35 left out
        + "X6. Y3. Z-16.\n"                        // 36 another depth
        + "G80\n"                                  // 37
        + "M30\n";                                 // 38
    const Shown s = shown(text);
    const std::vector<uint32_t> out = left_out(s, 5, 38);
    CHECK(out == std::vector<uint32_t>{7, 8, 14, 17, 18, 20, 22, 25, 28, 31, 35});
    CHECK(s.repeats == out.size() - 2);  // all but the plain moves
    // The plain calls among them (not 22, with its comment) are told from
    // their text, and so are the holes (they set the position to their values).
    CHECK(s.from_text == 8);
}

TEST_CASE("engine: a call is told a repeat from its text only when its values are plain numbers") {
    const std::string text =
        kStart                                           // 1-4
        + ozagr("1.", "2.", "5.") + "\n"                 // 5  the first call
        + ozagr("2.", "2.", "5.") + "\n"                 // 6
        + ozagr("+3.", "2.", "5.") + "\n"                // 7  from its text: a plus sign
        + ozagr("4", "-2", "5.") + "\n"                  // 8  from its text: no point, a minus sign
        + ozagr("-.5", "2.", "5.") + "\n"                // 9  from its text: no integer part
        + ozagr("1234567890123456", "2.", "5.") + "\n"   // 10 16 digits: parsed, a repeat
        + ozagr("3.(C)", "2.", "5.") + "\n"              // 11 a comment glued on: no repeat
        + ozagr("4.", "2.", "5.") + "\n"                 // 12 after a block with a comment
        + ozagr("5.", "2.", "5.") + "\n"                 // 13 from its text
        + ozagr("1.2.3", "2.", "5.") + "\n"              // 14 not a number: no repeat
        + ozagr("6.", "2.", "5.") + "\n"                 // 15
        + ozagr("7.", "2.", "5.") + "\n"                 // 16 from its text
        + ozagr("8.", "2.", "5.") + "\n";                // 17 the last block (no M30): parsed, a repeat
    const Shown s = shown(text);
    CHECK(left_out(s, 5, 17) == std::vector<uint32_t>{7, 8, 9, 10, 13, 16, 17});
    CHECK(s.from_text == 5);
}

TEST_CASE("engine: positioning blocks and holes are told repeats from their text") {
    // Under MODIN the macro runs at every positioning block and leaves the
    // position in the plane unknown: once a block left the state as it found
    // it, the next ones are told from their text. A hole of G114 leaves the
    // position at its X and Y: its repeats are told from their text too,
    // and set that position to their values.
    const std::string text =
        kStart +                                                        // 1-4
        "MODIN OG87N PR=5. PZ=-25. PL=4. PI=2. PJ=6. PF=40 PS=500\n"    // 5
        "X1. Y1.\n"                                                     // 6  from a known position, Z50.
        "X2. Y1.\n"                                                     // 7  leaves the state as it found it
        "X3. Y-1.\n"                                                    // 8  from its text
        "X+4 Y.5\n"                                                     // 9  from its text
        "X5. Y1. M9\n"                                                  // 10 another word, and a finding
        "X6. Y1.\n"                                                     // 11 after a finding
        "X7. Y1.\n"                                                     // 12 from its text
        "MODOUT\n"                                                      // 13
        "G114 R10 Z-21.5 F1200 FA=1300 X0 Y0\n"                         // 14
        "X1. Y1.\n"                                                     // 15
        "X2. Y1.\n"                                                     // 16
        "X3. Y1.\n"                                                     // 17 from its text
        "X4. Y1.\n"                                                     // 18 from its text
        "M204\n"                                                        // 19
        "M30\n";                                                        // 20
    const Shown s = shown(text);
    CHECK(left_out(s, 5, 20) == std::vector<uint32_t>{8, 9, 12, 17, 18});
    CHECK(s.from_text == 5);
}

TEST_CASE("engine: a block told a repeat from its text leaves the state a walk that reads it would") {
    // Runs of calls, MODIN positioning blocks and holes of G81 and G114 with
    // random values, broken now and then: the state before every block the
    // probe sees, and the final state, are those of a walk an observer
    // watches (which reads every line and applies every block).
    std::mt19937 rng(20261206);
    const auto number = [&] { return std::to_string(static_cast<int>(rng() % 120) - 60) + (rng() % 2 ? "." : ".5"); };
    uint64_t from_text = 0;
    for (int program = 0; program < 6; ++program) {
        std::string text = kStart;
        for (int run = 0; run < 12; ++run) {
            const unsigned kind = rng() % 4;
            std::string head, line, tail;
            switch (kind) {
                case 0: line = "CALL OZAGR PX=%X PY=%Y PR=5. PZ=-29. PI=6. PJ=1.5 PF=50 PS=600"; break;
                case 1: head = "MODIN OG87N PR=5. PZ=-25. PL=4. PI=2. PJ=6. PF=40 PS=500\n", line = "X%X Y%Y", tail = "MODOUT\n"; break;
                case 2: head = "G81 X0 Y0 Z-10. R2. F100\n", line = "X%X Y%Y", tail = "G80\n"; break;
                default: head = "G114 R10 Z-21.5 F1200 FA=1300 X0 Y0\n", line = "X%X Y%Y", tail = "M204\nS600 M3\n"; break;
            }
            text += head;
            for (int i = 0, n = 3 + static_cast<int>(rng() % 12); i < n; ++i) {
                std::string l = line;
                for (const char* key : {"%X", "%Y"}) l.replace(l.find(key), 2, number());
                if (rng() % 10 == 0) text += rng() % 2 ? "G91\n" : "G90\n";
                text += l + "\n";
            }
            text += tail;
            if (rng() % 3 == 0) text += "G0 G90 X" + number() + " Y" + number() + "\n";
        }
        text += "G0 Z50.\nM30\n";
        const States batch = states_seen(text, false), watched = states_seen(text, true);
        from_text += batch.from_text;
        CHECK(watched.from_text == 0);
        CHECK(batch.before.size() > 20);
        for (const auto& [line, state] : batch.before) {
            const auto it = watched.before.find(line);
            REQUIRE_MESSAGE(it != watched.before.end(), "line " << line);
            CHECK_MESSAGE(it->second == state, "the state before line " << line << " of\n" << text);
        }
        CHECK(batch.final_state.has_value());
        CHECK(batch.final_state == watched.final_state);
    }
    CHECK(from_text > 50);
}
