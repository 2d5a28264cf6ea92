// OSP213 g82-without-dwell: G82 (counterboring) started without P.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP213",
    .name = "g82-without-dwell",
    .severity = Severity::Warning,
    .summary = "G82 without P: no dwell at the hole bottom",
    .category = RuleCategory::Suspicious,
    .reports_may = true,
};

class G82WithoutDwell final : public RuleBase<G82WithoutDwell> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same cycle, started before.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // no fixed cycle is modal on a plain call line
    // check_block returns at once unless a fixed cycle is modal after the block.
    uint8_t block_needs() const override { return kCycleAfter; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const ActiveCycle* c = active_cycle(v.after);
        if (!c || c->code != 82 || !c->macro.empty()) return;
        const CycleStart start = cycle_start(*c, v.block);
        const auto effect = [] {  // built only for a finding: every hole of a G82 comes here
            return "the tool does not dwell at the hole bottom, so the cycle works like G81 and loses the depth "
                   "accuracy the dwell gives a blind hole or counterbore (" + cite("fixed-cycles/g82") +
                   "); add P, the dwell in seconds (revolutions x 60 / S), or use G81";
        };
        if (start == CycleStart::Here && c->known_absent("P")) {
            ctx.report(kMeta, c->start_range.empty() ? v.block.range : c->start_range, "G82 has no P: " + effect());
        } else if (start == CycleStart::Unknown && !c->given("P")) {
            // A subprogram's first G82, or one at a loop head: a P given with
            // a G82 before it is still in effect on the paths where that G82 is.
            report_may(ctx, kMeta, c->command_range,
                       "G82 may have no P: on the paths where no G82 is modal before this block, " + effect());
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP213() { return std::make_unique<G82WithoutDwell>(); }

}  // namespace osplint
