// OSP302 cycle-axis-order: a macro's cycle-axis points are in an order its
// action sequence cannot run (R not above Z, A not above Z, no section left
// for the end vector ...). The relations come from the catalog; OSP103 leaves
// those between cycle-axis arguments to this rule.
#include <cmath>
#include <set>

#include "semantics/motion.h"
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP302",
    .name = "cycle-axis-order",
    .severity = Severity::Warning,
    .summary = "A macro's cycle-axis points are in an order its action sequence cannot run",
    .category = RuleCategory::WrongMotion,
};

struct Value {
    bool known = false;
    double value = 0;
    bool current = false;   // taken from the current cycle-axis position
    ByteRange range;        // the word on the line, when written there
};

struct Side {
    bool known = false;
    double value = 0;
    std::string shown;  // "5-1.5 = 3.5"
    std::string notes;
    bool current = false;
    ByteRange range;
};

// The side's value with the text of a finding. `lookup(name, arg, how)` gives
// a Value, and says in `how` (when not null) where a value not written on the
// line comes from ("not given: default 5"); `args` holds each term's argument
// (RelationSides).
template <class Lookup>
Side evaluate_side(const std::optional<std::vector<ExprTerm>>& terms, const std::vector<int>& args,
                   const Lookup& lookup) {
    Side s;
    if (!terms) return s;
    double sum = 0;
    std::string shown;
    for (size_t i = 0; i < terms->size(); ++i) {
        const ExprTerm& t = (*terms)[i];
        double v = t.number;
        if (!t.name.empty()) {
            std::string how;
            Value x = lookup(t.name, args[i], &how);
            if (!x.known) return s;
            v = x.value;
            if (!how.empty()) s.notes += (s.notes.empty() ? "" : "; ") + t.name + " " + how;
            s.current = s.current || x.current;
            if (s.range.empty() && !x.range.empty()) s.range = x.range;
        }
        sum += t.sign * v;
        std::string num = v < 0 && (i > 0 || t.sign < 0) ? "(" + motion_number(v) + ")" : motion_number(v);
        shown += (i == 0 ? (t.sign < 0 ? "-" : "") : (t.sign < 0 ? "-" : "+")) + num;
    }
    s.known = true;
    s.value = sum;
    s.shown = terms->size() == 1 ? motion_number(sum) : shown + " = " + motion_number(sum);
    return s;
}

// A side's value only, and whether it reads the current position: what every
// call needs (most relations hold, and then no text and no range are needed).
struct SideValue {
    bool known = false;
    double value = 0;
    bool current = false;
};
template <class Lookup>
SideValue side_value(const std::optional<std::vector<ExprTerm>>& terms, const std::vector<int>& args,
                     const Lookup& lookup) {
    SideValue s;
    if (!terms) return s;
    double sum = 0;
    for (size_t i = 0; i < terms->size(); ++i) {
        const ExprTerm& t = (*terms)[i];
        double v = t.number;
        if (!t.name.empty()) {
            Value x = lookup(t.name, args[i], nullptr);
            if (!x.known) return s;
            v = x.value;
            s.current = s.current || x.current;
        }
        sum += t.sign * v;
    }
    s.known = true;
    s.value = sum;
    return s;
}

// Whether a side may read the current position: it names a cycle-axis
// argument that, omitted, takes it (and has no default to take instead).
bool may_read_current(const std::vector<int>& args, const MacroSpec& spec) {
    for (int i : args) {
        if (i < 0) continue;
        const ArgSpec& a = spec.args[static_cast<size_t>(i)];
        if (!a.default_value && a.omitted == ArgOmitted::Current && a.role == ArgRole::Cycle) return true;
    }
    return false;
}

// A side made only of cycle-axis coordinates and numbers (PR, PZ+1): a point on the axis.
bool is_point(const std::string& text, const MacroSpec& spec) {
    const auto* terms = catalog_expr(text);
    if (!terms) return false;
    int names = 0;
    for (const auto& t : *terms) {
        if (t.name.empty()) continue;
        const ArgSpec* a = spec.arg(t.name);
        if (!a || a->role != ArgRole::Cycle || t.sign < 0) return false;
        ++names;
    }
    return names == 1;
}

class CycleAxisOrder final : public RuleBase<CycleAxisOrder> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat). Unless a relation it checks reads a position in the plane.
    bool quiet_on_repeat(const Config&, const MacroSpec* spec) const override {
        return !spec || !macro::reads_position_value(*spec);
    }
    // Only a macro whose catalog entry orders its points (not a cycle macro: G114).
    bool sees_plain_calls_of(const MacroSpec& spec, CallKind) const override {
        return !spec.relations.empty() && !(spec.has_form(MacroForm::GCode) && !spec.cancel.empty());
    }
    // A CALL the memo holds, whose relations read none of the arguments its
    // repeats change: check_block returns at the memo on each of them.
    bool quiet_on_repeat_of(const BlockView& v) const override {
        const MacroSpec* spec = macro::shop_macro(v.call);
        if (!spec || v.call->kind != CallKind::Call || !v.before.plane.known) return false;
        return quiet_.holds_repeat(*spec, *v.call, v.before.plane.value, macro::repeat_args(*spec, v.before.plane.value));
    }
    void begin_program(RuleContext&, const ProgramView&) override { reported_.clear(); }
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || spec->relations.empty()) return;
        // G-code macro cycles (OG84L/G114) follow the fixed-cycle order rules.
        if (spec->has_form(MacroForm::GCode) && !spec->cancel.empty()) return;
        if (c->kind != CallKind::Call && c->kind != CallKind::Modin && c->kind != CallKind::ModinPositioning &&
            c->kind != CallKind::GCode)
            return;
        std::optional<Plane> plane;
        if (v.before.plane.known) plane = v.before.plane.value;
        const char axis = plane ? plane_axes(*plane).cycle : 0;
        // A call the last quiet one decides (below): nothing to say.
        const bool memo = c->kind != CallKind::ModinPositioning;
        if (memo && quiet_.same(*spec, *c, plane)) return;
        // What keeps the check out of quiet_: a value read from the current
        // position, a name of no argument (none in a catalog that loads), a finding.
        bool outside_memo = false, reported = false;

        // `arg`: the argument `name` is (its index in the spec's args, -1: none);
        // `how`, only for a finding: where a value not on the line comes from.
        const auto lookup = [&](const std::string& name, int arg, std::string* how) -> Value {
            Value out;
            const ArgSpec* a = arg >= 0 ? &spec->args[static_cast<size_t>(arg)] : nullptr;
            if (!a) outside_memo = true;
            if (const MacroArg* m = a ? macro::given(*c, *a) : c->arg(name)) {
                if (!m->value.known) return out;
                out.known = true;
                out.value = m->value.value;
                if (m->word) out.range = m->word->range;
                return out;
            }
            if (!a) return out;
            if (a->default_value) {
                out.known = true;
                out.value = *a->default_value;
                if (how) *how = "not given: default " + motion_number(*a->default_value);
            } else if (a->omitted == ArgOmitted::Current && a->role == ArgRole::Cycle && axis) {
                // Only meaningful where the macro runs (a CALL line, a MODIN positioning block).
                if (c->kind == CallKind::Modin) return out;
                Val<double> cur = v.before.axis(axis);
                if (!cur.known) return out;
                out.known = true;
                out.value = cur.value;
                out.current = true;
                outside_memo = true;
                if (how) *how = "not given: the current " + std::string(1, axis) + " position " + motion_number(cur.value);
            } else if (a->omitted == ArgOmitted::None &&
                       (a->role == ArgRole::Length || a->role == ArgRole::Stroke || a->role == ArgRole::Shift)) {
                out.known = true;
                out.value = 0;
                if (how) *how = "not given: 0";
            }
            return out;
        };

        RelationSides local;
        for (size_t i = 0; i < spec->relations.size(); ++i) {
            const Relation& r = spec->relations[i];
            const RelationSides& sides = macro::sides_of(*spec, i, local);
            if (!sides.cycle_order) continue;
            // On a positioning block of an open MODIN, only a relation that
            // may read the current position can say anything new (below).
            if (c->kind == CallKind::ModinPositioning && !may_read_current(sides.left_args, *spec) &&
                !may_read_current(sides.right_args, *spec))
                continue;
            // Only what the call's own words decide.
            const Tri applies = r.when.eval([&](const ConditionAtom& at) {
                if (at.kind != ConditionAtom::Kind::Given) return Tri::Unknown;
                const ArgSpec* a = spec->arg(at.arg);
                return a && macro::given(*c, *a) ? Tri::True : Tri::False;
            });
            if (applies != Tri::True) continue;
            const SideValue lv = side_value(sides.left, sides.left_args, lookup);
            const SideValue rv = side_value(sides.right, sides.right_args, lookup);
            if (!lv.known || !rv.known) continue;
            const bool uses_current = lv.current || rv.current;
            // On positioning blocks of an open MODIN only the relations that
            // depend on the current position are new; report those once per MODIN.
            if (c->kind == CallKind::ModinPositioning) {
                if (!uses_current) continue;
                if (reported_.count({c->modin_line, i})) continue;
            }
            if (relation_holds(lv.value, r.op, rv.value)) continue;
            const Side l = evaluate_side(sides.left, sides.left_args, lookup);
            const Side rt = evaluate_side(sides.right, sides.right_args, lookup);
            report(ctx, v, *spec, r, l, rt, plane, axis);
            reported = true;
            if (c->kind == CallKind::ModinPositioning) reported_.insert({c->modin_line, i});
        }
        if (memo && !reported && !outside_memo) quiet_.remember(*spec, *c, plane, [](const MacroSpec& s, auto&& add) { macro::relation_args(s, add); });
    }

    bool same_as(const CycleAxisOrder& o) const { return reported_ == o.reported_; }

private:
    void report(RuleContext& ctx, const BlockView& v, const MacroSpec& spec, const Relation& r, const Side& l,
                const Side& rt, std::optional<Plane> plane, char axis) {
        std::string ax = axis ? std::string(1, axis) : std::string("the cycle axis");
        std::string need;
        const bool points = is_point(r.left, spec) && is_point(r.right, spec);
        if (points && (r.op == ">" || r.op == "<"))
            need = r.left + " must be " + (r.op == ">" ? "above " : "below ") + r.right + " on " + ax + " (" + r.left +
                   " " + r.op + " " + r.right + ")";
        else
            need = "it needs " + r.left + " " + r.op + " " + r.right;
        std::string msg = spec.name + " cannot run its action sequence in this order: " + need + ", but " + r.left +
                          " = " + l.shown + " and " + r.right + " = " + rt.shown;
        msg += " (" + macro::source_ref(spec, r.source) + ")";
        if (r.inferred)
            msg += std::string("; this ") + (points ? "order" : "constraint") +
                   " is inferred from the action sequence, the manual does not state it";
        ByteRange where = !l.range.empty() ? l.range : !rt.range.empty() ? rt.range : macro::call_range(*v.call, v.block);
        auto& d = ctx.report(kMeta, where, std::move(msg));
        if (!r.note.empty()) d.notes.push_back({r.note, std::nullopt});
        std::string how = l.notes;
        if (!rt.notes.empty()) how += (how.empty() ? "" : "; ") + rt.notes;
        if (!how.empty()) d.notes.push_back({how, std::nullopt});
        if (plane && r.plane && macro::plane_number(*plane) != r.plane)
            d.notes.push_back({std::string("the manual describes G") + std::to_string(r.plane) + "; in " +
                                   plane_name(*plane) + " the cycle axis is " + ax + " and \"above\" is read as +" +
                                   ax + " (horizontal use: the macro itself does not check this order, " +
                                   macro::common_ref(ctx.catalog(), spec, "order of the R point") + ")",
                               std::nullopt});
        if (v.call->kind == CallKind::ModinPositioning)
            d.notes.push_back({"the macro runs here because MODIN " + spec.name + " (line " +
                                   std::to_string(v.call->modin_line) + ") is open",
                               std::nullopt});
    }
    std::set<std::pair<uint32_t, size_t>> reported_;

    // The last call found quiet without reading the current position
    // (macro::QuietCall): what the check reads of a call is the macro, the
    // kind of call, the plane, and of each argument a relation or its
    // condition names whether it is given and its value.
    macro::QuietCall quiet_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP302() { return std::make_unique<CycleAxisOrder>(); }

}  // namespace osplint
