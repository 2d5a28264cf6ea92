// OSP209 repeat-count-in-g90: L (repeat count) on a fixed cycle in G90 mode.
#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP209",
    .name = "repeat-count-in-g90",
    .severity = Severity::Warning,
    .summary = "L (repeat count) on a fixed cycle in G90: valid only under G91",
    .category = RuleCategory::Suspicious,
};

class RepeatCountInG90 final : public RuleBase<RepeatCountInG90> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same L word under the same cycle.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // no fixed cycle is modal on a plain call line
    // check_block returns at once unless a fixed cycle is modal after the block.
    uint8_t block_needs() const override { return kCycleAfter; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const ActiveCycle* c = active_cycle(v.after);
        if (!c || !c->macro.empty() || v.block.has_code("G", 80)) return;
        const Word* l = v.block.find("L");
        if (!l || !v.after.distance.is(Distance::Absolute)) return;
        const CycleSpec* spec = ctx.catalog().find_cycle(c->code);
        if (!spec) return;
        const ArgSpec* arg = spec->arg("L");
        if (!arg || !arg->g91_only) return;
        std::string src = macro::source_ref(*spec, arg->source);
        ctx.report(kMeta, l->range,
                   fmt::format("L{} (repeat count) on G{} is valid only in G91 mode ({}): under G90 it does not "
                               "give a row of holes, since every repetition names the same absolute position; use "
                               "G91 with incremental X/Y steps for the row, or write one block per hole in G90",
                               l->value_text, c->code, src));
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP209() { return std::make_unique<RepeatCountInG90>(); }

}  // namespace osplint
