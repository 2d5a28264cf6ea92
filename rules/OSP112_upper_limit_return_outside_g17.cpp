// OSP112 upper-limit-return-outside-g17: PM=52 / M52 asked for where the
// macro's action sequence returns to the Z+ limit only in G17.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP112",
    .name = "upper-limit-return-outside-g17",
    .severity = Severity::Warning,
    .summary = "PM=52/M52 given outside G17: the macro returns to the Z+ limit only in G17",
    .category = RuleCategory::WrongMotion,
    .reports_may = true,
};

// The action step that performs the upper-limit return "in G17 mode".
const ActionStep* g17_only_return(const MacroSpec& s) {
    for (const auto& st : s.action)
        if (st.when.required_plane() == 17 &&
            (st.when.mentions(ConditionAtom::Kind::MCode, 52) || st.when.mentions_value("PM", 52)))
            return &st;
    return nullptr;
}

class UpperLimitReturnOutsideG17 final : public RuleBase<UpperLimitReturnOutsideG17> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same PM, M words and plane.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || v.before.plane.is(Plane::G17)) return;
        const Origin* may = v.before.plane.known ? nullptr : v.before.plane_from.find();
        if (!v.before.plane.known && !may) return;
        const ActionStep* step = g17_only_return(*spec);
        if (!step) return;
        const MacroArg* pm = c->arg("PM");
        const Word* m52 = macro::m_code(*c, 52);
        ByteRange where;
        std::string asked;
        if (pm && pm->value.is(52) && (c->kind != CallKind::ModinPositioning)) {
            where = pm->word ? pm->word->range : macro::call_range(*c, v.block);
            asked = "PM=52";
        } else if (m52 && c->kind == CallKind::ModinPositioning) {
            where = m52->range;  // M52 during MODIN is read by the macro
            asked = "M52";
        } else {
            return;
        }
        const std::string consequence = ": the macro returns to the Z+ limit only in G17 mode, so the tool stays at "
                                        "the return level; retract explicitly after the call";
        Diagnostic* d = nullptr;
        if (may) {
            // The paths that reach the call disagree on the plane, and one of
            // them brings G18 or G19: a loop's jump or a branch.
            d = report_may(ctx, kMeta, where,
                           asked + " asks " + spec->name + " for the upper-limit return, but the plane may not be G17 "
                               "here: " + macro::may_path(*may, "G18 or G19", "this call") +
                               ", while other paths reach it in G17" + consequence);
            if (!d) return;
            macro::add_may_notes(ctx, *d, *may, "G18 or G19");
        } else {
            d = &ctx.report(kMeta, where,
                            asked + " asks " + spec->name + " for the upper-limit return, but the plane is " +
                                plane_name(v.before.plane.value) + consequence);
        }
        d->notes.push_back({"step " + step->step + ": \"" + step->text + "\" (" + macro::source_ref(*spec, step->source) + ")", std::nullopt});
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP112() { return std::make_unique<UpperLimitReturnOutsideG17>(); }

}  // namespace osplint
