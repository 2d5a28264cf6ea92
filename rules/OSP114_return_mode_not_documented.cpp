// OSP114 return-mode-not-documented: M53/M54 written on the call of a macro
// whose manual documents no M53/M54 behaviour (OLPEX/OLPEY, OLAPX/OLAPY).
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP114",
    .name = "return-mode-not-documented",
    .severity = Severity::Error,
    .summary = "M53/M54 on the call of a macro whose manual documents no return-level behaviour",
    .category = RuleCategory::WrongMotion,
};

class ReturnModeNotDocumented final : public RuleBase<ReturnModeNotDocumented> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same M words.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        // Both families of wall-finishing macros: OLPEX/OLPEY document PM=52
        // only, their predecessors OLAPX/OLAPY neither PM nor PT.
        if (!spec || spec->m53 != M53Mode::Undocumented) return;
        if (c->kind != CallKind::Call && c->kind != CallKind::Modin) return;
        for (double code : {53.0, 54.0}) {
            const Word* w = macro::m_code(*c, code);
            if (!w) continue;
            auto& d = ctx.report(kMeta, w->range,
                                 "M" + macro::format_number(code) + " on the call of " + spec->name +
                                     ": its manual documents no M53/M54 return and no PT, so where the tool ends "
                                     "after the cycle is not defined; remove it and retract explicitly");
            d.notes.push_back({"the format of " + spec->name +
                                   (macro::is_subprogram_macro(*spec) ? " lists only PM=52 (" : " lists neither PM nor PT (") +
                                   macro::format_ref(*spec) + ")",
                               std::nullopt});
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP114() { return std::make_unique<ReturnModeNotDocumented>(); }

}  // namespace osplint
