// OSP214 g83-dwell-without-j: P on G83 has an effect only when J is commanded.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP214",
    .name = "g83-dwell-without-j",
    .severity = Severity::Warning,
    .summary = "P (dwell) on G83 without J: the dwell is not performed",
    .category = RuleCategory::Suspicious,
};

class G83DwellWithoutJ final : public RuleBase<G83DwellWithoutJ> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same P word under the same cycle.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // no fixed cycle is modal on a plain call line
    // check_block returns at once unless a fixed cycle is modal after the block.
    uint8_t block_needs() const override { return kCycleAfter; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const ActiveCycle* c = active_cycle(v.after);
        if (!c || c->code != 83 || !c->macro.empty() || v.block.has_code("G", 80)) return;
        const Word* p = v.block.find("P");
        if (!p || !c->known_absent("J")) return;
        ctx.report(kMeta, p->range,
                   "P" + p->value_text + " on G83 has no effect: the dwell is valid only when J (the withdrawal "
                   "amount) is commanded (" + cite("fixed-cycles/g83") +
                       "), and this pick cycle has no J, so it returns to R after every peck without dwelling; add J, or remove P");
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP214() { return std::make_unique<G83DwellWithoutJ>(); }

}  // namespace osplint
