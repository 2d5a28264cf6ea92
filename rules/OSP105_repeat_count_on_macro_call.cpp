// OSP105 repeat-count-on-macro-call: a Q repeat count on CALL/MODIN of these macros.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP105",
    .name = "repeat-count-on-macro-call",
    .severity = Severity::Error,
    .summary = "A Q repeat count on CALL/MODIN of a macro that does not support repeated calls",
    .category = RuleCategory::WrongMotion,
};

class RepeatCount final : public RuleBase<RepeatCount> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same Q word.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line has no Q word
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || !spec->has(Hazard::RepeatCountAbnormal) || !c->repeat) return;
        if (c->kind != CallKind::Call && c->kind != CallKind::Modin) return;
        auto& d = ctx.report(kMeta, c->repeat->range,
                             "Q repeats the call of " + spec->name + ", which does not support repeated calls: "
                             "some arguments are sign-inverted inside the macro, so from the 2nd call on the tool "
                             "may cut in the wrong direction without an alarm; write the call once per repetition");
        d.notes.push_back({"\"Multiple calls of the subprogram with a Q command are not supported\" (" +
                               macro::common_ref(ctx.catalog(), *spec, "Q count") +
                               "). The argument PQ is not a repeat count.",
                           std::nullopt});
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP105() { return std::make_unique<RepeatCount>(); }

}  // namespace osplint
