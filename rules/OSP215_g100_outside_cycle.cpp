// OSP215 g100-outside-cycle: G100 (drilling ignore) where no fixed cycle is modal.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP215",
    .name = "g100-outside-cycle",
    .severity = Severity::Warning,
    .summary = "G100 outside a fixed cycle is ignored",
    .category = RuleCategory::Suspicious,
};

class G100OutsideCycle final : public RuleBase<G100OutsideCycle> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same G words under the same cycle.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line has no G word
    // Only a G100 word reports.
    uint8_t block_needs() const override { return kGWord; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const Word* g100 = nullptr;
        for (const auto& w : v.block.words)
            if (w.address == "G" && w.number && *w.number == 100) g100 = &w;
        if (!g100 || !no_cycle(v.before) || !no_cycle(v.after)) return;
        ctx.report(kMeta, g100->range,
                   "G100 is ignored here: it is valid only while a fixed cycle is modal (" + cite("fixed-cycles/g100") +
                       "), and no cycle is; the block runs as if G100 were not there. Command G100 on a hole block of the cycle "
                   "whose hole is to be skipped, or remove it");
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP215() { return std::make_unique<G100OutsideCycle>(); }

}  // namespace osplint
