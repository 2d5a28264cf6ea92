// The envelope of a macro call (CALL, a positioning block of an open MODIN, a
// one-shot G-code macro): the catalog's action steps walked in order, each
// step's cycle-axis point worked out from the call's arguments; then the
// start point in the positioning plane and where the motion may spread there.
#include <array>
#include <cmath>
#include <map>

#include "semantics/conditions.h"
#include "semantics/motion_internal.h"
#include "semantics/transfer.h"

namespace osplint::motion_detail {

namespace {

// What the steps of a macro's envelope read: the block, its call and macro,
// the states around it, and the plane it runs in.
struct MacroRun {
    const Block& b;
    const ModalState& before;
    const ModalState& after;
    const MacroCall& call;
    const MacroSpec& spec;
    const Config* config;  // nullptr: the + travel limit is not known
    Plane plane;
    char axis;  // the cycle axis
    bool describe = true;  // false: values only, no text (the transfer step's end point)

    // The value of an argument: as written, the default, or (for a cycle-axis
    // argument that is omitted) the current position.
    ArgValue arg(const std::string& name) const { return arg_of(spec.arg(name), name); }
    // The same, with the spec's argument of that name already found (nullptr: none).
    ArgValue arg_of(const ArgSpec* as, const std::string& name) const {
        ArgValue out;
        if (const MacroArg* m = given_arg(call, as, name)) {
            if (m->value.known) {
                out.state = ArgValue::State::Known;
                out.value = m->value.value;
            } else {
                out.state = ArgValue::State::Unknown;
                if (describe)
                    out.how = m->word ? "value of \"" + m->word->value_text + "\" not known" : "value not known";
            }
            return out;
        }
        if (!as) return out;
        if (as->default_value) {
            out.state = ArgValue::State::Known;
            out.value = *as->default_value;
            if (describe) out.how = "not given: default " + num(*as->default_value);
            return out;
        }
        if (as->omitted == ArgOmitted::Current && as->role == ArgRole::Cycle) {
            Val<double> cur = before.axis(axis);
            if (cur.known) {
                out.state = ArgValue::State::Known;
                out.value = cur.value;
                if (describe) out.how = "not given: current position " + num(cur.value);
            } else {
                out.state = ArgValue::State::Unknown;
                if (describe)
                    out.how = "not given, and the current " + std::string(1, axis) + " position is not known";
            }
        }
        return out;
    }

    // What evaluate_expr gives for a step's expression, its terms read and
    // their arguments found once for the macro (StepSides): without text (with
    // `describe`, or for an expression not read, evaluate_expr itself).
    Evaluated step_value(const ActionStep& step, bool by, const Lookup& lookup, bool conditional) const {
        const StepSides* sides = describe ? nullptr : spec.step_sides(static_cast<size_t>(&step - spec.action.data()));
        const std::optional<std::vector<ExprTerm>>* read = sides ? (by ? &sides->by : &sides->target) : nullptr;
        if (!read || !*read) return evaluate_expr(by ? step.by : step.target, &spec, lookup, conditional, describe);
        const std::vector<ExprTerm>* terms = &**read;
        const std::vector<int>& args = by ? sides->by_args : sides->target_args;
        return sum_values(*terms, conditional, [&](size_t k) {
            const ArgSpec* as = args[k] >= 0 ? &spec.args[static_cast<size_t>(args[k])] : nullptr;
            return std::pair{arg_of(as, (*terms)[k].name), as};
        });
    }
    // Whether a step that has neither `target` nor `by` goes to the + travel limit.
    bool to_limit(const ActionStep& step) const {
        const StepSides* sides = spec.step_sides(static_cast<size_t>(&step - spec.action.data()));
        return sides ? sides->to_limit : contains_ci(step.text, "+ limit");
    }

    // Whether the return level M52/M53/M54 is in effect for the macro.
    Tri m_active(int code) const {
        if (code == 52 && spec.m52 == M52Mode::IgnoredUsePM52 && call.kind != CallKind::ModinPositioning)
            return Tri::False;  // M52 on a CALL line is not read by the subprogram
        if (!after.return_level.known) return Tri::Unknown;
        return after.return_level.value == code ? Tri::True : Tri::False;
    }

    // An atom of a step's `when` (catalog/condition.h).
    Tri atom(const ConditionAtom& a) const {
        using K = ConditionAtom::Kind;
        switch (a.kind) {
            case K::Plane: {
                const int pn = plane_number(plane);
                return pn == a.number ? Tri::True : Tri::False;
            }
            case K::Distance:
            case K::Spindle:
            case K::CutterComp: return modal_atom(a, before);
            case K::MCode: return m_active(a.number);
            case K::Given: return given_arg(call, spec.arg(a.arg), a.arg) ? Tri::True : Tri::False;
            case K::ArgEquals: {
                ArgValue v = arg(a.arg);
                if (v.state == ArgValue::State::Absent) return Tri::False;
                if (v.state == ArgValue::State::Unknown) return Tri::Unknown;
                return v.value == a.value ? Tri::True : Tri::False;
            }
        }
        return Tri::Unknown;
    }
};

// Where the tool is on the cycle axis while the action steps are walked.
struct ActionWalk {
    std::optional<Interval> cur;  // after the steps so far (nullopt: not known)
    bool end_known = true;        // whether `Envelope::end` is where the last step leaves the tool
};

// A step with a `target`: the cycle-axis position it reaches. False when the
// step does not run (an argument it needs is not given).
bool target_step(const MacroRun& run, const Lookup& lookup, const ActionStep& step, MotionPoint& p, ActionWalk& walk,
                 Envelope& env) {
    Evaluated e = run.step_value(step, false, lookup, !step.when.empty());
    if (e.skip) {
        if (run.describe) env.notes.push_back("step " + step.step + " (" + step.target + ") skipped: " + e.why);
        return false;
    }
    if (run.describe) {
        p.expr = step.target;
        p.mark = mark_for(step.target);
        p.worked = std::move(e.worked);
    }
    if (p.possible) {
        if (e.value.known) p.reach = Interval{e.value.value, e.value.value};
        if (run.describe) p.worked += " (runs only if " + step.when.text() + ", not known here)";
        walk.end_known = false;
    } else {
        p.value = e.value;
        walk.cur = e.value.known ? std::optional(Interval{e.value.value, e.value.value}) : std::nullopt;
        walk.end_known = true;
        env.end = e.value;
    }
    return true;
}

// A step with `by`: a stroke of stated length whose direction the manual does
// not print, so a possible point either way. False when the step does not run.
bool stroke_step(const MacroRun& run, const Lookup& lookup, const ActionStep& step, MotionPoint& p, ActionWalk& walk,
                 Envelope& env) {
    Evaluated e = run.step_value(step, true, lookup, false);
    if (e.skip) {
        if (run.describe) env.notes.push_back("step " + step.step + " (by " + step.by + ") skipped: " + e.why);
        return false;
    }
    if (run.describe) p.expr = "by " + step.by;
    p.possible = true;
    if (walk.cur && e.value.known) {
        double len = std::fabs(e.value.value);
        walk.cur = Interval{walk.cur->lo - len, walk.cur->hi + len};
        p.reach = walk.cur;
        if (run.describe)
            p.worked = "a stroke of " + num(len) + " in a direction the manual does not print: " + num(walk.cur->lo) +
                       " .. " + num(walk.cur->hi);
    } else {
        walk.cur.reset();
        if (run.describe)
            p.worked = "stroke of unprinted direction; " +
                       (e.value.known ? std::string("start of the stroke not known") : e.why);
    }
    walk.end_known = false;
    env.end = Val<double>{};
    return true;
}

// A step to the + travel limit of the cycle axis (M52 / PM=52).
void limit_step(const MacroRun& run, const ActionStep& step, MotionPoint& p, ActionWalk& walk, Envelope& env) {
    p.limit = true;
    p.mark = "+lim";
    p.expr = std::string(1, env.axis) + "+ limit";
    if (auto mx = run.config ? travel_max(*run.config, env.axis) : std::nullopt) {
        if (run.describe)
            p.worked = num(*mx) + " ([machine.travel] " + std::string(1, static_cast<char>(std::tolower(env.axis))) +
                       " max)";
        if (p.possible) p.reach = Interval{*mx, *mx};
        else p.value = Val<double>::of(*mx);
    } else if (run.describe) {
        p.worked = "the + travel limit ([machine.travel] not configured)";
    }
    if (p.possible) {
        if (run.describe) p.worked += " (runs only if " + step.when.text() + ", not known here)";
        walk.end_known = false;
    } else {
        walk.end_known = true;
        env.end = p.value;
        walk.cur = p.value.known ? std::optional(Interval{p.value.value, p.value.value}) : std::nullopt;
    }
}

// The action steps in order: a point for every step that moves the cycle
// axis and whose condition is not known to be false.
void walk_action(const MacroRun& run, const Lookup& lookup, Envelope& env) {
    const auto atom = [&](const ConditionAtom& a) { return run.atom(a); };
    ActionWalk walk;
    // A point a step at most, made in place (a point is seven strings: moving
    // one copies each), and taken back when its step moves nothing.
    env.points.reserve(env.points.size() + run.spec.action.size());
    for (const auto& step : run.spec.action) {
        Tri cond = step.when.eval(atom);
        if (cond == Tri::False) continue;
        const bool target = !step.target.empty(), by = !target && !step.by.empty();
        const bool limit = !target && !by && run.to_limit(step);
        if (!target && !by && !limit) continue;  // no cycle-axis motion
        MotionPoint& p = env.points.emplace_back();
        if (run.describe) p = step_point(step);
        p.inferred = step.inferred;
        p.possible = cond == Tri::Unknown;
        bool runs = true;
        if (target) runs = target_step(run, lookup, step, p, walk, env);
        else if (by) runs = stroke_step(run, lookup, step, p, walk, env);
        else limit_step(run, step, p, walk, env);
        if (!runs) env.points.pop_back();
    }
    if (!walk.end_known) env.end = Val<double>{};
}

// The `Envelope::end` walk_action leaves, without the points: only the last
// step that runs decides it (a step whose condition is not false and whose
// arguments are given), so the steps are read from the end and one or two
// are evaluated, as values only. The transfer step calls it on every macro
// call; the tests hold it to walk_action on the corpus.
Val<double> action_end(const MacroRun& run, const Lookup& lookup, char axis) {
    const auto atom = [&](const ConditionAtom& a) { return run.atom(a); };
    const auto& steps = run.spec.action;
    for (auto it = steps.rbegin(); it != steps.rend(); ++it) {
        const ActionStep& step = *it;
        const Tri cond = step.when.eval(atom);
        if (cond == Tri::False) continue;
        if (!step.target.empty()) {
            Evaluated e = run.step_value(step, false, lookup, !step.when.empty());
            if (e.skip) continue;
            return cond == Tri::True ? e.value : Val<double>{};
        }
        if (!step.by.empty()) {
            if (run.step_value(step, true, lookup, false).skip) continue;
            return {};  // a stroke of unprinted direction
        }
        if (run.to_limit(step)) {
            if (cond != Tri::True || !run.config) return {};
            auto mx = travel_max(*run.config, axis);
            return mx ? Val<double>::of(*mx) : Val<double>{};
        }
    }
    return {};
}

// The centre on each axis of the plane (two at most; no tree for them).
class PlaneCentre {
public:
    void set(char a, double v) {
        for (size_t i = 0; i < n_; ++i)
            if (at_[i].first == a) {
                at_[i].second = v;
                return;
            }
        if (n_ < at_.size()) at_[n_++] = {a, v};
    }
    std::optional<double> of(char a) const {
        for (size_t i = 0; i < n_; ++i)
            if (at_[i].first == a) return at_[i].second;
        return std::nullopt;
    }

private:
    std::array<std::pair<char, double>, 2> at_{};
    size_t n_ = 0;
};

// The positioning plane: the start point / hole centre, per axis (the block's
// own words for a MODIN positioning block, else the macro's position
// arguments), or the current position when none is given.
PlaneCentre plane_centre(const MacroRun& run, Envelope& env) {
    const Block& b = run.b;
    const ModalState& before = run.before;
    const PlaneAxes pa = plane_axes(run.plane);
    const int pn = plane_number(run.plane);
    PlaneCentre centre;
    for (char a : {pa.first, pa.second}) {
        std::optional<double> v;
        std::string what;
        if (run.call.kind == CallKind::ModinPositioning) {
            if (block_has_axis(b, a)) {
                v = block_axis_target(b, a, before);
                what = std::string(1, a);
            } else if (!b.statement(StmtKind::CoordCalc) && before.axis(a).known) {
                v = before.axis(a).value;
                what = "current " + std::string(1, a);
            }
        } else {
            const ArgSpec* pos = run.spec.position_arg(pn, a);
            const MacroArg* m = pos ? given_arg(run.call, pos, pos->name) : nullptr;
            if (m && m->value.known) {
                if (before.distance.is(Distance::Absolute)) v = m->value.value;
                else if (before.distance.is(Distance::Incremental) && before.axis(a).known)
                    v = before.axis(a).value + m->value.value;
                what = pos->name;
            } else if (!m && before.axis(a).known) {
                v = before.axis(a).value;
                what = "current " + std::string(1, a);
            }
        }
        if (v) {
            centre.set(a, *v);
            env.plane_points.push_back({a, *v, what});
        }
    }
    return centre;
}

// --- Where the motion spreads in the positioning plane --------------------------

// Intervals of the positioning-plane axes, widened from the centre.
class PlaneSpread {
public:
    PlaneSpread(const MacroSpec& spec, const Lookup& lookup, const PlaneCentre& centre)
        : spec_(spec), lookup_(lookup), centre_(centre) {}

    // A known argument value (nullopt: not an argument of the macro, or not known).
    std::optional<double> known(const std::string& n) const {
        if (!spec_.arg(n)) return std::nullopt;
        ArgValue v = lookup_(n);
        if (v.state != ArgValue::State::Known) return std::nullopt;
        return v.value;
    }
    std::optional<double> centre_of(char a) const { return centre_.of(a); }
    // Widens the interval of axis `a` (which starts at the centre) to reach `v`.
    void widen(char a, double v) {
        auto c = centre_of(a);
        if (!c) return;
        auto it = spans_.find(a);
        if (it == spans_.end()) it = spans_.emplace(a, Interval{*c, *c}).first;
        it->second.lo = std::min(it->second.lo, v);
        it->second.hi = std::max(it->second.hi, v);
    }
    const std::map<char, Interval>& spans() const { return spans_; }

private:
    const MacroSpec& spec_;
    const Lookup& lookup_;
    const PlaneCentre& centre_;
    std::map<char, Interval> spans_;
};

// Whether the macro cuts its contour with cutter-radius compensation (it takes
// a compensation number).
bool compensated(const MacroSpec& spec) {
    for (const auto& a : spec.args)
        if (a.role == ArgRole::CompNumber) return true;
    return false;
}

// OG87C: the cutting edge runs round the counterbore circle PC about the
// centre; steps 3/13 shift the oriented tool by PI/PJ(/PK).
void counterbore_spans(Envelope& env, const MacroSpec& spec, PlaneSpread& spread, Plane plane, bool describe) {
    const PlaneAxes pa = plane_axes(plane);
    const int pn = plane_number(plane);
    auto d = spread.known("PC");
    if (!d) return;
    double r = std::fabs(*d) / 2;
    for (char a : {pa.first, pa.second})
        if (auto c = spread.centre_of(a)) {
            spread.widen(a, *c - r);
            spread.widen(a, *c + r);
        }
    for (const auto& arg : spec.args) {
        if (arg.role != ArgRole::Shift) continue;
        auto ax = arg.axis(pn);
        auto v = spread.known(arg.name);
        if (!ax || !v || (*ax != pa.first && *ax != pa.second)) continue;
        if (auto c = spread.centre_of(*ax)) spread.widen(*ax, *c + *v);
    }
    for (auto& [a, iv] : spread.spans())
        env.plane_spans.push_back({a, iv, describe ? "counterbore circle PC=" + num(*d) + " about the centre, tool shift" : "",
                                   false, compensated(spec), "PC"});
}

// Keyways and wall finishing: the slot from the start point along PI (keyway:
// PJ wide; wall finishing: the end-point vector), the start point taken as
// one end of it.
void slot_spans(Envelope& env, const MacroSpec& spec, PlaneSpread& spread, Plane plane, bool describe) {
    const PlaneAxes pa = plane_axes(plane);
    const int pn = plane_number(plane);
    const ArgSpec* pi = spec.arg("PI");
    if (!pi) return;
    auto along = pi->axis(pn);
    auto len = spread.known("PI");
    if (!along || !len || (*along != pa.first && *along != pa.second)) return;
    char across = *along == pa.first ? pa.second : pa.first;
    auto s = spread.centre_of(*along);
    if (!s) return;
    std::string why;
    if (plane == Plane::G17) {
        spread.widen(*along, *s + *len);
        why = "start point to start+PI along " + std::string(1, *along);
    } else {
        // The direction of PI outside G17 is not reliably documented (the keyway and wall finishing manuals use different plane conventions): both ways.
        spread.widen(*along, *s - std::fabs(*len));
        spread.widen(*along, *s + std::fabs(*len));
        why = "PI either way along " + std::string(1, *along) + " (direction outside G17 not documented)";
    }
    if (spec.family == "keyway") {
        if (auto w = spread.known("PJ"); w && spread.centre_of(across)) {
            spread.widen(across, *spread.centre_of(across) - std::fabs(*w) / 2);
            spread.widen(across, *spread.centre_of(across) + std::fabs(*w) / 2);
            why += ", width PJ across";
        }
    } else {
        for (const auto& arg : spec.args) {
            if (arg.role != ArgRole::Vector) continue;
            auto ax = arg.axis(pn);
            auto v = spread.known(arg.name);
            if (!ax || !v) continue;
            if (*ax == *along) spread.widen(*ax, *s + (plane == Plane::G17 ? *len : std::fabs(*len)) + *v);
            else if (*ax == across) spread.widen(*ax, *spread.centre_of(across) + *v);
        }
    }
    for (auto& [a, iv] : spread.spans())
        env.plane_spans.push_back({a, iv, describe ? why + " (start point taken as one end)" : "", true, compensated(spec),
                                   a == *along ? "PI" : spec.family == "keyway" ? "PJ" : "",
                                   plane != Plane::G17 && a == *along});
}

void add_plane_spans(Envelope& env, const MacroSpec& spec, const Lookup& lookup, Plane plane,
                     const PlaneCentre& centre, bool describe) {
    PlaneSpread spread(spec, lookup, centre);
    if (spec.arg("PC") && spec.family == "back-counterbore") {
        counterbore_spans(env, spec, spread, plane, describe);
        return;
    }
    if (spec.family != "keyway" && spec.family != "wall-finishing") return;
    slot_spans(env, spec, spread, plane, describe);
}

}  // namespace

std::optional<Envelope> macro_envelope(const Block& b, const ModalState& before, const ModalState& after,
                                       const MacroCall& call, const MacroSpec& spec, const Config* config,
                                       bool describe, bool steps) {
    Envelope env;
    env.source = MotionSource::Macro;
    env.name = spec.name;
    env.call_kind = call.kind;
    env.line = b.line;
    env.origin_line = call.kind == CallKind::ModinPositioning ? call.modin_line : 0;
    if (call.kind == CallKind::GCode)
        for (const auto& w : b.words)
            if (w.range == call.name_range) env.code = w.address + (w.number ? num(*w.number) : w.value_text);
    env.incremental = before.distance.is(Distance::Incremental);
    if (!before.plane.known) {
        if (describe) env.notes.push_back("the plane (G17/G18/G19) is not known here, so neither is the cycle axis");
        finish(env);
        return env;
    }
    const Plane plane = before.plane.value;
    env.plane = plane;
    env.axis = plane_axes(plane).cycle;
    env.start = before.axis(env.axis);

    const MacroRun run{b, before, after, call, spec, config, plane, env.axis, describe};
    const auto arg = [&](const std::string& name) { return run.arg(name); };
    const Lookup lookup = arg;
    if (steps) walk_action(run, lookup, env);
    if (describe && spec.g91 == G91Mode::Unsupported && env.incremental)
        env.notes.push_back(spec.name + " does not work under G91 (its motion is shifted); the envelope is the G90 reading");
    if (describe && before.units.is(Units::Inch) && spec.units == MacroUnits::MmOnly)
        env.notes.push_back(spec.name + " works in mm only; the values are taken as written");

    add_plane_spans(env, spec, lookup, plane, plane_centre(run, env), describe);
    finish(env);
    return env;
}

std::optional<std::pair<char, double>> macro_end_point(const Block& b, const ModalState& before,
                                                       const ModalState& after, const MacroCall& call,
                                                       const MacroSpec& spec) {
    if (!before.plane.known) return std::nullopt;
    const char axis = plane_axes(before.plane.value).cycle;
    const MacroRun run{b, before, after, call, spec, nullptr, before.plane.value, axis, /*describe=*/false};
    const auto arg = [&](const std::string& name) { return run.arg(name); };
    const Lookup lookup = arg;
    const Val<double> end = action_end(run, lookup, axis);
    if (!end.known) return std::nullopt;
    return std::pair{axis, end.value};
}

}  // namespace osplint::motion_detail

namespace osplint {

using motion_detail::same_val;

MacroAxisMemo::Key MacroAxisMemo::key_of(const BlockView& v, const TravelLimits& travel, std::vector<ArgSeen>* args) {
    Key k;
    const MacroCall* c = v.call;
    if (!motion_detail::runs_macro(v.block, c)) return k;
    const MacroSpec& spec = *c->spec;
    const std::vector<uint16_t>* reads = spec.action_args();
    if (!reads) return k;
    k.spec = &spec;
    k.kind = c->kind;
    k.plane = v.before.plane;
    k.distance = v.before.distance;
    k.spindle = v.before.spindle;
    k.cutter_comp = v.before.cutter_comp;
    k.return_level = v.after.return_level;
    if (v.before.plane.known) {
        const char axis = plane_axes(v.before.plane.value).cycle;
        k.position = v.before.axis(axis);
        if (auto it = travel.find(axis); it != travel.end()) k.travel = it->second;
    }
    if (args) {
        args->clear();
        for (uint16_t i : *reads) args->push_back(ArgSeen::of(c->given(spec.args[i])));
    }
    return k;
}

bool MacroAxisMemo::same(const BlockView& v, const TravelLimits& travel) const {
    // key_of's reading, compared field by field as it goes: the same macro
    // and kind of call run the macro where key_of found it did, but for a
    // positioning block under NCYL.
    const MacroCall* c = v.call;
    if (!key_.spec || !c || c->spec != key_.spec || c->kind != key_.kind || v.block.kind != LineKind::Block) return false;
    if (c->kind == CallKind::ModinPositioning && v.block.statement(StmtKind::Ncyl)) return false;
    const ModalState& b = v.before;
    if (!same_val(b.plane, key_.plane) || !same_val(b.distance, key_.distance) || !same_val(b.spindle, key_.spindle) ||
        !same_val(b.cutter_comp, key_.cutter_comp) || !same_val(v.after.return_level, key_.return_level))
        return false;
    if (b.plane.known) {
        const char axis = plane_axes(b.plane.value).cycle;
        if (!same_val(b.axis(axis), key_.position)) return false;
        const auto it = travel.find(axis);
        const bool has = it != travel.end();
        if (has != key_.travel.has_value() ||
            (has && (it->second.min != key_.travel->min || it->second.max != key_.travel->max)))
            return false;
    }
    const std::vector<uint16_t>& reads = *key_.spec->action_args();
    for (size_t j = 0; j < reads.size(); ++j)
        if (!(ArgSeen::of(c->given(key_.spec->args[reads[j]])) == args_[j])) return false;
    return true;
}

void MacroAxisMemo::remember(const BlockView& v, const TravelLimits& travel) { key_ = key_of(v, travel, &args_); }

}  // namespace osplint
