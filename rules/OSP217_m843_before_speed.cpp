// OSP217 m843-before-speed: M843 commanded before any spindle speed S.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP217",
    .name = "m843-before-speed",
    .severity = Severity::Warning,
    .summary = "M843 (synchronised tapping) before any S has been commanded",
    .category = RuleCategory::WrongMotion,
};

class M843BeforeSpeed final : public RuleBase<M843BeforeSpeed> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same M words, speed commanded or not as before.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line has no M word
    void check_block(RuleContext& ctx, const BlockView& v) override {
        if (!v.after.speed_commanded.is(false)) return;  // an S on the same block counts
        for (const auto& w : v.block.words) {
            if (w.address != "M" || !w.number || *w.number != 843) continue;
            ctx.report(kMeta, w.range,
                       "M843 starts the spindle for synchronised tapping, but no S has been commanded in this "
                       "program yet, so the speed it runs at is whatever the control last had; command the spindle "
                       "speed first (\"command the spindle speed first\", " + cite("fixed-cycles/g84-sync") +
                           "), e.g. on the positioning block before M843");
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP217() { return std::make_unique<M843BeforeSpeed>(); }

}  // namespace osplint
