// The envelope of a hole of a fixed cycle (G81 ...) or of a G-code macro
// cycle (OG84L via G114): the I point, R and Z in absolute terms (fixed cycles manual),
// the macro's own sequence when it has one, the return after the hole (M52 /
// M53 / M54, else G98 / G99), and the hole position in the positioning plane.
#include <fmt/format.h>

#include "semantics/motion_internal.h"
#include "semantics/transfer.h"

namespace osplint::motion_detail {

namespace {

// I point: where the hole starts (fixed cycles manual, "Basic motion"; under
// G99 the previous block's position).
MotionPoint initial_point(const Envelope& env) {
    MotionPoint ip;
    ip.step = "I";
    ip.label = "I point";
    ip.mark = "I";
    ip.expr = "I";
    ip.source = "004:L6";
    ip.text = "initial point: the cycle-axis position when the hole starts";
    ip.value = env.start;
    ip.start = true;
    ip.worked = env.start.known ? num(env.start.value)
                                : "? (the " + std::string(1, env.axis) + " position before the block is not known)";
    return ip;
}

// R and Z in absolute terms (G91: R from the I point, Z from R; 004:L12-13).
struct HoleLevels {
    ArgValue r, z;
};

HoleLevels absolute_levels(const ActiveCycle& c, const ModalState& before, const Envelope& env) {
    const std::string ax(1, env.axis);
    HoleLevels l;
    ArgValue& r = l.r;
    ArgValue& z = l.z;
    if (!before.distance.known) {
        r.state = z.state = ArgValue::State::Unknown;
        r.how = z.how = "G90/G91 not known";
        return l;
    }
    if (!c.r.known) {
        r.state = ArgValue::State::Unknown;
        r.how = "R not known";
    } else if (!env.incremental) {
        r.state = ArgValue::State::Known;
        r.value = c.r.value;
    } else if (env.start.known) {
        r.state = ArgValue::State::Known;
        r.value = env.start.value + c.r.value;
        r.how = "under G91 from the I point: " + num(env.start.value) + (c.r.value < 0 ? "" : "+") +
                num(c.r.value) + " = " + num(r.value);
    } else {
        r.state = ArgValue::State::Unknown;
        r.how = "under G91 R is measured from the I point, which is not known";
    }
    if (!c.z.known) {
        z.state = ArgValue::State::Unknown;
        z.how = ax + " not known";
    } else if (!env.incremental) {
        z.state = ArgValue::State::Known;
        z.value = c.z.value;
    } else if (r.state == ArgValue::State::Known) {
        z.state = ArgValue::State::Known;
        z.value = r.value + c.z.value;
        z.how = "under G91 from the R point: " + num(r.value) + (c.z.value < 0 ? "" : "+") + num(c.z.value) +
                " = " + num(z.value);
    } else {
        z.state = ArgValue::State::Unknown;
        z.how = "under G91 " + ax + " is measured from the R point, which is not known";
    }
    return l;
}

// A point of the fixed-cycle sequence (R, Z) with the value `v`.
MotionPoint point_from(const std::string& step, const std::string& label, const std::string& expr,
                       const std::string& mark, const ArgValue& v, const std::string& source, const std::string& text) {
    MotionPoint p;
    p.step = step;
    p.label = label;
    p.mark = mark;
    p.expr = expr;
    p.source = source;
    p.text = text;
    if (v.state == ArgValue::State::Known) {
        p.value = Val<double>::of(v.value);
        p.worked = num(v.value) + (v.how.empty() ? "" : " (" + v.how + ")");
    } else {
        p.worked = "? (" + v.how + ")";
    }
    return p;
}

// An argument of a G-code macro cycle at one of its holes: R and Z as the
// cycle holds them, a word of the block, a word given earlier in the cycle,
// or the default when it was never given since the cycle started.
ArgValue cycle_macro_arg(const Block& b, const ModalState& before, const ActiveCycle& c, const MacroSpec& macro,
                         const HoleLevels& levels, const std::string& name) {
    const ArgSpec* as = macro.arg(name);
    std::string n = as ? as->name : name;
    if (n == "R") return levels.r;
    if (n == "Z") return levels.z;
    for (const auto& w : b.words) {
        const ArgSpec* wa = macro.arg_for_address(w.address);
        if (!wa || wa->name != n) continue;
        ArgValue out;
        if (auto v = word_value(b, w, before)) {
            out.state = ArgValue::State::Known;
            out.value = *v;
        } else {
            out.state = ArgValue::State::Unknown;
            out.how = "value of \"" + w.value_text + "\" not known";
        }
        return out;
    }
    // The cycle's modal words (by address) hold what earlier blocks gave.
    for (const auto& [addr, val] : c.words) {
        const ArgSpec* wa = macro.arg_for_address(addr);
        if (!wa || wa->name != n) continue;
        ArgValue out;
        if (val.known) {
            out.state = ArgValue::State::Known;
            out.value = val.value;
            out.how = c.start_line ? "from line " + std::to_string(c.start_line) : "";
        } else {
            out.state = ArgValue::State::Unknown;
            out.how = "value given earlier in the cycle not known";
        }
        return out;
    }
    if (as && c.known_absent(addr_of(macro, n))) {
        ArgValue out;
        if (as->default_value) {
            out.state = ArgValue::State::Known;
            out.value = *as->default_value;
            out.how = "not given: default " + num(*as->default_value);
        }
        return out;  // not given since the cycle started
    }
    ArgValue out;
    out.state = ArgValue::State::Unknown;
    out.how = "whether it was given earlier in the cycle differs between the paths to this block";
    return out;
}

// The macro's own sequence (OG84L: R, Z+L, R), with R and Z as the cycle holds them.
void add_macro_sequence(const Block& b, const ModalState& before, const ActiveCycle& c, const MacroSpec& macro,
                        const HoleLevels& levels, Envelope& env) {
    const Lookup lookup = [&](const std::string& name) {
        return cycle_macro_arg(b, before, c, macro, levels, name);
    };
    const ArgValue& r = levels.r;
    for (const auto& step : macro.action) {
        if (step.target.empty()) continue;
        if (!step.when.empty()) continue;  // M52/M53 returns follow the fixed-cycle rules below
        Evaluated e = evaluate_expr(step.target, &macro, lookup, false);
        if (e.skip) {
            env.notes.push_back("step " + step.step + " (" + step.target + ") skipped: " + e.why);
            continue;
        }
        MotionPoint p;
        p.step = step.step;
        p.label = "step " + step.step;
        p.text = step.text;
        p.source = step.source;
        p.inferred = step.inferred;
        p.expr = step.target;
        p.mark = mark_for(step.target);
        p.value = e.value;
        p.worked = e.worked;
        if (step.target == "R" && !r.how.empty() && r.state == ArgValue::State::Known) p.worked += " (" + r.how + ")";
        env.points.push_back(std::move(p));
    }
}

// --- The return after the hole ----------------------------------------------------

// A return point; a possible one (the return level is not known) only widens
// the picture.
void add_return(Envelope& env, MotionPoint p, bool possible) {
    p.possible = possible;
    if (possible && p.value.known) {
        p.reach = Interval{p.value.value, p.value.value};
        p.value = Val<double>{};
        p.worked += " (only if this return level is in effect, not known here)";
    }
    env.points.push_back(std::move(p));
}

// M53: the return to the G71 level.
MotionPoint g71_point(Plane plane, const ModalState& before, const ModalState& after) {
    MotionPoint p;
    p.step = "return";
    p.label = "return (M53)";
    p.mark = "G71";
    p.expr = "G71 level";
    p.source = "004 (M53: return to the G71 level)";
    p.text = "M53: return to the level set by G71";
    if (plane != Plane::G17) {
        p.worked = "? (the G71 level is followed in G17 only)";
    } else if (!before.distance.is(Distance::Absolute)) {
        p.worked = "? (the G71 level is followed under G90 only)";
    } else if (after.g71_level.known) {
        p.value = after.g71_level;
        p.worked = num(after.g71_level.value);
    } else {
        p.worked = "? (no G71 level known here)";
    }
    return p;
}

// M52: the return to the + travel limit.
MotionPoint limit_point(const Config& config, char axis) {
    MotionPoint p;
    p.step = "return";
    p.label = "return (M52)";
    p.mark = "+lim";
    p.expr = std::string(1, axis) + "+ limit";
    p.limit = true;
    p.source = "M52: return to the upper limit";
    p.text = "M52: return to the + travel limit";
    if (auto mx = travel_max(config, axis)) {
        p.value = Val<double>::of(*mx);
        p.worked = num(*mx) + " ([machine.travel] max)";
    } else {
        p.worked = "the + travel limit ([machine.travel] not configured)";
    }
    return p;
}

// The return after the hole: M52/M53/M54 when known, else G98/G99; and where
// it leaves the tool (`Envelope::end`).
void add_hole_return(const ModalState& before, const ModalState& after, const Config& config, Val<double> r_val,
                     Envelope& env) {
    const Plane plane = *env.plane;
    Val<int> rl = after.return_level;
    if (rl.is(53)) {
        add_return(env, g71_point(plane, before, after), false);
        env.end = env.points.back().value;
    } else if (rl.is(52) && plane == Plane::G17) {
        add_return(env, limit_point(config, env.axis), false);
        env.end = env.points.back().value;
    } else {
        if (!rl.known) {
            if (plane == Plane::G17 && after.g71_level.known) add_return(env, g71_point(plane, before, after), true);
        } else if (rl.is(52)) {
            env.notes.push_back("M52 in " + std::string(plane_name(plane)) + ": the upper-limit return is followed in G17 only");
        }
        if (after.cycle_return.is(CycleReturn::R) || rl.is(54)) env.end = r_val;
        else if (after.cycle_return.is(CycleReturn::Initial)) env.end = env.start;
    }
}

// Positioning plane: the hole position (a hole pattern: several, not listed).
void add_hole_position(const Block& b, const ModalState& after, Envelope& env) {
    const PlaneAxes pa = plane_axes(*env.plane);
    for (char a : {pa.first, pa.second}) {
        if (!block_has_axis(b, a) || b.statement(StmtKind::CoordCalc)) continue;
        Val<double> v = after.axis(a);
        if (v.known) env.plane_points.push_back({a, v.value, std::string(1, a)});
    }
    if (b.statement(StmtKind::CoordCalc))
        env.notes.push_back("the hole positions come from " + b.statement(StmtKind::CoordCalc)->name +
                            " (several holes, same cycle-axis motion)");
}

}  // namespace

std::optional<Envelope> hole_envelope(const Block& b, const ModalState& before, const ModalState& after,
                                      const Config& config) {
    const ActiveCycle& c = *after.cycle.value;
    const MacroSpec* macro = c.macro.empty() ? nullptr : config.catalog.find(c.macro);
    Envelope env;
    env.source = macro ? MotionSource::CycleMacro : MotionSource::FixedCycle;
    env.code = fmt::format("G{}", c.code);
    env.name = macro ? macro->name : env.code;
    env.line = b.line;
    env.origin_line = c.start_line;
    env.incremental = before.distance.is(Distance::Incremental);
    if (!before.plane.known) {
        env.notes.push_back("the plane (G17/G18/G19) is not known here, so neither is the cycle axis");
        finish(env);
        return env;
    }
    env.plane = before.plane.value;
    env.axis = plane_axes(before.plane.value).cycle;
    env.start = before.axis(env.axis);

    const HoleLevels levels = absolute_levels(c, before, env);
    env.points.push_back(initial_point(env));
    if (macro && !macro->action.empty()) {
        add_macro_sequence(b, before, c, *macro, levels, env);
    } else {
        const std::string ax(1, env.axis);
        env.points.push_back(point_from("R", "R point", "R", "R", levels.r, "004:L7-8",
                                        "R point: rapid changes to cutting feed"));
        env.points.push_back(point_from("Z", "Z point", ax, "Z", levels.z, "004:L9", "Z point: the final depth"));
        if (!macro && !config.catalog.find_cycle(c.code))
            env.notes.push_back(env.code + " is not described in the manuals: I -> R -> Z assumed");
    }
    const Val<double> r_val =
        levels.r.state == ArgValue::State::Known ? Val<double>::of(levels.r.value) : Val<double>{};
    add_hole_return(before, after, config, r_val, env);
    add_hole_position(b, after, env);
    finish(env);
    return env;
}

}  // namespace osplint::motion_detail
