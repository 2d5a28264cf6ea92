// OSP103 invalid-argument-value: a documented value constraint is broken.
#include <cmath>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP103",
    .name = "invalid-argument-value",
    .severity = Severity::Error,
    .summary = "An argument value breaks a constraint documented in the manual",
    .category = RuleCategory::Alarm,
};

struct Known {
    std::optional<double> value;
    ByteRange range;
};
// `lookup(arg)` gives a Known.
// `args`: each term's argument (RelationSides).
template <class Lookup>
std::optional<double> eval_terms(const std::vector<ExprTerm>& terms, const std::vector<int>& args,
                                 const MacroSpec& spec, const Lookup& lookup) {
    double sum = 0;
    for (size_t i = 0; i < terms.size(); ++i) {
        const ExprTerm& t = terms[i];
        double v = t.number;
        if (!t.name.empty()) {
            if (args[i] < 0) return std::nullopt;
            Known k = lookup(spec.args[static_cast<size_t>(args[i])]);
            if (!k.value) return std::nullopt;
            v = *k.value;
        }
        sum += t.sign * v;
    }
    return sum;
}


template <class Lookup>
void check_values(RuleContext& ctx, const MacroSpec& spec, const Lookup& lookup, std::optional<Plane> plane,
                  ByteRange fallback) {
    for (const auto& a : spec.args) {
        if (a.allowed.empty() && a.sign == ArgSign::Any) continue;  // nothing to check
        Known k = lookup(a);
        if (!k.value || k.range.empty()) continue;
        double v = *k.value;
        // Made only for a finding: most calls have none, and a citation is a table search.
        auto shown = [&] { return a.name + "=" + macro::format_number(v); };
        auto src = [&] { return macro::source_ref(spec, a.source); };
        if (!a.allowed.empty()) {
            if (std::find(a.allowed.begin(), a.allowed.end(), v) == a.allowed.end()) {
                std::string list;
                for (double x : a.allowed) list += (list.empty() ? "" : " or ") + macro::format_number(x);
                ctx.report(kMeta, k.range,
                           shown() + " is not a value " + spec.name + " accepts: " + a.name + " (" + a.meaning +
                               ") must be " + list + " (" + src() + "); the macro stops with an alarm or does "
                               "something the manual does not define");
                continue;
            }
        }
        const char* need = nullptr;
        switch (a.sign) {
            case ArgSign::Positive: if (!(v > 0)) need = "greater than 0"; break;
            case ArgSign::NonNegative: if (v < 0) need = "0 or more (an unsigned distance)"; break;
            case ArgSign::NonZero: if (v == 0) need = "non-zero"; break;
            case ArgSign::Any: break;
        }
        if (!need) continue;
        auto& d = ctx.report(kMeta, k.range,
                             shown() + ": " + a.name + " (" + a.meaning + ") of " + spec.name + " must be " + need +
                                 " (" + src() + "); the macro stops with an alarm or moves the wrong way");
        if (a.always_incremental && v <= 0) {
            std::string note = a.name + " is an amount, always incremental, even under G90: a zero or negative "
                               "value is often a coordinate written where the amount belongs";
            // Where the manual gives no sign, the check is a reading the configuration can change.
            if (spec.kind == SpecKind::FixedCycle && spec.reading("peck-amount-sign"))
                note += "; the manual gives no sign, and this reading can be changed with `[cycle." + spec.name +
                        ".arg." + a.name + "] sign = \"any\"`";
            d.notes.push_back({note, std::nullopt});
        }
    }
    RelationSides local;
    for (size_t i = 0; i < spec.relations.size(); ++i) {
        const Relation& r = spec.relations[i];
        const RelationSides& sides = macro::sides_of(spec, i, local);
        if (sides.cycle_order) continue;  // OSP302's
        if (r.plane && (!plane || macro::plane_number(*plane) != r.plane)) continue;
        // Only what the call's own words decide; a condition on the modal
        // state is left to the motion rules.
        const Tri applies = r.when.eval([&](const ConditionAtom& at) {
            if (at.kind != ConditionAtom::Kind::Given) return Tri::Unknown;
            const ArgSpec* a = spec.arg(at.arg);
            return a && lookup(*a).value ? Tri::True : Tri::False;
        });
        if (applies != Tri::True) continue;
        if (!sides.left || !sides.right) continue;
        auto l = eval_terms(*sides.left, sides.left_args, spec, lookup);
        auto rv = eval_terms(*sides.right, sides.right_args, spec, lookup);
        if (!l || !rv || relation_holds(*l, r.op, *rv)) continue;
        ByteRange where = fallback;
        for (int k : sides.left_args)
            if (k >= 0)
                if (const ArgSpec& a = spec.args[static_cast<size_t>(k)]; !lookup(a).range.empty()) {
                    where = lookup(a).range;
                    break;
                }
        auto& d = ctx.report(kMeta, where,
                             spec.name + " needs " + r.left + " " + r.op + " " + r.right + ", but " + r.left + " = " +
                                 macro::format_number(*l) + " and " + r.right + " = " + macro::format_number(*rv) +
                                 " (" + macro::source_ref(spec, r.source) + ")" +
                                 (r.inferred ? "; this constraint is inferred from the manual, not stated" : ""));
        if (!r.note.empty()) d.notes.push_back({r.note, std::nullopt});
    }
}

class InvalidArgumentValue final : public RuleBase<InvalidArgumentValue> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat). Unless a constraint or relation it checks reads a position in the plane.
    bool quiet_on_repeat(const Config& config, const MacroSpec* spec) const override {
        return !macro::reads_position_value(config.catalog, spec);
    }
    // A CALL whose constraints and relations read none of the arguments its
    // repeats change; a hole of a G-code macro cycle (G114): the cycle's
    // arguments were checked where it was commanded, and its repeats have
    // none; a hole of a fixed cycle whose checks read neither of the plane's
    // axis words (check_block found so).
    bool quiet_on_repeat_of(const BlockView& v) const override {
        if (const MacroSpec* spec = macro::shop_macro(v.call)) return macro::quiet_on_call_repeats(*spec, v);
        if (v.call || !v.after.cycle.known || !v.after.cycle.value) return false;
        return !v.after.cycle.value->macro.empty() || (quiet_hole_line_ != 0 && quiet_hole_line_ == v.block.line);
    }
    // quiet_hole_line_ is a note for quiet_on_repeat_of, not state: what the rule reports is the same without it.
    bool same_as(const InvalidArgumentValue&) const { return true; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        quiet_hole_line_ = 0;
        std::optional<Plane> plane;
        if (v.before.plane.known) plane = v.before.plane.value;
        // Macro calls: the arguments written on the invoking line.
        if (const MacroSpec* spec = macro::shop_macro(v.call); spec && macro::is_invocation(*v.call)) {
            const MacroCall& c = *v.call;
            const auto lookup = [&](const ArgSpec& a) -> Known {
                if (const MacroArg* m = macro::given(c, a); m && m->word)
                    return {m->value.known ? std::optional(m->value.value) : std::nullopt, m->word->range};
                return {};
            };
            check_values(ctx, *spec, lookup, plane, macro::call_range(c, v.block));
            return;
        }
        // Fixed cycles: the addresses written on a block while the cycle is modal.
        if (!v.after.cycle.known || !v.after.cycle.value || !v.after.cycle.value->macro.empty()) return;
        const CycleSpec* cycle = ctx.catalog().find_cycle(v.after.cycle.value->code);
        if (!cycle) return;
        const auto lookup = [&](const ArgSpec& a) -> Known {
            // Not an operand of a hole pattern on the block (`BHC X0 Y0 I50. J0 K6`: its J is an angle).
            const Word* w = find_address(v.block, a.name);
            for (size_t i = 0; !w && i < a.aliases.size(); ++i) w = find_address(v.block, a.aliases[i]);
            if (!w) return {};
            std::optional<double> value = w->number;
            if (!value && w->value != kNoExpr) value = ctx.eval(v.block, w->value, v.before);
            return {value, w->range};
        };
        check_values(ctx, *cycle, lookup, plane, v.block.range);
        if (plane) {
            // Whether the checks read the word of a plane axis (by the argument's name or an alias).
            const PlaneAxes pa = plane_axes(*plane);
            const auto names_plane_axis = [&](const ArgSpec& a) {
                const auto axis = [&](const std::string& n) {
                    return n.size() == 1 && (n[0] == pa.first || n[0] == pa.second);
                };
                return axis(a.name) || std::any_of(a.aliases.begin(), a.aliases.end(), axis);
            };
            if (!macro::reads_value_of(*cycle, names_plane_axis)) quiet_hole_line_ = v.block.line;
        }
    }

private:
    uint32_t quiet_hole_line_ = 0;  // the line of the last hole whose repeats are quiet (0: none)
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP103() { return std::make_unique<InvalidArgumentValue>(); }

}  // namespace osplint
