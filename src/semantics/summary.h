// What a user subprogram (a program called with CALL that is not a macro of
// the catalog) leaves behind for its caller, worked out by analysing the
// subprogram itself: the modes it sets on every path to its end.
//
// The subprogram is walked twice, from two entry states that differ in every
// summarised mode (G90/G17/mm/G0, then G91/G18/inch/G1). A mode that ends the same
// in both walks is set by the subprogram; one that ends as it came in both is
// left as the caller had it; anything else (set on some paths only, or from a
// variable) is unknown after the call. Subprograms it calls in turn are taken
// as leaving the modes as they were, as every subprogram is where no summary
// is known.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "semantics/modal.h"

namespace osplint {

struct Config;

// One mode after the call: set to a value, left as the caller had it, or not known.
template <class T>
struct ModeEffect {
    enum class Kind { Kept, Set, Unknown } kind = Kind::Kept;
    T value{};
    friend bool operator==(const ModeEffect&, const ModeEffect&) = default;
};

struct SubprogramSummary {
    std::string name;  // "O1234"
    std::string file;  // the file that defines it
    uint32_t line = 0; // its name line (1-based)
    ModeEffect<Distance> distance;
    ModeEffect<Plane> plane;
    ModeEffect<Units> units;
    ModeEffect<int> motion;  // G0, G1, G2, G3 or G60 (a subprogram that ends in G60 keeps NCYL from working)

    // Whether it changes anything the caller had.
    bool changes_anything() const;
    // "leaves G91 in effect; sets G18", for notes; "" when it changes nothing.
    std::string describe() const;
};

// The two entry states of the walks: the state of a subprogram's entry
// (nothing known) with the summarised modes set one way, then the other
// (G90 G17 mm G0, then G91 G18 inch G1).
ModalState summary_probe(int which);
// The summary from the states where the two walks end (nullptr: no path
// reaches the end of the subprogram).
SubprogramSummary summarize(const ModalState* end0, const ModalState* end1);

// Applies the summary to the state after the CALL.
void apply_summary(const SubprogramSummary& summary, ModalState& s);

}  // namespace osplint
