// What the files of the cycle-axis motion evaluator share (motion.h is the
// public interface):
//
//   motion.cpp         the envelope types, finishing an envelope, which blocks
//                      run a macro or a hole (cycle_envelope)
//   motion_eval.cpp    the catalog's expressions, evaluated against the
//                      arguments of a call (`when` conditions: catalog/condition.h)
//   motion_macro.cpp   the envelope of a macro call (the catalog's action steps)
//   motion_hole.cpp    the envelope of a fixed-cycle hole (I -> R -> Z -> return,
//                      with G77 K, G83 J and the G88 shifts)
//   motion_travel.cpp  points outside [machine.travel]
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "catalog/catalog.h"
#include "semantics/motion.h"
#include "support/function_ref.h"
#include "support/text.h"

namespace osplint::motion_detail {

// --- Text ---------------------------------------------------------------------

inline std::string num(double v) { return motion_number(v); }
// A number as a term of a sum: negative numbers in parentheses.
inline std::string paren(double v) { return v < 0 ? "(" + num(v) + ")" : num(v); }
using osplint::contains_ci;  // support/text.h
using osplint::upper;

// --- Blocks and the configuration -----------------------------------------------

bool has_code(const Block& b, char address, int code);
// G codes whose axis words are not a move of the tool tip.
bool non_motion_block(const Block& b);
// A G-code macro that behaves as a fixed cycle until its cancel (OG84L).
bool is_cycle_macro(const MacroSpec& spec);
bool is_any_axis(std::string_view a);  // X Y Z A B C U V W
bool block_has_axis(const Block& b, char axis);
// The plane point a word of the block moves to (G90/G91).
std::optional<double> block_axis_target(const Block& b, char axis, const ModalState& before);
std::optional<double> travel_max(const Config& c, char axis);

// --- Tri-state values (Tri: catalog/condition.h) ---------------------------------

Tri tri_of(const Val<bool>& v);

// --- Argument values and catalog expressions ------------------------------------

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

// An argument the expressions take as 0 when it is not given (a length, a
// stroke or a shift that the manual gives no default).
bool zero_when_absent(const ArgSpec& a);

// What evaluate_expr gives without text (describe false) for `terms`:
// `fetch(k)` gives the value of term k's argument and the spec's argument of
// that name (nullptr: none); an argument not given skips the step when it
// is undocumented or the step `conditional`, counts as 0 when
// zero_when_absent, and leaves the sum unknown otherwise.
template <class Fetch>
Evaluated sum_values(const std::vector<ExprTerm>& terms, bool conditional, const Fetch& fetch) {
    Evaluated out;
    double sum = 0;
    bool known = true;
    for (size_t k = 0; k < terms.size(); ++k) {
        const ExprTerm& t = terms[k];
        double v = t.number;
        if (!t.name.empty()) {
            const auto [av, as] = fetch(k);
            if (av.state == ArgValue::State::Absent) {
                if ((as && as->undocumented) || conditional) {
                    out.skip = true;
                    return out;
                }
                if (as && zero_when_absent(*as)) v = 0;
                else known = false;
            } else if (av.state == ArgValue::State::Unknown) {
                known = false;
            } else {
                v = av.value;
            }
        }
        sum += t.sign * v;
    }
    if (known) out.value = Val<double>::of(sum);
    return out;
}

// Refers to a callable the caller keeps alive (a named lambda), not a copy.
using Lookup = FunctionRef<ArgValue(const std::string&)>;

// Evaluates a catalog expression (a sum of argument names and numbers) with
// the argument values `lookup` gives. `conditional`: the step has a `when`, so
// an argument that is not given skips it.
// `describe` false: only the value and whether the step is skipped (no text).
Evaluated evaluate_expr(const std::string& text, const MacroSpec* spec, const Lookup& lookup, bool conditional,
                        bool describe = true);
// The address an argument of a G-code macro is written with (OG84L: "L" for L).
std::string addr_of(const MacroSpec& spec, const std::string& name);
// The argument of the call that gives `name` (by its name or an alias).
const MacroArg* given_arg(const MacroCall& c, const ArgSpec* a, const std::string& name);
// The picture's mark for a point reached by `expr` ("R", "Z", ...; "" = none).
std::string mark_for(const std::string& expr);
// The point of an action step as the catalog describes it (no value yet).
MotionPoint step_point(const ActionStep& step);

// --- Envelopes ------------------------------------------------------------------

// Sets the extremes and the bounds of an envelope from its points.
void finish(Envelope& env);

// Whether the block runs a catalog macro with an action sequence: a CALL, a
// positioning block of an open MODIN (not under NCYL), a one-shot G-code macro.
bool runs_macro(const Block& b, const MacroCall* call);
// Whether the action steps of `spec` may read an argument a positioning
// axis of `plane` gives (its positioning argument, or the argument the
// axis's address stands for in the G-code form): true when its steps' reads
// are not listed (MacroSpec::action_args). Such a macro's points move with
// the position in the plane.
bool steps_read_plane(const MacroSpec& spec, Plane plane);

// `config` nullptr: the + travel limit (M52) is not known. `describe` false:
// the numbers and flags only (EnvelopeDetail::Values). `steps` false: no
// points of the action steps (EnvelopeDetail::Plane).
std::optional<Envelope> macro_envelope(const Block& b, const ModalState& before, const ModalState& after,
                                       const MacroCall& call, const MacroSpec& spec, const Config* config,
                                       bool describe = true, bool steps = true);
// The cycle axis and the `end` of macro_envelope (no travel limit known),
// when the plane and the end are known: for the transfer step, which needs
// nothing else of the envelope on every macro call.
std::optional<std::pair<char, double>> macro_end_point(const Block& b, const ModalState& before,
                                                       const ModalState& after, const MacroCall& call,
                                                       const MacroSpec& spec);
// `describe` false: the steps of a G-code macro cycle's own sequence
// (OG84L) without their text (EnvelopeDetail::Values); the fixed-cycle
// points are always described. `points` false: no points on the cycle axis,
// but for a G88 hole (EnvelopeDetail::Plane).
std::optional<Envelope> hole_envelope(const Block& b, const ModalState& before, const ModalState& after,
                                      const Config& config, bool describe = true, bool points = true);

// Whether two values are the same as a memo of the motion reads them: both
// unknown, or both known and equal (an unknown value's field is not read).
template <class T>
bool same_val(const Val<T>& a, const Val<T>& b) {
    return a.known == b.known && (!a.known || a.value == b.value);
}

}  // namespace osplint::motion_detail
