// OSP220 g88-shift-from-parameters: G88 (fine boring) without I and J: the
// shift direction and amount come from setting parameters.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP220",
    .name = "g88-shift-from-parameters",
    .severity = Severity::Warning,
    .summary = "G88 without I/J: the relief shift comes from the setting parameters",
    .category = RuleCategory::Suspicious,
    .reports_may = true,
};

class G88ShiftFromParameters final : public RuleBase<G88ShiftFromParameters> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same cycle, started before.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // no fixed cycle is modal on a plain call line
    // check_block returns at once unless a fixed cycle is modal after the block.
    uint8_t block_needs() const override { return kCycleAfter; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const ActiveCycle* c = active_cycle(v.after);
        if (!c || c->code != 88 || !c->macro.empty()) return;
        const CycleStart start = cycle_start(*c, v.block);
        const auto effect = [] {  // built only for a finding: every hole of a G88 comes here
            return "after the oriented stop the tool is relieved by the shift direction and amount stored in the "
                   "setting parameters (" + cite("fixed-cycles/g88") +
                   "); if this tool's edge is oriented differently from what they assume, the relief goes the wrong "
                   "way or by the wrong amount and the edge drags on the bore. Command I and J explicitly for this tool";
        };
        if (start == CycleStart::Here && c->known_absent("I") && c->known_absent("J")) {
            ctx.report(kMeta, c->start_range.empty() ? v.block.range : c->start_range,
                       "G88 has neither I nor J: " + effect());
        } else if (start == CycleStart::Unknown && !c->given("I") && !c->given("J")) {
            // As OSP213: I and J given with a G88 before it may still be in effect.
            report_may(ctx, kMeta, c->command_range,
                       "G88 may have neither I nor J: on the paths where no G88 is modal before this block, " +
                           effect());
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP220() { return std::make_unique<G88ShiftFromParameters>(); }

}  // namespace osplint
