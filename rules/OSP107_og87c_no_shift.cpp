// OSP107 og87c-no-shift: no non-zero shift in the positioning plane (the
// catalog's plane-dependent "at least one of" requirements; OG87C PI/PJ/PK).
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP107",
    .name = "og87c-no-shift",
    .severity = Severity::Error,
    .summary = "OG87C has no non-zero tool shift in the positioning plane (alarm)",
    .category = RuleCategory::Alarm,
};

class NoShift final : public RuleBase<NoShift> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat). Unless a shift it requires may be a position in the plane.
    bool quiet_on_repeat(const Config&, const MacroSpec* spec) const override {
        return !spec || !macro::reads_position_value(*spec);
    }
    // Only a macro that needs one of some arguments, on the line that calls it.
    bool sees_plain_calls_of(const MacroSpec& spec, CallKind kind) const override {
        return !spec.at_least_one.empty() && kind != CallKind::ModinPositioning;
    }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || !macro::is_invocation(*c) || spec->at_least_one.empty()) return;
        if (!v.before.plane.known) return;
        int plane = macro::plane_number(v.before.plane.value);
        for (const auto& req : spec->at_least_one) {
            if (req.plane && req.plane != plane) continue;
            bool some = false;
            std::string names;
            for (const auto& n : req.args) {
                names += (names.empty() ? "" : " or ") + n;
                const ArgSpec* a = spec->arg(n);
                const MacroArg* m = a ? macro::given(*c, *a) : c->arg(n);
                if (!m) continue;
                if (m->value.known && m->value.value == 0) continue;  // an explicit zero is no shift
                some = true;  // a non-zero value, or one osplint cannot know
            }
            if (some) continue;
            std::string msg = spec->name + " has no tool shift in G" + std::to_string(plane) + ": give " + names +
                              " (non-zero); without a shift the macro stops with an alarm";
            if (req.inferred) msg += " (the manual states this for G17; for this plane it is read from the plane table)";
            auto& d = ctx.report(kMeta, macro::call_range(*c, v.block), std::move(msg));
            d.notes.push_back({"at least one of " + names + " is required (" + macro::source_ref(*spec, req.source) + ")",
                               std::nullopt});
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP107() { return std::make_unique<NoShift>(); }

}  // namespace osplint
