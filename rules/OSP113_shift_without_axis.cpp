// OSP113 shift-without-axis: a shift argument the plane table gives no axis in
// the plane in effect (OG87C: PK in G17, PJ in G18, PI in G19).
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP113",
    .name = "shift-without-axis",
    .severity = Severity::Warning,
    .summary = "A shift argument has no axis in the plane in effect (blank in the plane table)",
    .category = RuleCategory::WrongMotion,
};

class ShiftWithoutAxis final : public RuleBase<ShiftWithoutAxis> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the shift arguments are not positions in the plane.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // Only a macro with a tool-shift argument, on the line that calls it.
    bool sees_plain_calls_of(const MacroSpec& spec, CallKind kind) const override {
        if (kind == CallKind::ModinPositioning) return false;
        for (const ArgSpec& a : spec.args)
            if (a.role == ArgRole::Shift) return true;
        return false;
    }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || !macro::is_invocation(*c) || !v.before.plane.known) return;
        int plane = macro::plane_number(v.before.plane.value);
        for (const auto& a : spec->args) {
            if (a.role != ArgRole::Shift) continue;
            const MacroArg* m = macro::given(*c, a);
            if (!m || !m->word) continue;
            if (m->value.known && m->value.value == 0) continue;
            if (a.axis(plane)) continue;
            auto& d = ctx.report(kMeta, m->word->range,
                                 a.name + " (" + a.meaning + ") has no axis in G" + std::to_string(plane) +
                                     ": the plane table of " + spec->name + " leaves it blank, so this shift is "
                                     "along the cycle axis and does not move the tool clear of the hole; give the "
                                     "shift on a positioning-plane axis instead");
            const PlaneTable* table = spec->plane_table.empty() ? nullptr : ctx.catalog().plane_table(spec->plane_table);
            d.notes.push_back({"plane table: " + macro::source_ref(*spec, table ? std::string_view(table->source) : ""),
                               std::nullopt});
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP113() { return std::make_unique<ShiftWithoutAxis>(); }

}  // namespace osplint
