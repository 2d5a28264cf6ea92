// Modal state of the control, computed once per block and shared by all rules.
//
// Every field is a `Val<T>`: either known (with a value) or unknown. The state
// at a block is the merge of the states flowing into it (textual predecessor,
// every jump to its sequence name, loop back edges); fields that differ become
// unknown. Rules never fire on an unknown field as if it were known; for
// G90/G91, G20/G21, G60, the plane, an open fixed cycle and an open MODIN the
// state also keeps where the value rules warn about was set (`ModeOrigin`), so
// that a rule can say what *may* be in effect and on which path.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "support/shared_value.h"
#include "syntax/model.h"

namespace osplint {

struct SubprogramSummary;

template <class T>
struct Val {
    bool known = false;
    T value{};

    // A number too large for a double (a sum of huge values) is unknown: the
    // state never holds an infinity or a NaN that a message could print.
    static Val of(T v) {
        if constexpr (std::is_floating_point_v<T>)
            if (!std::isfinite(v)) return Val{};
        return Val{true, std::move(v)};
    }
    static Val unknown() { return Val{}; }
    bool is(const T& v) const { return known && value == v; }
    // Merge: equal known values stay, anything else becomes unknown.
    void merge(const Val& o) {
        if (!known) return;
        if (!o.known || !(value == o.value)) *this = Val{};
    }
    friend bool operator==(const Val&, const Val&) = default;
};

enum class Units : uint8_t { Mm, Inch };
enum class Distance : uint8_t { Absolute, Incremental };  // G90 / G91

// Where a mode that some rules warn about (G91, G20, G60, a plane other than
// G17, a fixed cycle or a MODIN left open) was set, for "may"
// findings: the block that set it last on some path that reaches here (its
// line and the range of the word; line 0: the initial state) and the last jump
// that path took since (line 0: none). When paths disagree the field itself is
// unknown, and the origin says that the mode may be in effect and how it got
// here. Of two origins the one set earlier wins (then the earlier jump): the
// merge is a join, so every order of merging reaches the same state. Only the
// warned-about value is kept, so a loop that never sets it converges as fast
// as without origins.
struct Origin {
    bool present = false;
    uint32_t line = 0;
    ByteRange range;
    uint32_t via_line = 0;
    ByteRange via_range;
    friend bool operator==(const Origin&, const Origin&) = default;
    bool before(const Origin& o) const;
};

template <class E, E Tracked>
struct ModeOrigin {
    Origin origin;
    // The mode is set to `v` by the block at `line` (the word at `range`).
    void set(E v, uint32_t line, ByteRange range) {
        origin = v == Tracked ? Origin{true, line, range, 0, {}} : Origin{};
    }
    void clear() { origin = {}; }
    // The state flows along a jump (the block at `line`, its jump at `range`).
    void jumped(uint32_t line, ByteRange range) {
        if (!origin.present) return;
        origin.via_line = line;
        origin.via_range = range;
    }
    void merge(const ModeOrigin& x) {
        if (x.origin.present && (!origin.present || x.origin.before(origin))) origin = x.origin;
    }
    // Where the mode was set on some path, or nullptr: on no path known to reach here.
    const Origin* find() const { return origin.present ? &origin : nullptr; }
    friend bool operator==(const ModeOrigin&, const ModeOrigin&) = default;
};

enum class Plane : uint8_t { G17, G18, G19 };
enum class CycleReturn : uint8_t { Initial, R };  // G98 / G99

// Axis letters of a plane: first and second positioning axes, cycle axis.
struct PlaneAxes {
    char first, second, cycle;
};
// Inline: asked of nearly every block the walk visits.
inline PlaneAxes plane_axes(Plane p) {
    switch (p) {
        case Plane::G18: return {'Z', 'X', 'Y'};
        case Plane::G19: return {'Y', 'Z', 'X'};
        default: return {'X', 'Y', 'Z'};
    }
}
const char* plane_name(Plane p);  // "G17"
inline int plane_number(Plane p) { return p == Plane::G17 ? 17 : p == Plane::G18 ? 18 : 19; }  // 17, 18, 19

// An active fixed cycle (G73..G89, G77, G78, G186, ... or a registered G-code
// macro cycle such as G114): its code and the values commanded so far.
struct ActiveCycle {
    int code = 0;                  // 81, 84, 114, ...
    std::string macro;             // "OG84L" when the cycle is a G-code macro, else empty
    uint32_t start_line = 0;       // block that started it (0: differs between paths, or a subprogram did)
    ByteRange start_range;         // the G word that started it (empty: differs between paths, or not
                                   // known; the called name when a subprogram started it and left it modal)
    // The G word that commanded it last (a start, or the same code again; the
    // called name as above). Every path that reaches a commanding block agrees
    // on it there, so it is known where the start is not: a cycle commanded
    // while the paths disagree on the modal cycle (a subprogram's entry, a
    // join of loops) may start there or carry on from an earlier block.
    ByteRange command_range;
    Val<double> r, z;              // R and Z as commanded (meaning depends on G90/G91)
    Val<double> initial;           // cycle-axis position when the cycle was commanded
    // The other addresses commanded since the cycle started (Q, K, J, P, I, L,
    // FA, ...; not the axes, R or G/M/N), with their values when known. They are
    // modal within the cycle. `words_known` is false when paths that reach a
    // block disagree on which addresses were given: then absence proves nothing.
    // Shared between the copies of the state (it is copied at every block
    // while the cycle is modal), copied when one of them changes.
    SharedValue<std::map<std::string, Val<double>>> words;
    bool words_known = true;
    std::string via;  // "O100" when a user subprogram started it and left it modal; else empty
    friend bool operator==(const ActiveCycle&, const ActiveCycle&) = default;

    bool given(const std::string& address) const { return words.get().count(address) > 0; }
    // Known to be absent: not commanded on any path since the cycle started.
    bool known_absent(const std::string& address) const { return words_known && !words.get().count(address); }
};

// A fixed cycle that was started and that no G80 (or cancel macro) has ended
// since. A G0/G1/G2/G3 leaves open whether the cycle is still modal (`cycle`
// unknown), but not this: the manual asks for G80 in any case.
struct OpenCycle {
    int code = 0;
    std::string macro;
    ByteRange start;  // the G word that started it
    std::string via;  // as ActiveCycle::via
    friend bool operator==(const OpenCycle&, const OpenCycle&) = default;
};

// The arguments of a MODIN line, as the modal state carries them.
struct ModinArgs {
    // Argument name -> known numeric value (absent: not given or value unknown).
    std::map<std::string, double> values;
    std::vector<std::string> given;  // every argument name given on the MODIN line
    friend bool operator==(const ModinArgs&, const ModinArgs&) = default;
};

// The macro of an open MODIN, with its arguments as commanded.
struct ActiveModin {
    std::string macro;  // "OG87C"
    uint32_t line = 0;  // the MODIN block
    std::string via;  // "O100" when a user subprogram opened it and left it open; else empty

    // The state is copied at every block while the MODIN stays open: the
    // arguments are shared between the copies, and copied only when one
    // of them changes (args_to_edit).
    const std::map<std::string, double>& values() const { return args().values; }
    const std::vector<std::string>& given() const { return args().given; }
    const ModinArgs& args() const { return args_.get(); }
    // The arguments as shared between the copies of the state: the same
    // pointer means the same arguments (nullptr: none given).
    std::shared_ptr<const ModinArgs> shared_args() const { return args_.shared(); }
    ModinArgs& args_to_edit() { return args_.edit(); }
    friend bool operator==(const ActiveModin&, const ActiveModin&) = default;

private:
    SharedValue<ModinArgs> args_;
};

struct ModalState {
    // The state every program of the file starts with is in `initial_state`
    // (analyzer.h); a default-constructed state has every field unknown.
    Val<Plane> plane;
    Val<Distance> distance;
    ModeOrigin<Distance, Distance::Incremental> g91_from;  // where G91 was set (for "may" findings)
    Val<Units> units;
    ModeOrigin<Units, Units::Inch> g20_from;                 // where G20 was set (for "may" findings)
    Val<int> motion;  // 0, 1, 2, 3 or 60 (G60 is in the interpolation group on OSP)
    ModeOrigin<bool, true> g60_from;  // where G60 was set (set(false): G0..G3) (for "may" findings)
    ModeOrigin<bool, true> plane_from;  // where a plane other than G17 was set (set(false): G17)
    Val<double> work_offset;             // G15 H
    Val<bool> length_offset;             // G56 active (true) / G53 cancelled (false)
    Val<double> length_offset_h;         // H of G56
    Val<int> cutter_comp;                // 40, 41, 42
    Val<double> cutter_comp_d;           // D
    Val<double> g71_level;               // G71 Z..
    Val<int> return_level;               // 52, 53, 54; 0 = none commanded yet (G98/G99 decide)
    Val<std::optional<ActiveCycle>> cycle;    // known none / known cycle / unknown
    Val<std::optional<OpenCycle>> uncancelled;  // known none / a cycle no G80 ended / unknown
    ModeOrigin<bool, true> cycle_from;          // where the cycle in `uncancelled` was started (set(false): G80)
    Val<CycleReturn> cycle_return;            // G98 / G99
    Val<std::optional<ActiveModin>> modin;    // known none / known MODIN / unknown
    ModeOrigin<bool, true> modin_from;        // where the MODIN was opened (set(false): MODOUT)
    Val<int> spindle;                    // 3, 4, 5 (M843 counts as 3, M845 as 5)
    // Line of the G80/M204 that stopped the spindle by ending a G114 (OG84L)
    // mode; 0 when the spindle state comes from an explicit M code.
    Val<uint32_t> spindle_stopped_by;
    Val<double> spindle_speed;           // S
    Val<bool> speed_commanded;           // an S has been commanded in this program
    Val<bool> sync_tap;                  // M843 (synchronised tapping mode) until M845
    Val<bool> coolant;                   // M7/M8/M12 on, M9 off
    Val<double> feed;                    // F
    Val<bool> feed_commanded;            // an F has been commanded in this program (or a macro's PF)
    Val<bool> overrides_disabled;        // after G114 until M204 (G80 leaves them off)
    Val<double> x, y, z;                 // tool-tip position in program coordinates
    // Variables with known constant values ("VC12", "PX", ...). A name that is
    // absent has an unknown value.
    std::map<std::string, double> vars;

    // The user subprogram whose summary (semantics/summary.h) set G90/G91, the
    // plane or the units last, while no block has set one of them since
    // (nullptr otherwise): the note a rule gives for a mode set out of sight.
    const SubprogramSummary* modes_from = nullptr;

    // One-shot commands of a block (NCYL, NOEX, G100). They describe the block
    // whose `after` state this is and are false in every `before` state (the
    // driver clears them before the state flows on).
    bool ncyl = false;
    bool noex = false;
    bool g100 = false;
    void clear_one_shots() { ncyl = noex = g100 = false; }

    // Fields that differ become unknown. The fixed-cycle slot merges field by
    // field when both sides have the same cycle (same code and macro), so that
    // "a G81 is modal" stays known when the paths disagree only on its R or Z;
    // so does a MODIN opened by the same block, keeping the argument values
    // both sides agree on.
    void merge(const ModalState& o);
    // The merge of a state that flows along a jump: the GOTO, IF, WHILE or
    // END of the block at `line` (`range`: its flow statements). The origins
    // that `o` brings are marked as having come through it.
    void merge_jump(const ModalState& o, uint32_t line, ByteRange range);
    // This state flows along such a jump.
    void jumped(uint32_t line, ByteRange range) {
        each_origin([&](auto& o) { o.jumped(line, range); });
    }
    // Calls `f` on every origin field.
    template <class F>
    void each_origin(F&& f) {
        f(g91_from);
        f(g20_from);
        f(g60_from);
        f(plane_from);
        f(cycle_from);
        f(modin_from);
    }
    // Calls `f` on every byte range the state holds (the origins, where the
    // fixed cycle started); stops at the first for which it returns false,
    // and returns whether there was none.
    template <class F>
    bool each_range(F&& f) {
        bool ok = true;
        each_origin([&](auto& o) { ok = ok && f(o.origin.range) && f(o.origin.via_range); });
        if (ok && cycle.value) ok = f(cycle.value->start_range);
        if (ok && uncancelled.value) ok = f(uncancelled.value->start);
        return ok;
    }
    friend bool operator==(const ModalState&, const ModalState&) = default;

    Val<double> axis(char a) const {
        switch (a) {
            case 'X': return x;
            case 'Y': return y;
            case 'Z': return z;
            default: return {};
        }
    }
    Val<double>* axis_ref(char a) {
        switch (a) {
            case 'X': return &x;
            case 'Y': return &y;
            case 'Z': return &z;
            default: return nullptr;
        }
    }
};

std::string describe_state(const ModalState& s);  // one line for `osplint trace`

// The fixed cycle modal in a state when that is known; nullptr when no cycle
// is modal or when it is not known whether one is.
inline const ActiveCycle* active_cycle(const ModalState& s) {
    return s.cycle.known && s.cycle.value ? &*s.cycle.value : nullptr;
}
// Whether block `b` starts the cycle `c` modal after it: Here; Earlier (it
// carries on a cycle started before it, or does not command one); or
// Unknown: it commands the cycle while the paths that reach it disagree on
// which cycle is modal (a subprogram's first cycle, a loop head), so it
// starts one on some paths and carries one on on others.
enum class CycleStart : uint8_t { Here, Earlier, Unknown };
inline CycleStart cycle_start(const ActiveCycle& c, const Block& b) {
    if (c.start_line) return c.start_line == b.line ? CycleStart::Here : CycleStart::Earlier;
    const bool commanded_here = c.via.empty() && !c.command_range.empty() &&
                                b.range.begin <= c.command_range.begin && c.command_range.end <= b.range.end;
    return commanded_here ? CycleStart::Unknown : CycleStart::Earlier;
}
// Known: no fixed cycle is modal.
inline bool no_cycle(const ModalState& s) { return s.cycle.known && !s.cycle.value; }
inline const ActiveModin* active_modin(const ModalState& s) {
    return s.modin.known && s.modin.value ? &*s.modin.value : nullptr;
}
// Whether a word is an operand of a coordinate-calculation statement of its
// block (`BHC X.. Y.. I.. J.. K..`, `RSTRT R12`): a pattern parameter, not an
// address of the block itself (not a position, not the cycle's R).
inline bool is_coord_calc_operand(const Block& b, const Word& w) {
    for (const auto& st : b.statements)
        if (st.kind == StmtKind::CoordCalc && w.range.begin >= st.range.begin && w.range.begin < st.range.end)
            return true;
    return false;
}
// The first word with this address that is not a coordinate-calculation operand.
inline const Word* find_address(const Block& b, std::string_view address) {
    for (const auto& w : b.words)
        if (w.address == address && !is_coord_calc_operand(b, w)) return &w;
    return nullptr;
}

// The cycle axis of the plane in effect, or 0 when the plane is unknown.
inline char cycle_axis(const ModalState& s) { return s.plane.known ? plane_axes(s.plane.value).cycle : 0; }

}  // namespace osplint
