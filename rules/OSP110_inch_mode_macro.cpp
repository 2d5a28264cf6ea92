// OSP110 inch-mode-macro: an mm-only macro used while inch units are in effect.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP110",
    .name = "inch-mode-macro",
    .severity = Severity::Error,
    .summary = "A macro that works in mm only is used while inch units are in effect",
    .category = RuleCategory::WrongMotion,
    .reports_may = true,
};

class InchModeMacro final : public RuleBase<InchModeMacro> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same macro under the same units.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || spec->units != MacroUnits::MmOnly || !macro::is_invocation(*c)) return;
        if (!v.after.units.known) {
            if (const Origin* g20 = v.after.g20_from.find()) report_may_g20(ctx, *spec, *c, v.block, *g20);
            return;
        }
        if (!v.after.units.is(Units::Inch)) return;
        auto& d = ctx.report(kMeta, macro::call_range(*c, v.block),
                             spec->name + " works in the mm unit system only, but inch units (G20) are in effect: "
                                          "its internal distances are taken as inches and the tool moves 25.4 times "
                                          "too far; command G21 and metric values");
        d.notes.push_back({"\"Only the mm unit system can be used\" (" + macro::note_ref(ctx.catalog(), *spec, "mm unit") + ")", std::nullopt});
        if (auto from = macro::mode_from_subprogram(v.after, "G20"); !from.empty()) d.notes.push_back({from, std::nullopt});
    }

private:
    static void report_may_g20(RuleContext& ctx, const MacroSpec& spec, const MacroCall& c, const Block& b,
                               const Origin& g20) {
        Diagnostic* d = report_may(ctx, kMeta, macro::call_range(c, b),
                                   spec.name + " works in the mm unit system only, and inch units may be in effect "
                                               "here: " + macro::may_path(g20, "G20", "this call") +
                                       ", while other paths reach it in G21; under G20 its internal distances are "
                                       "taken as inches; command G21 before the call");
        if (!d) return;
        macro::add_may_notes(ctx, *d, g20, "G20");
        d->notes.push_back({"\"Only the mm unit system can be used\" (" +
                                macro::note_ref(ctx.catalog(), spec, "mm unit") + ")",
                            std::nullopt});
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP110() { return std::make_unique<InchModeMacro>(); }

}  // namespace osplint
