// OSP212 cut-after-spindle-stop: G80 or M204 ending G114 (OG84L) stops the
// spindle; a later cutting move without M3/M4 runs with the spindle stopped.
#include <map>
#include <set>

#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP212",
    .name = "cut-after-spindle-stop",
    .severity = Severity::Warning,
    .summary = "A cutting move after G80/M204 ended G114 (the spindle stopped) without M3/M4",
    .category = RuleCategory::WrongMotion,
    .blocks = RuleBlocks::All,
};

bool has_axis(const Block& b) {
    for (const auto& w : b.words)
        if (w.address == "X" || w.address == "Y" || w.address == "Z" || w.address == "A" || w.address == "B" ||
            w.address == "C")
            return true;
    for (const auto& s : b.statements)
        if (s.kind == StmtKind::CoordCalc) return true;
    return false;
}

class CutAfterSpindleStop final : public RuleBase<CutAfterSpindleStop> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same spindle state; a cut after a stop is reported once.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }

    void begin_program(RuleContext&, const ProgramView&) override {
        stops_.clear();
        reported_.clear();
        set_wants_plain_moves(true);
    }

    void check_block(RuleContext& ctx, const BlockView& v) override {
        const Block& b = v.block;
        // A plain move leaves the spindle as it is: only while it is stopped by
        // the end of a G114 mode can one be a cut to report.
        set_wants_plain_moves(v.after.spindle.is(5) && v.after.spindle_stopped_by.known &&
                              v.after.spindle_stopped_by.value != 0);
        if (v.after.spindle_stopped_by.is(b.line) && b.line != 0) stops_[b.line] = b.range;
        if (!v.after.spindle.is(5) || !v.after.spindle_stopped_by.known || v.after.spindle_stopped_by.value == 0)
            return;
        const uint32_t stop = v.after.spindle_stopped_by.value;
        if (stop == b.line || reported_.count(stop) || !has_axis(b)) return;
        std::string what;
        if (const ActiveCycle* c = active_cycle(v.after); c && c->macro.empty() && !v.after.ncyl && !v.after.g100)
            what = fmt::format("G{} machines a hole here", c->code);
        else if (no_cycle(v.after) && v.call == nullptr &&
                 (v.after.motion.is(1) || v.after.motion.is(2) || v.after.motion.is(3)))
            what = fmt::format("this G{} move cuts", v.after.motion.value);
        if (what.empty()) return;
        reported_.insert(stop);
        auto& d = ctx.report(kMeta, b.range,
                             what + " with the spindle stopped: the G114 cancel on line " + std::to_string(stop) +
                                 " stopped the spindle (\"the spindle stops too!\", " + cite("tap-cycle/differences") +
                                 ") and no M3/M4 follows it; command M3 (or M4) with S before this block");
        if (auto it = stops_.find(stop); it != stops_.end())
            d.notes.push_back({"the spindle stops here", ctx.resolve(it->second)});
    }

    bool same_as(const CutAfterSpindleStop& o) const { return stops_ == o.stops_ && reported_ == o.reported_; }
    template <class Move>
    bool each_range(Move&& move) {
        for (auto& [line, range] : stops_)
            if (!move(range)) return false;
        return true;
    }

private:
    std::map<uint32_t, ByteRange> stops_;
    std::set<uint32_t> reported_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP212() { return std::make_unique<CutAfterSpindleStop>(); }

}  // namespace osplint
