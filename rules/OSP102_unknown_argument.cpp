// OSP102 unknown-argument: an argument the macro does not take.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP102",
    .name = "unknown-argument",
    .severity = Severity::Warning,
    .summary = "A macro call passes an argument the macro does not take",
    .category = RuleCategory::Suspicious,
};

class UnknownArgument final : public RuleBase<UnknownArgument> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a repeat gives the same arguments.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::documented_invocation(c);
        if (!spec) return;
        for (const auto& a : c->args) {
            if (!a.word) continue;
            if (a.spec || spec->arg(a.name)) continue;  // a.spec: linked to the call's spec, which is `spec`
            if (c->kind == CallKind::GCode && spec->arg_for_address(a.word->address)) continue;
            std::string msg;
            if (c->kind != CallKind::GCode && a.name.size() == 1) {
                msg = a.name + " is not an argument of " + spec->name + ": on a " +
                      std::string(macro::call_kind_name_short(c->kind)) +
                      " line arguments are written NAME=value (P-names), so this value is lost";
                if (const ArgSpec* p = spec->arg("P" + a.name)) msg += "; did you mean P" + a.name + "= (" + p->meaning + ")?";
            } else {
                msg = a.name + " is not an argument of " + spec->name +
                      ": the macro never reads it, so the value is silently lost";
                // Two-letter names are all one edit apart (PC, PX, PZ ...): suggest
                // only for longer names, where a close match means a typo.
                const ArgSpec* best = nullptr;
                for (const auto& s : spec->args)
                    if (a.name.size() >= 3 && macro::edit_distance(s.name, a.name) == 1) {
                        best = &s;
                        break;
                    }
                if (best) msg += "; did you mean " + best->name + " (" + best->meaning + ")?";
            }
            auto& d = ctx.report(kMeta, a.word->range, std::move(msg));
            std::string names;
            for (const auto& s : spec->args) names += (names.empty() ? "" : " ") + s.name;
            d.notes.push_back({spec->name + " takes: " + names + " (" + macro::args_ref(*spec) + ")", std::nullopt});
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP102() { return std::make_unique<UnknownArgument>(); }

}  // namespace osplint
