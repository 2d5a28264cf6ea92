// OSP303 cycle-axis-unbounded: the cycle-axis envelope of a macro call or a
// fixed-cycle hole cannot be bounded, so OSP301 cannot check it.
#include "semantics/motion.h"
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP303",
    .name = "cycle-axis-unbounded",
    .severity = Severity::Info,
    .summary = "The cycle-axis motion of a call or hole cannot be bounded (a value or the start is unknown)",
    .category = RuleCategory::Suspicious,
    .enabled_by_default = false,
    .analysis_switch = "explain-unknown",
};

void report_unbounded_envelope(RuleContext& ctx, const BlockView& v, const Envelope& env) {
    ByteRange where = v.call ? macro::call_range(*v.call, v.block) : v.block.range;
    std::string msg;
    if (!env.plane) {
        msg = "the cycle-axis motion of " + env.title() + " cannot be bounded: the plane (G17/G18/G19) is not known " +
              "here, so neither is the cycle axis";
    } else {
        auto unknown = env.unknown_points();
        std::string axis(1, env.axis);
        msg = "the " + axis + " motion of " + env.title() + " cannot be bounded";
        if (env.lowest && env.highest && env.lowest->value != env.highest->value)
            msg += " (the known points span " + axis + motion_number(env.lowest->value) + " to " + axis +
                   motion_number(env.highest->value) + ")";
        if (!unknown.empty()) msg += ": " + unknown.front()->describe();
        msg += "; travel limits cannot be checked for it";
        if (!unknown.empty()) {
            // Point at the word whose value is not known, when it is on this line.
            if (const auto* terms = catalog_expr(unknown.front()->expr))
                for (const auto& t : *terms) {
                    if (t.name.empty()) continue;
                    if (v.call)
                        if (const MacroArg* a = v.call->arg(t.name); a && a->word && !a->value.known) {
                            where = a->word->range;
                            break;
                        }
                }
        }
    }
    auto& d = ctx.report(kMeta, where, std::move(msg));
    auto unknown = env.unknown_points();
    for (size_t i = 1; i < unknown.size() && i < 4; ++i) d.notes.push_back({unknown[i]->describe(), std::nullopt});
    d.notes.push_back({"osplint never guesses a value it cannot know: give the argument as a number, or set the "
                       "position with an absolute move before the call",
                       std::nullopt});
}

class CycleAxisUnbounded final : public RuleBase<CycleAxisUnbounded> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        if (!v.reachable) return;
        // The values decide; the text of a finding needs the envelope in full.
        std::optional<Envelope> env = cycle_envelope(v, ctx.config(), EnvelopeDetail::Values);
        if (!env || env->bounded()) return;
        env = cycle_envelope(v, ctx.config());
        if (env && !env->bounded()) report_unbounded_envelope(ctx, v, *env);
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP303() { return std::make_unique<CycleAxisUnbounded>(); }

}  // namespace osplint
