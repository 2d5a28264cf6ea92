// Cycle-axis motion: where a macro call or a fixed-cycle hole takes the tool.
//
// For every block that runs a catalog macro (a CALL, a positioning block of an
// open MODIN, a one-shot G-code macro) or a hole of a fixed cycle (G81 ...,
// and the G-code macro cycle OG84L/G114), the evaluator walks the manual's
// action sequence (the catalog's `action` steps, or the fixed-cycle points
// I -> R -> Z of the fixed cycles manual, with the K point of G77, the J depth
// of G83 and the relief of G88) and records, per step, the cycle-axis position the
// step reaches. The envelope is the range [lowest, highest] of those points,
// each end naming the step that produced it ("step 3c: PZ-PI-PL = -20-12-5 =
// -37").
//
// Nothing is guessed: an argument or start position the analyzer cannot know
// leaves its points unknown, and the envelope says which end it cannot bound.
// Strokes whose direction the manual does not print (OG87N "by PL") and steps
// whose condition cannot be decided (M53 modal state unknown) are kept apart
// as "possible" points: they widen the picture, never a finding.
//
// Axes follow the plane: the cycle axis is Z in G17, Y in G18, X in G19, and
// the catalog's "+" (toward the R side, up on a vertical machine) is the +
// direction of that axis in every plane.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "semantics/config.h"
#include "semantics/modal.h"
#include "syntax/model.h"
#include "semantics/calls.h"

namespace osplint {

struct Interval {
    double lo = 0;
    double hi = 0;
};

enum class MotionSource : uint8_t {
    Macro,       // CALL, MODIN positioning block, one-shot G-code macro
    FixedCycle,  // a hole of G73..G89, G77, G78, G186 ...
    CycleMacro,  // a hole of a G-code macro cycle (OG84L registered to G114)
};

// One cycle-axis point of the motion, from one step of the action sequence.
struct MotionPoint {
    std::string step;    // "3c"; fixed cycles: "I", "R", "K", "J", "J return", "d2", "Z", "shift", "return"
    std::string label;   // "step 3c", "R point", "return (G98)"
    std::string mark;    // short label for pictures: "R", "Z", "A", "T", "I", "G71", "+lim"; "" = none
    std::string expr;    // the catalog expression ("PZ-PI-PL"), or what the point is ("I point")
    std::string worked;  // the arithmetic ("-20-12-5 = -37") or why the value is unknown
    std::string text;    // the step's description from the catalog
    std::string source;  // "000:L607"
    Val<double> value;   // the position reached (definite points)
    std::optional<Interval> reach;  // possible points: where the tool may end up
    bool possible = false;  // may or may not be reached (see the header comment)
    bool inferred = false;  // the catalog marks this target as inferred, not printed
    bool limit = false;     // the + travel limit of the axis (M52 / PM=52 in G17)
    bool start = false;     // where the tool already is when the block starts (the I point):
                            // part of the envelope, but no move of this block

    // "step 3c: PZ-PI-PL = -20-12-5 = -37" (fixed cycles: "R point: R = 3").
    std::string describe() const;
};

// An end of an envelope: its value and the point that produced it.
struct EnvelopeEnd {
    double value = 0;
    std::size_t point = 0;  // index into Envelope::points
};

// A point of the positioning plane the motion certainly visits (a hole centre,
// a macro's start point), in program coordinates.
struct PlanePoint {
    char axis = 0;
    double value = 0;
    std::string what;  // "PX" / "X"
};

// Where the motion spreads in the positioning plane (a slot, a counterbore
// circle, the shift of a fine-boring cycle), checked against the travel like
// the points (`travel_violations`).
struct PlaneSpan {
    char axis = 0;
    Interval range;
    std::string why;
    bool inferred = false;     // rests on a reading (e.g. the start point is one end of the slot)
    bool compensated = false;  // a contour cut with cutter-radius compensation: the spindle
                               // centre runs inside it by the tool radius, which is not known
    std::string arg;           // the argument or address that sets its extent ("PC", "PI", "I")
    bool either_way = false;   // the motion goes to one end or the other (a direction the
                               // manual does not document): not checked against the travel
};

struct Envelope {
    MotionSource source = MotionSource::Macro;
    std::string name;              // "OZAGR", "G81", "OG84L"
    std::string code;              // "G114", "G81"; empty for CALL/MODIN
    CallKind call_kind = CallKind::None;
    uint32_t line = 0;             // the block
    uint32_t origin_line = 0;      // the MODIN line / the block that started the cycle (0 for a CALL)
    std::optional<Plane> plane;    // unknown plane: no axis, nothing bounded
    char axis = 0;                 // the cycle axis ('Z' in G17)
    bool incremental = false;      // G91 in effect
    std::vector<MotionPoint> points;  // in the order of the action sequence
    std::optional<EnvelopeEnd> lowest, highest;  // extremes of the known definite points
    bool bounded_low = true;       // no definite point is unknown (lowest is the true lowest)
    bool bounded_high = true;
    std::optional<std::size_t> limit_point;  // the motion goes to the + travel limit
    std::optional<EnvelopeEnd> may_low, may_high;  // possible points beyond lowest / highest
    Val<double> start;             // the cycle-axis position before the block
    Val<double> end;               // where the tool is left on the cycle axis
    std::vector<PlanePoint> plane_points;
    std::vector<PlaneSpan> plane_spans;
    std::vector<std::string> notes;  // readings applied, steps skipped

    bool bounded() const { return plane && bounded_low && bounded_high; }
    // Definite points whose value is unknown (why the envelope is not bounded).
    std::vector<const MotionPoint*> unknown_points() const;
    // "OZAGR (CALL)", "G81 hole", "G114 hole (OG84L)"
    std::string title() const;
};

// Whether the block drills a hole of the fixed cycle active after it (not
// under NCYL or G100, not the G-code macro declaration block).
bool is_cycle_hole(const Block& block, const ModalState& before, const ModalState& after, const MacroCall* call);

// How much of an envelope to work out. Values: every number and flag as in
// Full (points, extremes, bounds, end, plane points and spans), without the
// text that shows them (a point's label, arithmetic and catalog text, the
// notes, a span's reason): what a rule needs to decide whether it reports,
// at a fraction of the cost; it asks again in full for the finding. The
// points of a fixed cycle's holes are described either way (only the steps
// of a G-code macro cycle's own sequence, OG84L's, go without their text).
// Plane: as Values without the points on the cycle axis (what a rule asks
// once MacroAxisMemo or HoleAxisMemo has told it they are as before): for a
// macro, without the points of its action steps; for a hole, its position in
// the plane only (a G88 hole, whose shifts after Z move in the plane, as
// Values).
enum class EnvelopeDetail : uint8_t { Full, Values, Plane };

// The envelope of the motion the block runs on the cycle axis, or nullopt when
// it runs no macro and no fixed-cycle hole. The holes of a G-code macro cycle
// read the arguments of earlier blocks (G114 ... L) from the cycle's modal words.
std::optional<Envelope> cycle_envelope(const Block& block, const ModalState& before, const ModalState& after,
                                       const MacroCall* call, const Config& config,
                                       EnvelopeDetail detail = EnvelopeDetail::Full);
std::optional<Envelope> cycle_envelope(const BlockView& view, const Config& config,
                                       EnvelopeDetail detail = EnvelopeDetail::Full);

// The last macro call remembered, with all that the points of its action
// steps (the cycle-axis part of its envelope) are worked out from: the macro,
// the kind of call, the plane, the modes the steps' conditions test
// (distance, spindle, cutter compensation, return level), the current
// cycle-axis position, the cycle axis's travel limits, and each argument the
// action sequence reads (MacroSpec::action_args). A call that agrees on all
// of these has the same points: a posted program calls a macro thousands of
// times with only its position changed. A macro whose steps read more than
// that (MacroSpec::action_args is nullptr) is never remembered. OSP301
// keeps one for each of the last few calls whose points are inside the
// travel; the transfer step, one for a call's end point (macro_end). A
// cache, not state: what is worked out with it is what is worked out
// without it.
class MacroAxisMemo {
public:
    // Whether `v` runs a macro with the same points as the call remembered,
    // under `travel` ([machine.travel]; none where no limit is known).
    bool same(const BlockView& v, const TravelLimits& travel) const;
    // Remembers `v`, when it runs a macro whose steps' reads are listed;
    // otherwise forgets.
    void remember(const BlockView& v, const TravelLimits& travel);
    // Whether a call is remembered (remember forgets one whose steps' reads are not listed).
    bool holds() const { return key_.spec != nullptr; }
    // The macro of the call remembered (nullptr: none).
    const MacroSpec* spec() const { return key_.spec; }

private:
    struct Key {
        const MacroSpec* spec = nullptr;
        CallKind kind = CallKind::None;
        Val<Plane> plane;
        Val<Distance> distance;
        Val<int> spindle, cutter_comp, return_level;
        Val<double> position;  // on the cycle axis
        std::optional<TravelLimit> travel;  // of the cycle axis
    };
    // The key of `v` (spec nullptr: not one to remember), and in `args` what
    // it reads of each argument. `same` compares `v` with the key as it reads
    // it: a field added to Key is read in both.
    static Key key_of(const BlockView& v, const TravelLimits& travel, std::vector<ArgSeen>* args);
    Key key_;
    std::vector<ArgSeen> args_;
};

// The last hole of a modal cycle remembered, with all that its points on the
// cycle axis are worked out from: the cycle (its code, macro, R, Z and modal
// words), the plane, G90/G91, the cycle-axis position before the block, the
// return level, the G71 level, G98/G99 and the cycle axis's travel limits. A
// hole block that gives no word but the two plane axes, in a cycle that
// agrees on all of these, has the same points there: a posted program drills
// thousands of holes of one cycle with only X and Y changed. Not remembered:
// a G88 hole (its shifts after Z move in the plane), a G-code macro cycle
// whose steps read more than MacroSpec::action_args lists or read the
// argument a plane axis gives. OSP301 remembers a hole whose cycle-axis
// points are inside the travel. A cache, not state.
class HoleAxisMemo {
public:
    // Whether `v` drills a hole with the same cycle-axis points as the one
    // remembered, under `config` (its travel limits).
    bool same(const BlockView& v, const Config& config) const;
    // Remembers `v` when it is such a hole; otherwise forgets.
    void remember(const BlockView& v, const Config& config);

private:
    struct Key {
        std::optional<ActiveCycle> cycle;  // nullopt: nothing remembered
        Val<Plane> plane;
        Val<Distance> distance;
        Val<double> position;  // on the cycle axis, before the block
        Val<int> return_level;
        Val<double> g71_level;
        Val<CycleReturn> cycle_return;
        std::optional<TravelLimit> travel;  // of the cycle axis
    };
    // The key of `v` (cycle nullopt: not a hole to remember). `same` reads
    // `v` as key_of does, field by field: a field added to Key is read in both.
    static Key key_of(const BlockView& v, const Config& config);
    Key key_;
};

// Where a catalog macro the block runs (a CALL, a positioning block of an open
// MODIN, a one-shot G-code macro) leaves the tool on the cycle axis: the axis
// and the last point of its action sequence, when that point is definite and
// known (`Envelope::end`); nullopt otherwise. The + travel limit (M52) needs
// `[machine.travel]`, which the transfer function does not have: nullopt.
// `memo`, when set, holds the last call worked out and its end point: a call
// it calls the same takes that end point.
struct MacroEndMemo {
    MacroAxisMemo call;
    std::optional<std::pair<char, double>> end;
    bool fresh = false;  // the last call of macro_end with it found `end` there, or remembered it
};
// `repeat`: as apply_block's; the end point is then the memo's, when the
// last call found or remembered it there and the macro's steps read no
// argument the plane's axes give.
std::optional<std::pair<char, double>> macro_end(const Block& b, const ModalState& before, const ModalState& after,
                                                 const MacroCall* call, MacroEndMemo* memo = nullptr,
                                                 bool repeat = false);
// Whether macro_end, on a repeat of the call it worked out last with
// `memo`, takes the memo's end point as it is: the last call found or
// remembered it there, and the macro's steps read no argument the plane's
// axes give (so the call's values in the plane do not move that point).
bool macro_end_repeats(const MacroEndMemo& memo, const MacroSpec& spec, const ModalState& before);

// A point outside `[machine.travel]`.
struct TravelViolation {
    char axis = 0;
    double value = 0;    // the position reached
    double limit = 0;    // the limit it passes
    bool below = false;  // below the minimum (else above the maximum)
    std::string what;    // "step 3c: PZ-PI-PL = -298-5-5 = -308", "positioning to PX = 420"
    bool inferred = false;
    std::string name;    // plane points and spans: the argument or address that set the position ("PX", "X")
    int point = -1;      // cycle axis: index into Envelope::points
    std::string note;    // spans: what the extent rests on, to be stated with the finding
};

// The definite points of the envelope (cycle axis and plane points) outside
// the configured travel: at most one per axis and direction, the farthest.
// The start point (I) and a trip to the + limit are not moves past a limit.
// Then the plane spans that go beyond a limit, the farthest per axis and
// direction, where no plane point is already past that limit; a span that is
// inferred or a compensated contour is `inferred`, with its `note`.
std::vector<TravelViolation> travel_violations(const Envelope& env, const Config& config);

// An axis a plain positioning block moves to outside the configured travel.
// No initialisers: axes_past_travel sets every field of the ones it counts,
// and leaves the others of its array alone (zeroing it on every move costs
// more than the check).
struct AxisPastTravel {
    char axis;
    double value;  // the position reached
    double limit;  // the limit it passes
    bool below;    // below the minimum (else above the maximum)
    ByteRange word;  // the axis's word on the block (its last, when written twice)
};
// At most one per axis X, Y, Z, in the order of the block's words: a fixed
// array, since a wrong work offset puts every move of a program here.
struct AxesPastTravel {
    std::array<AxisPastTravel, 3> axes;
    size_t count = 0;
    const AxisPastTravel* begin() const { return axes.data(); }
    const AxisPastTravel* end() const { return axes.data() + count; }
};

// A plain positioning block (no macro, no hole): the axes it moves to outside
// the configured travel. A block the view says is a plain move is one.
AxesPastTravel positioning_violations(const BlockView& v, const Config& config);

// X, Y or Z (inline: asked of every word of every move).
inline bool is_axis_letter(std::string_view a) { return a.size() == 1 && (a[0] == 'X' || a[0] == 'Y' || a[0] == 'Z'); }
// The axis a word moves, X, Y or Z, else 0: of a block's word, or of a plain
// move's read without its block.
inline char moved_axis(const Word& w) { return is_axis_letter(w.address) ? w.address[0] : 0; }
inline char moved_axis(const PlainMoveWord& w) { return w.address >= 'X' && w.address <= 'Z' ? w.address : 0; }

// What positioning_violations finds once it knows the block moves to its
// axis words (every one but the cycle axis in a fixed cycle, a depth), from
// the block's words or from a plain move's (PlainMove): called directly for a
// block the engine says is a plain move (inline: a wrong work offset puts
// every move of a program here). `limits`: the configured travel's
// axis_limits, looked up once for many blocks (RuleContext::axis_limits).
template <class Words>
AxesPastTravel axes_past_travel(const Words& words, const ModalState& before, const ModalState& after,
                                const AxisLimits& limits) {
    AxesPastTravel out;
    const bool in_cycle = after.cycle.known && after.cycle.value;
    const char cyc = in_cycle && before.plane.known ? plane_axes(before.plane.value).cycle : 0;
    unsigned seen = 0;                        // X, Y, Z: bits 0, 1, 2
    std::array<uint8_t, 3> slot{3, 3, 3};     // X, Y, Z: the place in out.axes (3: none)
    size_t count = 0;
    for (const auto& w : words) {
        const char a = moved_axis(w);
        if (!a || (in_cycle && a == cyc)) continue;  // not an axis; a cycle depth, not a move
        const auto i = static_cast<size_t>(a - 'X');
        const unsigned bit = 1u << i;
        if (seen & bit) {
            if (slot[i] < 3) out.axes[slot[i]].word = w.range;
            continue;
        }
        seen |= bit;
        const TravelLimit* limit = limits[i];
        const Val<double> pos = after.axis(a);
        if (!limit || !pos.known) continue;
        if (pos.value < limit->min || pos.value > limit->max) {
            // Field by field: a braced temporary is built on the stack in
            // narrow stores and copied in wide loads, a stall on every move.
            const bool below = pos.value < limit->min;
            slot[i] = static_cast<uint8_t>(count);
            AxisPastTravel& t = out.axes[count++];
            t.axis = a;
            t.value = pos.value;
            t.limit = below ? limit->min : limit->max;
            t.below = below;
            t.word = w.range;
        }
    }
    out.count = count;
    return out;
}

// The same, looking the limits up in `config` for this block alone.
template <class Words>
AxesPastTravel axes_past_travel(const Words& words, const ModalState& before, const ModalState& after,
                                const Config& config) {
    return axes_past_travel(words, before, after, axis_limits(config.travel));
}

// A number as the trace and the messages print it: at most 4 decimals, no trailing zeros.
std::string motion_number(double v);

}  // namespace osplint
