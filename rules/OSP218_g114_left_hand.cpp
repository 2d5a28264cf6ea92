// OSP218 g114-left-hand: G114 (OG84L) with the spindle in reverse (M4).
#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP218",
    .name = "g114-left-hand",
    .severity = Severity::Warning,
    .summary = "G114 (OG84L) with the spindle in reverse: there is no left-hand version",
    .category = RuleCategory::WrongMotion,
};

class G114LeftHand final : public RuleBase<G114LeftHand> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same spindle state under the same cycle.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // no fixed cycle is modal on a plain call line
    uint8_t block_needs() const override { return kCycleAfter; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const ActiveCycle* c = active_cycle(v.after);
        if (!c || c->macro.empty() || !v.after.spindle.is(4) || v.block.has_code("G", 80)) return;
        const MacroSpec* spec = ctx.catalog().find(c->macro);
        if (!spec || !spec->tapping) return;
        // Report where the combination starts.
        const ActiveCycle* was = active_cycle(v.before);
        if (was && was->start_line == c->start_line && v.before.spindle.is(4)) return;
        ByteRange where = c->start_line == v.block.line && !c->start_range.empty() ? c->start_range : v.block.range;
        for (const auto& w : v.block.words)
            if (w.address == "M" && w.number && *w.number == 4) where = w.range;
        ctx.report(kMeta, where,
                   fmt::format("G{} ({}) runs with the spindle in reverse (M4): there is no left-hand-thread version "
                               "of this tapping cycle ({}), the auto-reverse tapper is driven the wrong "
                               "way; use M3 and a right-hand tap, or left-hand tapping only with the optional "
                               "spindle-reversal function",
                               c->code, c->macro, cite("tap-cycle/conditions")));
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP218() { return std::make_unique<G114LeftHand>(); }

}  // namespace osplint
