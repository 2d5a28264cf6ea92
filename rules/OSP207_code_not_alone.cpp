// OSP207 code-not-alone: M843 or M845 in a block together with another word.
#include <string>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP207",
    .name = "code-not-alone",
    .severity = Severity::Error,
    .summary = "M843 or M845 in a block with any other word",
    .category = RuleCategory::Alarm,
    .fix = FixSafety::Safe,
};

class CodeNotAlone final : public RuleBase<CodeNotAlone> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same M words.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line has no M word
    // Only an M843 or M845 word reports.
    uint8_t block_needs() const override { return kMWord; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const Block& b = v.block;
        for (const auto& w : b.words) {
            if (w.address != "M" || !w.number || (*w.number != 843 && *w.number != 845)) continue;
            const bool others = b.words.size() > 1 || !b.assignments.empty() || !b.statements.empty();
            if (!others) continue;
            const bool start = *w.number == 843;
            const std::string code = start ? "M843" : "M845";
            auto& d = ctx.report(kMeta, w.range,
                                 code + " shares this block with other words: M843 and M845 cannot be commanded "
                                        "together with any other word (" + cite("fixed-cycles/g84-sync") +
                                        "), the control rejects the block; write " + code + " alone on its own line " +
                                        (start ? "before the tapping cycle" : "after G80"));
            // Fix: move the code to a line of its own (before the block for M843,
            // after it for M845). Not offered when moving it would change which
            // blocks a jump or BLOCK SKIP reaches.
            if (b.sequence || b.block_delete) continue;
            // The line and the first character of its terminator, if any.
            const std::string_view line = ctx.text(ByteRange{b.range.begin, b.range.end + 1});
            const uint32_t base = b.range.begin;
            auto at = [&](uint32_t offset) { return line[offset - base]; };
            std::string indent;
            for (uint32_t i = b.range.begin; i < b.range.end && (at(i) == ' ' || at(i) == '\t'); ++i) indent += at(i);
            const uint32_t first = b.range.begin + static_cast<uint32_t>(indent.size());
            ByteRange cut = w.range;
            while (cut.begin > first && (at(cut.begin - 1) == ' ' || at(cut.begin - 1) == '\t')) --cut.begin;
            if (cut.begin == first)  // the first word: take the blanks after it instead
                while (cut.end < b.range.end && (at(cut.end) == ' ' || at(cut.end) == '\t')) ++cut.end;
            std::string eol = "\n";
            if (line.size() > b.range.size() && at(b.range.end) == '\r') eol = "\r\n";
            Fix fix;
            fix.safe = true;  // what the manual asks for, with the same meaning
            fix.title = "Move " + code + " to a line of its own";
            if (start) {
                fix.edits.push_back({ctx.resolve(ByteRange{b.range.begin, b.range.begin}), indent + code + eol});
                fix.edits.push_back({ctx.resolve(cut), ""});
            } else {
                fix.edits.push_back({ctx.resolve(cut), ""});
                fix.edits.push_back({ctx.resolve(ByteRange{b.range.end, b.range.end}), eol + indent + code});
            }
            d.fixes.push_back(std::move(fix));
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP207() { return std::make_unique<CodeNotAlone>(); }

}  // namespace osplint
