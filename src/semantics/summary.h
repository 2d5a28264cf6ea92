// What a user subprogram (a program called with CALL that is not a macro of
// the catalog) leaves behind for its caller, worked out by analysing the
// subprogram itself: the modes it sets on every path to its end, the fixed
// cycle and the MODIN it leaves open, the common variables it writes, and
// whether it returns at all.
//
// The subprogram is walked twice, from two entry states that differ in every
// summarised mode (G90/G17/mm/G0 with no cycle and no MODIN, then
// G91/G18/inch/G1 with both unknown). A mode that ends the same in both walks
// is set by the subprogram; one that ends as it came in both is left as the
// caller had it; anything else (set on some paths only, or from a variable) is
// unknown after the call. Subprograms it calls in turn are taken as leaving
// the modes as they were, as every subprogram is where no summary is known,
// and as writing any common variable.
#pragma once

#include <cstdint>
#include <map>
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
    // The fixed cycle it leaves modal (Set with a value), cancels (Set with
    // none) or leaves as it was; its lines and ranges are the subprogram's.
    ModeEffect<std::optional<ActiveCycle>> cycle;
    ModeEffect<std::optional<OpenCycle>> uncancelled;
    ModeEffect<std::optional<ActiveModin>> modin;  // the MODIN it leaves open, closes, or keeps
    // The common variables it assigns (number -> the value it leaves on every
    // path, when known). `writes_any`: it may write others too (an assignment
    // through a computed name, a subprogram it calls).
    std::map<int, std::optional<double>> writes;
    bool writes_any = false;
    // A catalog macro it runs that overwrites VC120-VC128 ("OG87C"), or empty.
    std::string clobbers_reserved;
    // Whether an RTS ends some path of it: without one, control never comes
    // back to the caller (it ends with M02/M30).
    bool returns = true;

    friend bool operator==(const SubprogramSummary&, const SubprogramSummary&) = default;

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

// Whether two summaries leave the same behind (where they were found aside).
bool same_effect(const SubprogramSummary& a, const SubprogramSummary& b);

// Applies the summary to the state after the CALL at `line` (`range`: the
// called name, where a cycle or a MODIN it leaves open is taken to start).
void apply_summary(const SubprogramSummary& summary, uint32_t line, ByteRange range, ModalState& s);

}  // namespace osplint
