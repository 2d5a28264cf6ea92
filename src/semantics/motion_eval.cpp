// The catalog's expressions, evaluated against the arguments of a call (see
// motion_internal.h): the arithmetic each point of an
// envelope shows ("PZ-PI-PL = -20-12-5 = -37") and why a value is not known.
#include <algorithm>
#include <cctype>
#include <cstring>

#include "semantics/motion_internal.h"

namespace osplint::motion_detail {


// --- Tri-state values ------------------------------------------------------------

Tri tri_of(const Val<bool>& v) { return v.known ? (v.value ? Tri::True : Tri::False) : Tri::Unknown; }

// --- Argument values ----------------------------------------------------------

bool zero_when_absent(const ArgSpec& a) {
    return a.omitted == ArgOmitted::None &&
           (a.role == ArgRole::Length || a.role == ArgRole::Stroke || a.role == ArgRole::Shift);
}

Evaluated evaluate_expr(const std::string& text, const MacroSpec* spec, const Lookup& lookup, bool conditional,
                        bool describe) {
    Evaluated out;
    const auto* terms = catalog_expr(text);
    if (!terms) {
        out.why = "\"" + text + "\" is not an expression osplint can read";
        out.worked = "? (" + out.why + ")";
        return out;
    }
    if (!describe)
        return sum_values(*terms, conditional, [&](size_t k) {
            const std::string& name = (*terms)[k].name;
            ArgValue av = lookup(name);
            const ArgSpec* as = av.state == ArgValue::State::Absent && spec ? spec->arg(name) : nullptr;
            return std::pair{std::move(av), as};
        });
    double sum = 0;
    bool known = true;
    std::string shown, notes, unknown_why;
    for (size_t k = 0; k < terms->size(); ++k) {
        const ExprTerm& t = (*terms)[k];
        double v = t.number;
        std::string piece;
        if (!t.name.empty()) {
            ArgValue av = lookup(t.name);
            if (av.state == ArgValue::State::Absent) {
                const ArgSpec* as = spec ? spec->arg(t.name) : nullptr;
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
                if (describe && !av.how.empty()) notes += (notes.empty() ? "" : "; ") + t.name + " " + av.how;
            }
        }
        sum += t.sign * v;
        if (!describe) continue;
        if (piece.empty()) piece = k == 0 ? (t.sign < 0 ? "-" + paren(v) : num(v)) : (t.sign < 0 ? "-" : "+") + paren(v);
        else piece = (k == 0 ? (t.sign < 0 ? "-" : "") : (t.sign < 0 ? "-" : "+")) + piece;
        shown += piece;
    }
    if (!describe) {
        if (known) out.value = Val<double>::of(sum);
        return out;
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

std::string addr_of(const MacroSpec& spec, const std::string& name) {
    if (spec.gcode_form)
        for (const auto& [addr, target] : spec.gcode_form->address_map)
            if (target == name) return addr;
    return name;
}

const MacroArg* given_arg(const MacroCall& c, const ArgSpec* a, const std::string& name) {
    if (!a) return c.arg(name);
    if (const MacroArg* m = c.given(*a)) return m;
    // given() has looked for `a` by its name and its aliases already: only
    // another spelling of it can still be written on the call.
    if (name == a->name || std::find(a->aliases.begin(), a->aliases.end(), name) != a->aliases.end()) return nullptr;
    return c.arg(name);
}

MotionPoint step_point(const ActionStep& step) {
    MotionPoint p;
    p.step = step.step;
    p.label = "step " + step.step;
    p.text = step.text;
    p.source = step.source;
    p.inferred = step.inferred;
    return p;
}

std::string mark_for(const std::string& expr) {
    if (expr == "PR" || expr == "R") return "R";
    if (expr == "PZ" || expr == "Z") return "Z";
    if (expr == "PA") return "A";
    if (expr == "PT") return "T";
    if (expr == "Z+L") return "Z+L";  // OG84L: the spindle stops at Z+L, the tap reaches Z
    return "";
}

}  // namespace osplint::motion_detail
