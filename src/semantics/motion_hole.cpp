// The envelope of a hole of a fixed cycle (G81 ...) or of a G-code macro
// cycle (OG84L via G114): the I point, R and Z in absolute terms (fixed cycles manual),
// what G77 (K), G83 (J) and G88 (the shifts) add between them, the macro's own
// sequence when it has one, the return after the hole (M52 / M53 / M54, else
// G98 / G99), and the hole position in the positioning plane.
#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "semantics/motion_internal.h"
#include "semantics/transfer.h"
#include "support/function_ref.h"

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

// A word of a cycle at one of its holes, by its address: on the block, or
// given earlier in the cycle (the cycle's modal words hold what earlier blocks
// gave). Absent: not given since the cycle started; Unknown when the paths to
// the block disagree on that.
ArgValue cycle_word(const Block& b, const ModalState& before, const ActiveCycle& c,
                    FunctionRef<bool(const std::string&)> is_it, bool describe = true) {
    for (const auto& w : b.words) {
        if (!is_it(w.address)) continue;
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
    for (const auto& [addr, val] : c.words.get()) {
        if (!is_it(addr)) continue;
        ArgValue out;
        if (val.known) {
            out.state = ArgValue::State::Known;
            out.value = val.value;
            if (describe && c.start_line) out.how = "from line " + std::to_string(c.start_line);
        } else {
            out.state = ArgValue::State::Unknown;
            out.how = "value given earlier in the cycle not known";
        }
        return out;
    }
    ArgValue out;
    if (!c.words_known) {
        out.state = ArgValue::State::Unknown;
        out.how = "whether it was given earlier in the cycle differs between the paths to this block";
    }
    return out;
}

ArgValue cycle_word(const Block& b, const ModalState& before, const ActiveCycle& c, const std::string& address) {
    return cycle_word(b, before, c, [&](const std::string& a) { return a == address; });
}

// An argument of a G-code macro cycle at one of its holes: R and Z as the
// cycle holds them, a word of the block, a word given earlier in the cycle,
// or the default when it was never given since the cycle started.
// `describe`: with the `how` of a value (false: values only).
ArgValue cycle_macro_arg(const Block& b, const ModalState& before, const ActiveCycle& c, const MacroSpec& macro,
                         const HoleLevels& levels, const std::string& name, bool describe) {
    const ArgSpec* as = macro.arg(name);
    const std::string& n = as ? as->name : name;
    if (n == "R") return levels.r;
    if (n == "Z") return levels.z;
    ArgValue out = cycle_word(
        b, before, c,
        [&](const std::string& addr) {
            const ArgSpec* wa = macro.arg_for_address(addr);
            return wa && wa->name == n;
        },
        describe);
    if (out.state != ArgValue::State::Absent) return out;
    if (as) {
        if (as->default_value) {
            out.state = ArgValue::State::Known;
            out.value = *as->default_value;
            if (describe) out.how = "not given: default " + num(*as->default_value);
        }
        return out;  // not given since the cycle started
    }
    out.state = ArgValue::State::Unknown;
    out.how = "whether it was given earlier in the cycle differs between the paths to this block";
    return out;
}

// The macro's own sequence (OG84L: R, Z+L, R), with R and Z as the cycle
// holds them. `describe`: with the text of each point and the notes (false:
// values only, EnvelopeDetail::Values).
void add_macro_sequence(const Block& b, const ModalState& before, const ActiveCycle& c, const MacroSpec& macro,
                        const HoleLevels& levels, Envelope& env, bool describe) {
    const auto arg = [&](const std::string& name) {
        return cycle_macro_arg(b, before, c, macro, levels, name, describe);
    };
    const Lookup lookup = arg;
    const ArgValue& r = levels.r;
    for (const auto& step : macro.action) {
        if (step.target.empty()) continue;
        if (!step.when.empty()) continue;  // M52/M53 returns follow the fixed-cycle rules below
        Evaluated e = evaluate_expr(step.target, &macro, lookup, false, describe);
        if (e.skip) {
            if (describe) env.notes.push_back("step " + step.step + " (" + step.target + ") skipped: " + e.why);
            continue;
        }
        MotionPoint p = describe ? step_point(step) : MotionPoint{};
        p.inferred = step.inferred;
        p.value = e.value;
        if (describe) {
            p.expr = step.target;
            p.mark = mark_for(step.target);
            p.worked = e.worked;
            if (step.target == "R" && !r.how.empty() && r.state == ArgValue::State::Known)
                p.worked += " (" + r.how + ")";
        }
        env.points.push_back(std::move(p));
    }
}

// --- What G77, G83 and G88 add to I -> R -> Z -----------------------------------

// A point that may or may not be reached: it only widens the picture.
void make_possible(MotionPoint& p, const std::string& why) {
    p.possible = true;
    if (p.value.known) p.reach = Interval{p.value.value, p.value.value};
    p.value = Val<double>{};
    p.worked += " (" + why + ")";
}

bool given_in_cycle(const Block& b, const ActiveCycle& c, const std::string& address) {
    return b.find(address) != nullptr || c.given(address);
}

// G77: K is where the step motion (G87) changes to the pick motion (G83);
// under G91 it is measured from the R point, like Z. It lies between R and Z;
// a K elsewhere is only a possible point, with a note (OSP205 reports it).
void add_g77_k(const Block& b, const ModalState& before, const ActiveCycle& c, const HoleLevels& l, Envelope& env) {
    const ArgValue k = cycle_word(b, before, c, "K");
    if (k.state == ArgValue::State::Absent) {
        env.notes.push_back("K not given: the point where the step motion changes to the pick motion is not known");
        return;
    }
    ArgValue at;
    if (k.state == ArgValue::State::Unknown) {
        at = k;
    } else if (!before.distance.known) {
        at.state = ArgValue::State::Unknown;
        at.how = "G90/G91 not known";
    } else if (!env.incremental) {
        at = k;
    } else if (l.r.state == ArgValue::State::Known) {
        at.state = ArgValue::State::Known;
        at.value = l.r.value + k.value;
        at.how = "under G91 from the R point: " + num(l.r.value) + (k.value < 0 ? "" : "+") + num(k.value) + " = " +
                 num(at.value);
    } else {
        at.state = ArgValue::State::Unknown;
        at.how = "under G91 K is measured from the R point, which is not known";
    }
    MotionPoint p = point_from("K", "K point", "K", "K", at, "004:L56-57",
                               "K point: the step motion (G87) changes to the pick motion (G83)");
    // Between R and Z it changes nothing of the envelope's extremes; elsewhere
    // the manual says nothing of where the tool goes.
    if (!p.value.known) {
        make_possible(p, "between R and Z");
    } else if (l.r.state != ArgValue::State::Known || l.z.state != ArgValue::State::Known) {
        make_possible(p, "R or Z not known: whether K lies between them is not known");
    } else if (p.value.value > std::max(l.r.value, l.z.value) || p.value.value < std::min(l.r.value, l.z.value)) {
        env.notes.push_back("K point " + num(p.value.value) + " does not lie between R (" + num(l.r.value) +
                            ") and Z (" + num(l.z.value) + "): the manual has K on the way from R to Z");
        make_possible(p, "not between R and Z");
    }
    env.points.push_back(std::move(p));
}

// G83 with J: pecks of Q down to the withdrawal amount J below R, a rapid
// return to R, a rapid approach to d2 short of the bottom (d2 a setting
// parameter, initially 1 mm), and so on J deeper each time down to Z. The
// first withdrawal depth R-J and the return to R are followed; the approach
// rests on the setting parameter.
void add_g83_j(const Block& b, const ModalState& before, const ActiveCycle& c, const HoleLevels& l, Envelope& env) {
    const ArgValue j = cycle_word(b, before, c, "J");
    if (j.state == ArgValue::State::Absent) return;  // a return to R after every Q
    const std::string ax(1, env.axis);
    if (j.state == ArgValue::State::Unknown) {
        env.notes.push_back("J (" + j.how + "): the withdrawal depth with J is not known");
        return;
    }
    if (l.r.state != ArgValue::State::Known || l.z.state != ArgValue::State::Known) {
        env.notes.push_back("J " + num(j.value) + ": the withdrawal depth R-J is not known (R or " + ax + " not known)");
        return;
    }
    const double r = l.r.value, z = l.z.value;
    const double down = r >= z ? -1.0 : 1.0;  // the direction of the cut, from R toward Z
    if (j.value <= 0) {
        env.notes.push_back("J " + num(j.value) + " is not a positive withdrawal amount: the motion with J is not followed");
        return;
    }
    if (j.value >= std::fabs(r - z)) {
        env.notes.push_back("J " + num(j.value) + " is not less than the depth from R to " + ax + " (" +
                            num(std::fabs(r - z)) + "): the hole is cut to " + ax + " before the first return to R");
        return;
    }
    const double at = r + down * j.value;
    const std::string sign = down < 0 ? "-" : "+";
    MotionPoint jp;
    jp.step = "J";
    jp.label = "J depth";
    jp.expr = "R" + sign + "J";
    jp.value = Val<double>::of(at);
    jp.worked = num(r) + sign + num(j.value) + " = " + num(at);
    jp.source = "004:L144-146";
    jp.text = "with J: pecks of Q, each with a rapid return of d1, down to the withdrawal amount J";
    env.points.push_back(std::move(jp));
    MotionPoint back;
    back.step = "J return";
    back.label = "return to R (J)";
    back.expr = "R";
    back.value = Val<double>::of(r);
    back.worked = num(r);
    back.source = "004:L146";
    back.text = "after the J depth: rapid return to the R point";
    env.points.push_back(std::move(back));
    MotionPoint d2;
    d2.step = "d2";
    d2.label = "approach (J)";
    d2.expr = "R" + sign + "J" + (down < 0 ? "+" : "-") + "d2";
    d2.value = Val<double>::of(at - down * 1.0);
    d2.worked = num(r) + sign + num(j.value) + (down < 0 ? "+" : "-") + "1 = " + num(at - down * 1.0);
    d2.source = "004:L147-150";
    d2.text = "rapid approach to d2 short of the bottom";
    make_possible(d2, "d2 is a setting parameter, initially 1 mm");
    env.points.push_back(std::move(d2));
    env.notes.push_back("with J the cutting goes on J deeper each time down to " + ax +
                        ", with a rapid return to R and a rapid approach to d2 short of the bottom (d1 and d2 are "
                        "setting parameters, initially 1 mm)");
}

// G88: after Z the cycle axis is relieved by the Z shift (Q in the format and
// the function text, K in the address list: Q first), away from the hole
// bottom, and X/Y by the shifts I/J (G17) before the rapid return to R.
void add_g88_shifts(const Block& b, const ModalState& before, const ModalState& after, const ActiveCycle& c,
                    const HoleLevels& l, Envelope& env) {
    const std::string ax(1, env.axis);
    std::string addr;
    if (given_in_cycle(b, c, "Q")) {
        addr = "Q";
        if (given_in_cycle(b, c, "K")) env.notes.push_back("Q and K both given: Q is taken as the Z shift");
    } else if (given_in_cycle(b, c, "K")) {
        addr = "K";
    }
    if (addr.empty()) {
        env.notes.push_back(c.words_known ? "no Z shift (Q or K) given: the relief after " + ax + " is not known"
                                          : "whether a Z shift (Q or K) was given differs between the paths to this block");
    } else {
        const ArgValue q = cycle_word(b, before, c, addr);
        MotionPoint p;
        p.step = "shift";
        p.label = "Z shift (" + addr + ")";
        p.expr = ax + "+" + addr;
        p.source = "004:L261-262";
        p.text = "after Z the spindle stops oriented and the cycle axis is relieved by the shift, away from the bottom";
        if (q.state != ArgValue::State::Known) {
            p.worked = "? (" + q.how + ")";
        } else if (l.z.state != ArgValue::State::Known) {
            p.worked = "? (" + l.z.how + ")";
        } else {
            const double v = l.z.value + std::fabs(q.value);
            p.value = Val<double>::of(v);
            p.worked = num(l.z.value) + "+" + num(std::fabs(q.value)) + " = " + num(v) +
                       (q.value < 0 ? " (the shift taken as an amount)" : "");
        }
        env.points.push_back(std::move(p));
    }
    if (*env.plane != Plane::G17) {
        if (given_in_cycle(b, c, "I") || given_in_cycle(b, c, "J"))
            env.notes.push_back("the I/J shifts are followed in G17 only");
        return;
    }
    if (b.statement(StmtKind::CoordCalc)) return;  // several holes: no one position to shift from
    for (auto [a, axis] : {std::pair<const char*, char>{"I", 'X'}, {"J", 'Y'}}) {
        const ArgValue s = cycle_word(b, before, c, a);
        const Val<double> from = after.axis(axis);
        if (s.state == ArgValue::State::Absent) {
            env.notes.push_back(std::string(a) + " not given: the " + axis +
                                " shift is the setting parameter's, not known here");
        } else if (s.state == ArgValue::State::Unknown) {
            env.notes.push_back(std::string(a) + " shift not known (" + s.how + ")");
        } else if (from.known) {
            const double to = from.value + s.value;
            env.plane_spans.push_back({axis, Interval{std::min(from.value, to), std::max(from.value, to)},
                                       std::string("G88 shift ") + a + " after Z, from " + num(from.value) +
                                           " (the sign of " + a + " taken as the direction)",
                                       true, false, a});
        }
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
                                      const Config& config, bool describe, bool points) {
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
    if (!points && (macro || c.code != 88)) {
        add_hole_position(b, after, env);
        finish(env);
        return env;
    }

    const HoleLevels levels = absolute_levels(c, before, env);
    env.points.push_back(initial_point(env));
    if (macro && !macro->action.empty()) {
        add_macro_sequence(b, before, c, *macro, levels, env, describe);
    } else {
        const std::string ax(1, env.axis);
        env.points.push_back(point_from("R", "R point", "R", "R", levels.r, "004:L7-8",
                                        "R point: rapid changes to cutting feed"));
        if (!macro && c.code == 77) add_g77_k(b, before, c, levels, env);
        if (!macro && c.code == 83) add_g83_j(b, before, c, levels, env);
        env.points.push_back(point_from("Z", "Z point", ax, "Z", levels.z, "004:L9", "Z point: the final depth"));
        if (!macro && c.code == 88) add_g88_shifts(b, before, after, c, levels, env);
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

namespace osplint {

using motion_detail::same_val;

namespace {

// A block that gives nothing but the two axes of the positioning plane
// `plane` (no statement, no other word): a hole there reads nothing of its
// own on the cycle axis.
bool plane_words_only(const Block& b, Plane plane) {
    if (b.kind != LineKind::Block || b.words.empty() || b.block_delete || b.program_name || !b.statements.empty() ||
        !b.assignments.empty() || !b.errors.empty())
        return false;
    const PlaneAxes pa = plane_axes(plane);
    for (const auto& w : b.words)
        if (w.address.size() != 1 || (w.address[0] != pa.first && w.address[0] != pa.second)) return false;
    return true;
}

std::optional<TravelLimit> travel_of(const TravelLimits& travel, char axis) {
    const auto it = travel.find(axis);
    if (it == travel.end()) return std::nullopt;
    return it->second;
}
}  // namespace

HoleAxisMemo::Key HoleAxisMemo::key_of(const BlockView& v, const Config& config) {
    Key k;
    const ModalState& before = v.before;
    const ModalState& after = v.after;
    if (v.call || !before.plane.known || !after.cycle.known || !after.cycle.value) return k;
    if (!plane_words_only(v.block, before.plane.value)) return k;
    const ActiveCycle& c = *after.cycle.value;
    if (!is_cycle_hole(v.block, before, after, v.call)) return k;
    const PlaneAxes pa = plane_axes(before.plane.value);
    if (!c.macro.empty()) {
        // The steps of a G-code macro cycle read its arguments: not one a
        // plane axis's word gives (the word changes from hole to hole).
        if (const MacroSpec* spec = config.catalog.find(c.macro); spec && !spec->action.empty())
            if (motion_detail::steps_read_plane(*spec, before.plane.value)) return k;
    } else if (c.code == 88) {
        return k;  // the shifts after Z move in the plane, from the hole
    }
    k.cycle = c;
    k.plane = before.plane;
    k.distance = before.distance;
    k.position = before.axis(pa.cycle);
    k.return_level = after.return_level;
    k.g71_level = after.g71_level;
    k.cycle_return = after.cycle_return;
    k.travel = travel_of(config.travel, pa.cycle);
    return k;
}

bool HoleAxisMemo::same(const BlockView& v, const Config& config) const {
    // key_of's reading, compared as it goes; the macro's reads were looked at
    // when the key was made (the same cycle in the same plane).
    if (!key_.cycle || v.call || !v.before.plane.known || !same_val(v.before.plane, key_.plane)) return false;
    const ModalState& before = v.before;
    const ModalState& after = v.after;
    if (!after.cycle.known || !after.cycle.value || !plane_words_only(v.block, before.plane.value)) return false;
    if (!same_val(before.distance, key_.distance) || !same_val(after.return_level, key_.return_level) ||
        !same_val(after.g71_level, key_.g71_level) || !same_val(after.cycle_return, key_.cycle_return))
        return false;
    const char axis = plane_axes(before.plane.value).cycle;
    if (!same_val(before.axis(axis), key_.position) || travel_of(config.travel, axis) != key_.travel) return false;
    if (!(*after.cycle.value == *key_.cycle)) return false;
    return is_cycle_hole(v.block, before, after, v.call);
}

void HoleAxisMemo::remember(const BlockView& v, const Config& config) { key_ = key_of(v, config); }

}  // namespace osplint
