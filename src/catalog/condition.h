// The `when` conditions of the catalog (action steps and relations), parsed
// once when the catalog loads. A condition is atoms joined by `and`, `or` and
// `not`, with parentheses:
//
//   G17 G18 G19      the active plane
//   G90 G91          absolute or incremental mode
//   M52 M53 M54      the return mode in effect for the call
//   M3 M4 M5         the spindle's state when the call starts (M3 forward,
//                    M4 reverse, M5 stopped; an M code on the call line
//                    itself is not read by the macro)
//   G40 G41 G42      cutter-radius compensation in effect at the call
//   given:PK         the argument is written on the call
//   PM=52            the argument is written with this value
//
// A condition is evaluated three-valued: what decides an atom is the caller's
// (the motion evaluator knows the modal state and the call; a rule may know
// only which arguments are given and leave the rest Unknown).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "support/function_ref.h"

namespace osplint {

// True, false, or not known statically.
enum class Tri { False, True, Unknown };

struct ConditionAtom {
    enum class Kind {
        Plane,      // number: 17, 18, 19
        Distance,   // number: 90, 91
        MCode,      // number: 52, 53, 54
        Spindle,    // number: 3, 4, 5
        CutterComp, // number: 40, 41, 42
        Given,      // arg
        ArgEquals,  // arg = value
    };
    Kind kind = Kind::Plane;
    int number = 0;
    std::string arg;  // upper case
    double value = 0;
};

class Condition {
public:
    Condition() = default;
    // Parses `text`; on a syntax error returns nullopt and sets `error` to
    // what is wrong ("unknown atom \"G16\"").
    static std::optional<Condition> parse(std::string_view text, std::string& error);

    // No condition: the step or relation always applies.
    bool empty() const { return nodes_.empty(); }
    // As written in the catalog, for cards and messages.
    const std::string& text() const { return text_; }

    // Three-valued: an atom `decide` cannot decide is Unknown, and so is
    // everything that depends on it.
    Tri eval(FunctionRef<Tri(const ConditionAtom&)> decide) const;

    // Every atom, in the order written (to validate argument names).
    std::vector<const ConditionAtom*> atoms() const;
    // The plane the condition requires: a G17/G18/G19 atom that must hold
    // for the whole condition to hold (a conjunct of the top level).
    std::optional<int> required_plane() const;
    // Whether an atom of this kind and number (M52, G17) or this argument
    // value (PM=52) occurs anywhere in the condition.
    bool mentions(ConditionAtom::Kind kind, int number) const;
    bool mentions_value(std::string_view arg, double value) const;

private:
    struct Node {
        enum class Op { Atom, And, Or, Not } op = Op::Atom;
        int left = -1, right = -1;  // children (Not: left only)
        ConditionAtom atom;
    };
    friend class ConditionParser;
    Tri eval_node(int i, FunctionRef<Tri(const ConditionAtom&)> decide) const;
    std::vector<Node> nodes_;
    int root_ = -1;
    std::string text_;
};

}  // namespace osplint
