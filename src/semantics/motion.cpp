// The cycle-axis motion evaluator and the side view of `osplint trace --svg` (see motion.h).
#include "semantics/motion.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <set>

#include <fmt/format.h>

#include "catalog/catalog.h"
#include "semantics/eval.h"
#include "semantics/transfer.h"

namespace osplint {

std::string motion_number(double v) {
    double r = std::round(v * 10000.0) / 10000.0;
    if (r == 0) r = 0;  // no "-0"
    std::string s = fmt::format("{:.4f}", r);
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
}

namespace {

std::string num(double v) { return motion_number(v); }
std::string paren(double v) { return v < 0 ? "(" + num(v) + ")" : num(v); }

std::string upper(std::string_view s) {
    std::string out(s);
    for (auto& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

bool contains_ci(std::string_view hay, std::string_view needle) {
    return upper(hay).find(upper(needle)) != std::string::npos;
}

bool has_code(const Block& b, char address, int code) {
    for (const auto& w : b.words)
        if (w.address.size() == 1 && w.address[0] == address)
            if (auto c = code_of(w); c && *c == code) return true;
    return false;
}

// G codes whose axis words are not a move of the tool tip (the same list the
// transfer function uses, plus the coordinate-system selections).
bool non_motion_block(const Block& b) {
    for (int c : {4, 10, 11, 15, 16, 20, 22, 23, 30, 50, 71, 92})
        if (has_code(b, 'G', c)) return true;
    return false;
}

bool is_cycle_macro(const MacroSpec& spec) { return spec.has_form(MacroForm::GCode) && !spec.cancel.empty(); }

bool is_any_axis(std::string_view a) {
    return a.size() == 1 && std::string_view("XYZABCUVW").find(a[0]) != std::string_view::npos;
}

bool is_axis_letter(std::string_view a) {
    return a.size() == 1 && (a[0] == 'X' || a[0] == 'Y' || a[0] == 'Z');
}

std::optional<double> travel_max(const Config& c, char axis) {
    if (auto it = c.travel.find(axis); it != c.travel.end()) return it->second.max;
    return std::nullopt;
}

// --- Tri-state conditions of the catalog's `when` -----------------------------

enum class Tri { False, True, Unknown };
Tri tri_not(Tri a) { return a == Tri::Unknown ? a : (a == Tri::True ? Tri::False : Tri::True); }
Tri tri_and(Tri a, Tri b) {
    if (a == Tri::False || b == Tri::False) return Tri::False;
    if (a == Tri::True && b == Tri::True) return Tri::True;
    return Tri::Unknown;
}
Tri tri_or(Tri a, Tri b) {
    if (a == Tri::True || b == Tri::True) return Tri::True;
    if (a == Tri::False && b == Tri::False) return Tri::False;
    return Tri::Unknown;
}
Tri tri_of(const Val<bool>& v) { return v.known ? (v.value ? Tri::True : Tri::False) : Tri::Unknown; }

// `G17 and (PM=52 or M52)`, `given:PK`, `M53`: atoms joined by and/or, with
// parentheses. Anything it cannot read is Unknown.
class Condition {
public:
    Condition(std::string_view text, std::function<Tri(std::string_view)> atom) : s_(text), atom_(std::move(atom)) {}
    Tri eval() {
        Tri r = parse_or();
        skip();
        return i_ == s_.size() ? r : Tri::Unknown;
    }

private:
    void skip() {
        while (i_ < s_.size() && s_[i_] == ' ') ++i_;
    }
    std::string_view token() {
        skip();
        if (i_ >= s_.size()) return {};
        if (s_[i_] == '(' || s_[i_] == ')') return s_.substr(i_, 1);
        size_t j = i_;
        while (j < s_.size() && s_[j] != ' ' && s_[j] != '(' && s_[j] != ')') ++j;
        return s_.substr(i_, j - i_);
    }
    Tri parse_or() {
        Tri r = parse_and();
        while (upper(token()) == "OR") {
            i_ += 2;
            r = tri_or(r, parse_and());
        }
        return r;
    }
    Tri parse_and() {
        Tri r = parse_primary();
        while (upper(token()) == "AND") {
            i_ += 3;
            r = tri_and(r, parse_primary());
        }
        return r;
    }
    Tri parse_primary() {
        std::string_view t = token();
        if (t.empty()) return Tri::Unknown;
        if (t == "(") {
            ++i_;
            Tri r = parse_or();
            if (token() == ")") ++i_;
            return r;
        }
        if (upper(t) == "NOT") {
            i_ += 3;
            return tri_not(parse_primary());
        }
        i_ += t.size();
        return atom_(t);
    }
    std::string_view s_;
    size_t i_ = 0;
    std::function<Tri(std::string_view)> atom_;
};

// --- Argument values ----------------------------------------------------------

struct ArgValue {
    enum class State { Known, Unknown, Absent } state = State::Absent;
    double value = 0;
    std::string how;  // why it has this value when not written: "default 5", "current position"
};

// What the evaluation of one catalog expression gives.
struct Evaluated {
    Val<double> value;
    std::string worked;  // "-20-12-5 = -37 (PL not given: default 5)"
    bool skip = false;   // the step does not run (an argument it needs is not given)
    std::string why;     // why skipped / unknown
};

using Lookup = std::function<ArgValue(const std::string&)>;

bool zero_when_absent(const ArgSpec& a) {
    return a.omitted == ArgOmitted::None &&
           (a.role == ArgRole::Length || a.role == ArgRole::Stroke || a.role == ArgRole::Shift);
}

Evaluated evaluate_expr(const std::string& text, const MacroSpec* spec, const Lookup& lookup, bool conditional) {
    Evaluated out;
    auto terms = parse_catalog_expr(text);
    if (!terms) {
        out.why = "\"" + text + "\" is not an expression osplint can read";
        out.worked = "? (" + out.why + ")";
        return out;
    }
    double sum = 0;
    bool known = true;
    std::string shown, notes, unknown_why;
    for (size_t k = 0; k < terms->size(); ++k) {
        const ExprTerm& t = (*terms)[k];
        double v = t.number;
        std::string piece;
        if (!t.name.empty()) {
            ArgValue av = lookup(t.name);
            const ArgSpec* as = spec ? spec->arg(t.name) : nullptr;
            if (av.state == ArgValue::State::Absent) {
                if (as && as->undocumented) {
                    out.skip = true;
                    out.why = t.name + " is not given (the manual uses it here but never defines it)";
                    return out;
                }
                if (conditional) {
                    out.skip = true;
                    out.why = t.name + " is not given";
                    return out;
                }
                if (as && zero_when_absent(*as)) {
                    av.state = ArgValue::State::Known;
                    av.value = 0;
                    av.how = "not given: 0";
                } else {
                    known = false;
                    if (unknown_why.empty()) unknown_why = t.name + " is not given";
                    piece = t.name;
                }
            } else if (av.state == ArgValue::State::Unknown) {
                known = false;
                if (unknown_why.empty())
                    unknown_why = t.name + (av.how.empty() ? std::string(": value not known") : ": " + av.how);
                piece = t.name;
            }
            if (av.state == ArgValue::State::Known) {
                v = av.value;
                if (!av.how.empty()) notes += (notes.empty() ? "" : "; ") + t.name + " " + av.how;
            }
        }
        if (piece.empty()) piece = k == 0 ? (t.sign < 0 ? "-" + paren(v) : num(v)) : (t.sign < 0 ? "-" : "+") + paren(v);
        else piece = (k == 0 ? (t.sign < 0 ? "-" : "") : (t.sign < 0 ? "-" : "+")) + piece;
        shown += piece;
        sum += t.sign * v;
    }
    if (known) {
        out.value = Val<double>::of(sum);
        out.worked = terms->size() == 1 ? num(sum) : shown + " = " + num(sum);
        if (!notes.empty()) out.worked += " (" + notes + ")";
    } else {
        out.why = unknown_why;
        std::string bare;
        for (char ch : text)
            if (ch != ' ') bare += ch;
        out.worked = (terms->size() == 1 || shown == bare ? std::string("?") : shown + " = ?") + " (" + unknown_why + ")";
    }
    return out;
}

// The address an argument of a G-code macro is written with (OG84L: "L" for L).
std::string addr_of(const MacroSpec& spec, const std::string& name) {
    if (spec.gcode_form)
        for (const auto& [addr, target] : spec.gcode_form->address_map)
            if (target == name) return addr;
    return name;
}

const MacroArg* given_arg(const MacroCall& c, const ArgSpec* a, const std::string& name) {
    if (a) {
        if (const MacroArg* m = c.arg(a->name)) return m;
        for (const auto& alias : a->aliases)
            if (const MacroArg* m = c.arg(alias)) return m;
    }
    return c.arg(name);
}

std::string mark_for(const std::string& expr) {
    if (expr == "PR" || expr == "R") return "R";
    if (expr == "PZ" || expr == "Z") return "Z";
    if (expr == "PA") return "A";
    if (expr == "PT") return "T";
    if (expr == "Z+L") return "Z+L";  // OG84L: the spindle stops at Z+L, the tap reaches Z
    return "";
}

// --- Finishing an envelope ----------------------------------------------------

void finish(Envelope& env) {
    env.lowest.reset();
    env.highest.reset();
    env.may_low.reset();
    env.may_high.reset();
    env.bounded_low = env.bounded_high = env.plane.has_value();
    for (size_t i = 0; i < env.points.size(); ++i) {
        const MotionPoint& p = env.points[i];
        if (!p.possible) {
            if (p.value.known) {
                double v = p.value.value;
                if (!env.lowest || v < env.lowest->value) env.lowest = EnvelopeEnd{v, i};
                if (!env.highest || v > env.highest->value) env.highest = EnvelopeEnd{v, i};
            } else if (!p.limit) {
                env.bounded_low = env.bounded_high = false;
            }
            if (p.limit) env.limit_point = i;
        } else if (p.reach) {
            if (!env.may_low || p.reach->lo < env.may_low->value) env.may_low = EnvelopeEnd{p.reach->lo, i};
            if (!env.may_high || p.reach->hi > env.may_high->value) env.may_high = EnvelopeEnd{p.reach->hi, i};
        }
    }
    if (!env.lowest && !env.limit_point) env.bounded_low = env.bounded_high = false;
    if (env.may_low && env.lowest && env.may_low->value >= env.lowest->value) env.may_low.reset();
    if (env.may_high && env.highest && env.may_high->value <= env.highest->value) env.may_high.reset();
    if (env.limit_point && env.may_high) {
        const MotionPoint& lp = env.points[*env.limit_point];
        if (lp.value.known && env.may_high->value <= lp.value.value) env.may_high.reset();
    }
}

// The plane point a word of the block moves to (G90/G91).
std::optional<double> block_axis_target(const Block& b, char axis, const ModalState& before) {
    for (const auto& w : b.words) {
        if (w.address.size() != 1 || w.address[0] != axis) continue;
        auto v = word_value(b, w, before);
        if (!v || !before.distance.known) return std::nullopt;
        if (before.distance.value == Distance::Absolute) return v;
        Val<double> old = before.axis(axis);
        if (!old.known) return std::nullopt;
        return old.value + *v;
    }
    return std::nullopt;
}

bool block_has_axis(const Block& b, char axis) {
    for (const auto& w : b.words)
        if (w.address.size() == 1 && w.address[0] == axis) return true;
    return false;
}

// --- Macros -------------------------------------------------------------------

void add_plane_spans(Envelope& env, const MacroSpec& spec, const Lookup& lookup, Plane plane,
                     const std::map<char, double>& centre) {
    const PlaneAxes pa = plane_axes(plane);
    const int pn = plane == Plane::G17 ? 17 : plane == Plane::G18 ? 18 : 19;
    auto known = [&](const std::string& n) -> std::optional<double> {
        if (!spec.arg(n)) return std::nullopt;
        ArgValue v = lookup(n);
        if (v.state != ArgValue::State::Known) return std::nullopt;
        return v.value;
    };
    auto centre_of = [&](char a) -> std::optional<double> {
        if (auto it = centre.find(a); it != centre.end()) return it->second;
        return std::nullopt;
    };
    std::map<char, Interval> spans;
    auto widen = [&](char a, double v) {
        auto c = centre_of(a);
        if (!c) return;
        auto it = spans.find(a);
        if (it == spans.end()) it = spans.emplace(a, Interval{*c, *c}).first;
        it->second.lo = std::min(it->second.lo, v);
        it->second.hi = std::max(it->second.hi, v);
    };
    if (const ArgSpec* pc = spec.arg("PC"); pc && spec.family == "back-counterbore") {
        // OG87C: the cutting edge runs round the counterbore circle PC about the
        // centre; steps 3/13 shift the oriented tool by PI/PJ(/PK).
        auto d = known("PC");
        if (!d) return;
        double r = std::fabs(*d) / 2;
        for (char a : {pa.first, pa.second})
            if (auto c = centre_of(a)) {
                widen(a, *c - r);
                widen(a, *c + r);
            }
        for (const auto& arg : spec.args) {
            if (arg.role != ArgRole::Shift) continue;
            auto ax = arg.axis(pn);
            auto v = known(arg.name);
            if (!ax || !v || (*ax != pa.first && *ax != pa.second)) continue;
            if (auto c = centre_of(*ax)) widen(*ax, *c + *v);
        }
        for (auto& [a, iv] : spans)
            env.plane_spans.push_back({a, iv, "counterbore circle PC=" + num(*d) + " about the centre, tool shift", false});
        return;
    }
    if (spec.family != "keyway" && spec.family != "wall-finishing") return;
    const ArgSpec* pi = spec.arg("PI");
    if (!pi) return;
    auto along = pi->axis(pn);
    auto len = known("PI");
    if (!along || !len || (*along != pa.first && *along != pa.second)) return;
    char across = *along == pa.first ? pa.second : pa.first;
    auto s = centre_of(*along);
    if (!s) return;
    std::string why;
    if (plane == Plane::G17) {
        widen(*along, *s + *len);
        why = "start point to start+PI along " + std::string(1, *along);
    } else {
        // The direction of PI outside G17 is not reliably documented (A-39): both ways.
        widen(*along, *s - std::fabs(*len));
        widen(*along, *s + std::fabs(*len));
        why = "PI either way along " + std::string(1, *along) + " (direction outside G17 not documented)";
    }
    if (spec.family == "keyway") {
        if (auto w = known("PJ"); w && centre_of(across)) {
            widen(across, *centre_of(across) - std::fabs(*w) / 2);
            widen(across, *centre_of(across) + std::fabs(*w) / 2);
            why += ", width PJ across";
        }
    } else {
        for (const auto& arg : spec.args) {
            if (arg.role != ArgRole::Vector) continue;
            auto ax = arg.axis(pn);
            auto v = known(arg.name);
            if (!ax || !v) continue;
            if (*ax == *along) widen(*ax, *s + (plane == Plane::G17 ? *len : std::fabs(*len)) + *v);
            else if (*ax == across) widen(*ax, *centre_of(across) + *v);
        }
    }
    for (auto& [a, iv] : spans) env.plane_spans.push_back({a, iv, why + " (start point taken as one end)", true});
}

std::optional<Envelope> macro_envelope(const Block& b, const ModalState& before, const ModalState& after,
                                       const MacroCall& call, const MacroSpec& spec, const Config& config) {
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
        env.notes.push_back("the plane (G17/G18/G19) is not known here, so neither is the cycle axis");
        finish(env);
        return env;
    }
    const Plane plane = before.plane.value;
    env.plane = plane;
    const PlaneAxes pa = plane_axes(plane);
    env.axis = pa.cycle;
    env.start = before.axis(env.axis);
    const int pn = plane == Plane::G17 ? 17 : plane == Plane::G18 ? 18 : 19;

    Lookup lookup = [&](const std::string& name) -> ArgValue {
        const ArgSpec* as = spec.arg(name);
        ArgValue out;
        if (const MacroArg* m = given_arg(call, as, name)) {
            if (m->value.known) {
                out.state = ArgValue::State::Known;
                out.value = m->value.value;
            } else {
                out.state = ArgValue::State::Unknown;
                out.how = m->word ? "value of \"" + m->word->value_text + "\" not known" : "value not known";
            }
            return out;
        }
        if (!as) return out;
        if (as->default_value) {
            out.state = ArgValue::State::Known;
            out.value = *as->default_value;
            out.how = "not given: default " + num(*as->default_value);
            return out;
        }
        if (as->omitted == ArgOmitted::Current && as->role == ArgRole::Cycle) {
            Val<double> cur = before.axis(env.axis);
            if (cur.known) {
                out.state = ArgValue::State::Known;
                out.value = cur.value;
                out.how = "not given: current position " + num(cur.value);
            } else {
                out.state = ArgValue::State::Unknown;
                out.how = "not given, and the current " + std::string(1, env.axis) + " position is not known";
            }
        }
        return out;
    };

    auto m_active = [&](int code) -> Tri {
        if (code == 52 && spec.m52 == M52Mode::IgnoredUsePM52 && call.kind != CallKind::ModinPositioning)
            return Tri::False;  // M52 on a CALL line is not read by the subprogram
        if (!after.return_level.known) return Tri::Unknown;
        return after.return_level.value == code ? Tri::True : Tri::False;
    };
    auto atom = [&](std::string_view t) -> Tri {
        std::string a = upper(t);
        if (a == "G17" || a == "G18" || a == "G19") return (a == plane_name(plane)) ? Tri::True : Tri::False;
        if (a == "G90") return tri_of(before.distance.known ? Val<bool>::of(before.distance.value == Distance::Absolute) : Val<bool>{});
        if (a == "G91") return tri_of(before.distance.known ? Val<bool>::of(before.distance.value == Distance::Incremental) : Val<bool>{});
        if (a == "M52") return m_active(52);
        if (a == "M53") return m_active(53);
        if (a == "M54") return m_active(54);
        if (a.rfind("GIVEN:", 0) == 0) {
            std::string n = a.substr(6);
            return given_arg(call, spec.arg(n), n) ? Tri::True : Tri::False;
        }
        if (auto eq = a.find('='); eq != std::string::npos) {
            std::string n = a.substr(0, eq);
            double want = std::atof(a.c_str() + eq + 1);
            ArgValue v = lookup(n);
            if (v.state == ArgValue::State::Absent) return Tri::False;
            if (v.state == ArgValue::State::Unknown) return Tri::Unknown;
            return v.value == want ? Tri::True : Tri::False;
        }
        return Tri::Unknown;
    };

    std::optional<Interval> cur;  // where the tool is after the steps so far
    bool end_known = true;
    for (const auto& step : spec.action) {
        Tri cond = step.when.empty() ? Tri::True : Condition(step.when, atom).eval();
        if (cond == Tri::False) continue;
        MotionPoint p;
        p.step = step.step;
        p.label = "step " + step.step;
        p.text = step.text;
        p.source = step.source;
        p.inferred = step.inferred;
        p.possible = cond == Tri::Unknown;
        if (!step.target.empty()) {
            Evaluated e = evaluate_expr(step.target, &spec, lookup, !step.when.empty());
            if (e.skip) {
                env.notes.push_back("step " + step.step + " (" + step.target + ") skipped: " + e.why);
                continue;
            }
            p.expr = step.target;
            p.mark = mark_for(step.target);
            p.worked = e.worked;
            if (p.possible) {
                if (e.value.known) p.reach = Interval{e.value.value, e.value.value};
                p.worked += " (runs only if " + step.when + ", not known here)";
                end_known = false;
            } else {
                p.value = e.value;
                cur = e.value.known ? std::optional(Interval{e.value.value, e.value.value}) : std::nullopt;
                end_known = true;
                env.end = e.value;
            }
        } else if (!step.by.empty()) {
            Evaluated e = evaluate_expr(step.by, &spec, lookup, false);
            if (e.skip) {
                env.notes.push_back("step " + step.step + " (by " + step.by + ") skipped: " + e.why);
                continue;
            }
            p.expr = "by " + step.by;
            p.possible = true;
            if (cur && e.value.known) {
                double len = std::fabs(e.value.value);
                cur = Interval{cur->lo - len, cur->hi + len};
                p.reach = cur;
                p.worked = "a stroke of " + num(len) + " in a direction the manual does not print: " + num(cur->lo) +
                           " .. " + num(cur->hi);
            } else {
                cur.reset();
                p.worked = "stroke of unprinted direction; " +
                           (e.value.known ? std::string("start of the stroke not known") : e.why);
            }
            end_known = false;
            env.end = Val<double>{};
        } else if (contains_ci(step.text, "+ limit")) {
            p.limit = true;
            p.mark = "+lim";
            p.expr = std::string(1, env.axis) + "+ limit";
            if (auto mx = travel_max(config, env.axis)) {
                p.worked = num(*mx) + " ([machine.travel] " + std::string(1, static_cast<char>(std::tolower(env.axis))) +
                           " max)";
                if (p.possible) p.reach = Interval{*mx, *mx};
                else p.value = Val<double>::of(*mx);
            } else {
                p.worked = "the + travel limit ([machine.travel] not configured)";
            }
            if (p.possible) {
                p.worked += " (runs only if " + step.when + ", not known here)";
                end_known = false;
            } else {
                end_known = true;
                env.end = p.value;
                cur = p.value.known ? std::optional(Interval{p.value.value, p.value.value}) : std::nullopt;
            }
        } else {
            continue;  // no cycle-axis motion
        }
        env.points.push_back(std::move(p));
    }
    if (!end_known) env.end = Val<double>{};
    if (spec.g91_forbidden && env.incremental)
        env.notes.push_back(spec.name + " does not work under G91 (its motion is shifted); the envelope is the G90 reading");
    if (before.units.is(Units::Inch) && spec.mm_only)
        env.notes.push_back(spec.name + " works in mm only; the values are taken as written");

    // Positioning plane: the start point / hole centre.
    std::map<char, double> centre;
    for (char a : {pa.first, pa.second}) {
        std::optional<double> v;
        std::string what;
        if (call.kind == CallKind::ModinPositioning) {
            if (block_has_axis(b, a)) {
                v = block_axis_target(b, a, before);
                what = std::string(1, a);
            } else if (!b.statement(StmtKind::CoordCalc) && before.axis(a).known) {
                v = before.axis(a).value;
                what = "current " + std::string(1, a);
            }
        } else {
            const ArgSpec* pos = nullptr;
            for (const auto& as : spec.args)
                if (as.role == ArgRole::Position && as.axis(pn) && *as.axis(pn) == a) pos = &as;
            const MacroArg* m = pos ? given_arg(call, pos, pos->name) : nullptr;
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
            centre[a] = *v;
            env.plane_points.push_back({a, *v, what});
        }
    }
    add_plane_spans(env, spec, lookup, plane, centre);
    finish(env);
    return env;
}

// --- Fixed cycles and G-code macro cycles --------------------------------------

std::optional<Envelope> hole_envelope(const Block& b, const ModalState& before, const ModalState& after,
                                      const Config& config) {
    const ActiveCycle& c = *after.cycle.value;
    const MacroSpec* macro = c.macro.empty() ? nullptr : config.catalog.find(c.macro);
    Envelope env;
    env.source = macro ? MotionSource::CycleMacro : MotionSource::FixedCycle;
    env.name = macro ? macro->name : "G" + std::to_string(c.code);
    env.code = "G" + std::to_string(c.code);
    env.line = b.line;
    env.origin_line = c.start_line;
    env.incremental = before.distance.is(Distance::Incremental);
    if (!before.plane.known) {
        env.notes.push_back("the plane (G17/G18/G19) is not known here, so neither is the cycle axis");
        finish(env);
        return env;
    }
    const Plane plane = before.plane.value;
    env.plane = plane;
    const PlaneAxes pa = plane_axes(plane);
    env.axis = pa.cycle;
    const std::string ax(1, env.axis);
    env.start = before.axis(env.axis);

    // I point: where the hole starts (seed 004 L6; under G99 the previous
    // block's position, A-53).
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
                                : "? (the " + ax + " position before the block is not known)";

    // R and Z in absolute terms (G91: R from the I point, Z from R; 004:L12-13).
    ArgValue r, z;
    if (!before.distance.known) {
        r.state = z.state = ArgValue::State::Unknown;
        r.how = z.how = "G90/G91 not known";
    } else {
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
    }
    auto point_from = [&](const std::string& step, const std::string& label, const std::string& expr,
                          const std::string& mark, const ArgValue& v, const std::string& source,
                          const std::string& text) {
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
    };

    env.points.push_back(ip);
    Val<double> r_val = r.state == ArgValue::State::Known ? Val<double>::of(r.value) : Val<double>{};
    if (macro && !macro->action.empty()) {
        // The macro's own sequence (OG84L: R, Z+L, R), with R and Z as the cycle holds them.
        Lookup lookup = [&](const std::string& name) -> ArgValue {
            const ArgSpec* as = macro->arg(name);
            std::string n = as ? as->name : name;
            if (n == "R") return r;
            if (n == "Z") return z;
            for (const auto& w : b.words) {
                const ArgSpec* wa = macro->arg_for_address(w.address);
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
                const ArgSpec* wa = macro->arg_for_address(addr);
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
            if (as && c.known_absent(addr_of(*macro, n))) {
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
        };
        for (const auto& step : macro->action) {
            if (step.target.empty()) continue;
            if (!step.when.empty()) continue;  // M52/M53 returns follow the fixed-cycle rules below
            Evaluated e = evaluate_expr(step.target, macro, lookup, false);
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
    } else {
        env.points.push_back(point_from("R", "R point", "R", "R", r, "004:L7-8",
                                        "R point: rapid changes to cutting feed"));
        env.points.push_back(point_from("Z", "Z point", ax, "Z", z, "004:L9", "Z point: the final depth"));
        if (!macro && !config.catalog.find_cycle(c.code))
            env.notes.push_back("G" + std::to_string(c.code) + " is not described in the manuals: I -> R -> Z assumed");
    }

    // The return after the hole: M52/M53/M54 when known, else G98/G99.
    Val<int> rl = after.return_level;
    auto add_return = [&](MotionPoint p, bool possible) {
        p.possible = possible;
        if (possible && p.value.known) {
            p.reach = Interval{p.value.value, p.value.value};
            p.value = Val<double>{};
            p.worked += " (only if this return level is in effect, not known here)";
        }
        env.points.push_back(std::move(p));
    };
    auto g71_point = [&]() {
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
    };
    auto limit_point = [&]() {
        MotionPoint p;
        p.step = "return";
        p.label = "return (M52)";
        p.mark = "+lim";
        p.expr = ax + "+ limit";
        p.limit = true;
        p.source = "M52: return to the upper limit";
        p.text = "M52: return to the + travel limit";
        if (auto mx = travel_max(config, env.axis)) {
            p.value = Val<double>::of(*mx);
            p.worked = num(*mx) + " ([machine.travel] max)";
        } else {
            p.worked = "the + travel limit ([machine.travel] not configured)";
        }
        return p;
    };
    if (rl.is(53)) {
        add_return(g71_point(), false);
        env.end = env.points.back().value;
    } else if (rl.is(52) && plane == Plane::G17) {
        add_return(limit_point(), false);
        env.end = env.points.back().value;
    } else {
        if (!rl.known) {
            if (plane == Plane::G17 && after.g71_level.known) add_return(g71_point(), true);
        } else if (rl.is(52)) {
            env.notes.push_back("M52 in " + std::string(plane_name(plane)) + ": the upper-limit return is followed in G17 only");
        }
        if (after.cycle_return.is(CycleReturn::R) || rl.is(54)) env.end = r_val;
        else if (after.cycle_return.is(CycleReturn::Initial)) env.end = env.start;
    }

    // Positioning plane: the hole position.
    for (char a : {pa.first, pa.second}) {
        if (!block_has_axis(b, a) || b.statement(StmtKind::CoordCalc)) continue;
        Val<double> v = after.axis(a);
        if (v.known) env.plane_points.push_back({a, v.value, std::string(1, a)});
    }
    if (b.statement(StmtKind::CoordCalc))
        env.notes.push_back("the hole positions come from " + b.statement(StmtKind::CoordCalc)->name +
                            " (several holes, same cycle-axis motion)");
    finish(env);
    return env;
}

}  // namespace

std::string MotionPoint::describe() const {
    std::string out = label.empty() ? "step " + step : label;
    out += ": ";
    out += expr;
    if (!worked.empty()) out += " = " + worked;
    if (inferred) out += " [inferred]";
    return out;
}

std::vector<const MotionPoint*> Envelope::unknown_points() const {
    std::vector<const MotionPoint*> out;
    for (const auto& p : points)
        if (!p.possible && !p.limit && !p.value.known) out.push_back(&p);
    return out;
}

std::string Envelope::title() const {
    switch (source) {
        case MotionSource::FixedCycle: return name + " hole";
        case MotionSource::CycleMacro: return code + " hole (" + name + ")";
        case MotionSource::Macro: break;
    }
    switch (call_kind) {
        case CallKind::Call: return name + " (CALL)";
        case CallKind::ModinPositioning: return name + " (MODIN, line " + std::to_string(origin_line) + ")";
        case CallKind::GCode: return name + " (" + code + ")";
        default: return name;
    }
}

bool is_cycle_hole(const Block& b, const ModalState& before, const ModalState& after, const MacroCall* call) {
    (void)before;
    if (b.kind != LineKind::Block) return false;
    if (!after.cycle.known || !after.cycle.value) return false;
    // Positioning only: NCYL, G100, NOEX (one-shots of the block), G80.
    if (after.ncyl || after.g100 || after.noex || has_code(b, 'G', 80)) return false;
    if (b.statement(StmtKind::Ncyl) || b.statement(StmtKind::Noex) || has_code(b, 'G', 100)) return false;
    for (int c : {4, 71, 92, 50, 22, 23})
        if (has_code(b, 'G', c)) return false;
    // The declaration block of a G-code macro cycle positions only (003:L86-88);
    // a CALL, a MODIN or a modal macro call inside a cycle is not a hole.
    if (call && call->kind != CallKind::MCode) return false;
    if (b.statement(StmtKind::Call) || b.statement(StmtKind::Modin)) return false;
    if (b.statement(StmtKind::CoordCalc) || b.find("R")) return true;
    for (const auto& w : b.words)
        if (is_any_axis(w.address)) return true;
    // The block that starts the cycle drills where the tool stands.
    const ActiveCycle& c = *after.cycle.value;
    return c.start_line == b.line && !c.start_range.empty() && b.range.begin <= c.start_range.begin &&
           c.start_range.end <= b.range.end;
}

std::optional<Envelope> cycle_envelope(const Block& b, const ModalState& before, const ModalState& after,
                                       const MacroCall* call, const Config& config) {
    if (b.kind != LineKind::Block) return std::nullopt;
    if (call && call->spec && call->spec->kind == SpecKind::Macro && !call->spec->action.empty()) {
        const MacroSpec& spec = *call->spec;
        bool runs = call->kind == CallKind::Call ||
                    (call->kind == CallKind::ModinPositioning && !b.statement(StmtKind::Ncyl)) ||
                    (call->kind == CallKind::GCode && !is_cycle_macro(spec));
        if (runs) return macro_envelope(b, before, after, *call, spec, config);
    }
    if (is_cycle_hole(b, before, after, call)) return hole_envelope(b, before, after, config);
    return std::nullopt;
}

std::optional<Envelope> cycle_envelope(const BlockView& v, const Config& config) {
    return cycle_envelope(v.block, v.before, v.after, v.call, config);
}

std::vector<TravelViolation> travel_violations(const Envelope& env, const Config& config) {
    std::vector<TravelViolation> out;
    if (env.axis) {
        if (auto it = config.travel.find(env.axis); it != config.travel.end()) {
            const TravelLimit& t = it->second;
            const MotionPoint *below = nullptr, *above = nullptr;
            for (const auto& p : env.points) {
                if (p.possible || p.limit || p.start || !p.value.known) continue;
                if (p.value.value < t.min && (!below || p.value.value < below->value.value)) below = &p;
                if (p.value.value > t.max && (!above || p.value.value > above->value.value)) above = &p;
            }
            auto index = [&](const MotionPoint* p) { return static_cast<int>(p - env.points.data()); };
            if (below)
                out.push_back({env.axis, below->value.value, t.min, true, below->describe(), below->inferred, "",
                               index(below)});
            if (above)
                out.push_back({env.axis, above->value.value, t.max, false, above->describe(), above->inferred, "",
                               index(above)});
        }
    }
    for (const auto& pp : env.plane_points) {
        if (pp.what.rfind("current", 0) == 0) continue;  // where the tool already is: not a move of this block
        auto it = config.travel.find(pp.axis);
        if (it == config.travel.end()) continue;
        if (pp.value < it->second.min)
            out.push_back({pp.axis, pp.value, it->second.min, true, "positioning to " + pp.what + " = " + num(pp.value), false,
                           pp.what, -1});
        else if (pp.value > it->second.max)
            out.push_back({pp.axis, pp.value, it->second.max, false, "positioning to " + pp.what + " = " + num(pp.value),
                           false, pp.what, -1});
    }
    return out;
}

std::vector<TravelViolation> positioning_violations(const Block& b, const ModalState& before, const ModalState& after,
                                                    const MacroCall* call, const Config& config) {
    std::vector<TravelViolation> out;
    if (b.kind != LineKind::Block || config.travel.empty()) return out;
    if (call && call->kind != CallKind::GCode) return out;  // macros: see their envelopes
    if (call && call->spec && !is_cycle_macro(*call->spec)) return out;
    if (is_cycle_hole(b, before, after, call)) return out;  // holes: see their envelopes
    if (non_motion_block(b) || b.statement(StmtKind::Call) || b.statement(StmtKind::Modin)) return out;
    const bool in_cycle = after.cycle.known && after.cycle.value;
    const char cyc = before.plane.known ? plane_axes(before.plane.value).cycle : 0;
    std::set<char> seen;
    for (const auto& w : b.words) {
        if (!is_axis_letter(w.address)) continue;
        char a = w.address[0];
        if (in_cycle && a == cyc) continue;  // a cycle depth, not a move
        if (!seen.insert(a).second) continue;
        auto it = config.travel.find(a);
        Val<double> v = after.axis(a);
        if (it == config.travel.end() || !v.known) continue;
        std::string what = "positioning " + std::string(1, a) + num(v.value);
        if (v.value < it->second.min) out.push_back({a, v.value, it->second.min, true, what, false, w.address, -1});
        else if (v.value > it->second.max) out.push_back({a, v.value, it->second.max, false, what, false, w.address, -1});
    }
    return out;
}

}  // namespace osplint
