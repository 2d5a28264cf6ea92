// The transfer function (see transfer.h): what one block does to the modal
// state. apply_block takes the block in steps, one per concern: the G codes
// and the modes they set, the modal words (H, D, S, F), the M codes, the
// fixed-cycle slot, the tool-tip position, the statements and macro runs, the
// assignments. Every value of the block is read in the state before it.
#include "semantics/transfer.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstring>
#include <span>

#include <fmt/format.h>

#include "catalog/catalog.h"
#include "semantics/eval.h"
#include "semantics/motion.h"
#include "semantics/motion_internal.h"
#include "semantics/summary.h"
#include "semantics/transfer_internal.h"

namespace osplint {

using transfer_detail::has_axis_word;
using transfer_detail::has_coord_calc;
using transfer_detail::is_axis_address;

std::optional<double> word_value(const Block& b, const Word& w, const ModalState& s) {
    if (w.number) return w.number;
    if (w.value != kNoExpr) return evaluate(b, w.value, s);
    return std::nullopt;
}

namespace {

// A fixed cycle of the catalog, or one of the synchronized tapping cycles.
bool is_fixed_cycle_code(const Catalog& catalog, int g) {
    if (catalog.find_cycle(g)) return true;
    return g == 273 || g == 274 || g == 283 || g == 284;
}

// A G-code macro that behaves as a fixed cycle until its cancel (OG84L).
bool is_cycle_macro(const MacroSpec& spec) {
    return spec.has_form(MacroForm::GCode) && !spec.cancel.empty();
}

// The G or M codes of a block, in the written order: a block writes a few,
// kept in place (apply_block runs for every block); more go to the heap.
class CodeList {
public:
    void push_back(int c) {
        if (heap_.empty() && n_ < in_place_.size()) {
            in_place_[n_++] = c;
            return;
        }
        if (heap_.empty()) heap_.assign(in_place_.begin(), in_place_.begin() + n_);
        heap_.push_back(c);
    }
    const int* begin() const { return heap_.empty() ? in_place_.data() : heap_.data(); }
    const int* end() const { return begin() + size(); }
    size_t size() const { return heap_.empty() ? n_ : heap_.size(); }
    bool empty() const { return size() == 0; }
    // The list sorted and de-duplicated, for `has`.
    CodeList as_set() const {
        CodeList out = *this;
        int* first = out.heap_.empty() ? out.in_place_.data() : out.heap_.data();
        int* last = first + out.size();
        std::sort(first, last);
        const size_t kept = static_cast<size_t>(std::unique(first, last) - first);
        if (out.heap_.empty()) out.n_ = static_cast<uint8_t>(kept);
        else out.heap_.resize(kept);
        return out;
    }

private:
    std::array<int, 8> in_place_{};
    uint8_t n_ = 0;
    std::vector<int> heap_;  // all of them, once there are more than in_place_ holds
};

// The G codes of a block as a set, for `has`: codes below 128 (all that
// apply_block asks about) as bits, others in a sorted list.
class CodeSet {
public:
    CodeSet() = default;
    explicit CodeSet(const CodeList& codes) {
        for (int c : codes) {
            if (c >= 0 && c < 128) bits_[c >> 6] |= uint64_t{1} << (c & 63);
            else others_.push_back(c);
        }
        if (!others_.empty()) others_ = others_.as_set();
    }
    bool has(int x) const {
        if (x >= 0 && x < 128) return (bits_[x >> 6] >> (x & 63)) & 1u;
        return std::find(others_.begin(), others_.end(), x) != others_.end();
    }

private:
    std::array<uint64_t, 2> bits_{};
    CodeList others_;
};

inline bool has(const CodeSet& set, int x) { return set.has(x); }

bool is_call_block(const Block& b) {
    return b.statement(StmtKind::Call) || b.statement(StmtKind::Modin);
}

}  // namespace

ModalState initial_state(const Config& config, bool subprogram) {
    ModalState s;
    if (subprogram) {
        // A subprogram inherits whatever its caller had: nothing is known.
        return s;
    }
    s.plane = Val<Plane>::of(config.plane);
    s.units = Val<Units>::of(config.units);
    s.distance = Val<Distance>::of(config.distance);
    s.g91_from.set(config.distance, 0, {});
    s.g20_from.set(config.units, 0, {});
    s.plane_from.set(config.plane != Plane::G17, 0, {});
    s.cycle = Val<std::optional<ActiveCycle>>::of(std::nullopt);
    s.uncancelled = Val<std::optional<OpenCycle>>::of(std::nullopt);
    s.modin = Val<std::optional<ActiveModin>>::of(std::nullopt);
    s.overrides_disabled = Val<bool>::of(false);
    s.return_level = Val<int>::of(0);
    s.spindle_stopped_by = Val<uint32_t>::of(0);
    s.speed_commanded = Val<bool>::of(false);
    s.feed_commanded = Val<bool>::of(false);
    s.sync_tap = Val<bool>::of(false);
    return s;
}

namespace {

// G or M codes of a block, literal or evaluated in the state before it.
// `unknown` is set when a G/M word has a value that cannot be known.
CodeList block_codes(const Block& b, char address, const ModalState& before, bool& unknown) {
    CodeList out;
    for (const auto& w : b.words) {
        if (w.address.size() != 1 || w.address[0] != address) continue;
        if (auto c = code_of(w)) {
            out.push_back(*c);
            continue;
        }
        auto v = word_value(b, w, before);
        if (v && *v >= 0 && *v <= 100000 && *v == std::floor(*v))
            out.push_back(static_cast<int>(*v));
        else
            unknown = true;
    }
    return out;
}

Val<double> known_or_unknown(const std::optional<double>& v) { return v ? Val<double>::of(*v) : Val<double>{}; }

// Addresses that are not recorded among a cycle's modal words.
bool cycle_word_ignored(std::string_view a) {
    return a == "G" || a == "M" || a == "N" || a == "O" || a == "R" || is_axis_address(a);
}

// Records the addresses of a block that belong to the active cycle.
void update_cycle(ActiveCycle& c, const Block& b, const ModalState& before, char cyc_axis) {
    if (const Word* r = find_address(b, "R")) c.r = known_or_unknown(word_value(b, *r, before));
    if (cyc_axis) {
        if (const Word* z = find_address(b, std::string(1, cyc_axis)))
            c.z = known_or_unknown(word_value(b, *z, before));
    } else {
        // Which word is the depth is not known without the plane.
        for (const auto& w : b.words)
            if ((w.address == "X" || w.address == "Y" || w.address == "Z") && !is_coord_calc_operand(b, w))
                c.z = Val<double>{};
    }
    for (const auto& w : b.words) {
        if (cycle_word_ignored(w.address) || is_coord_calc_operand(b, w)) continue;
        const Val<double> v = known_or_unknown(word_value(b, w, before));
        const auto& words = c.words.get();
        if (const auto it = words.find(w.address); it != words.end() && it->second == v) continue;
        c.words.edit()[w.address] = v;
    }
}

void all_positions_unknown(ModalState& s) { s.x = s.y = s.z = Val<double>{}; }

// What a subprogram or macro run does to the state, beyond the tool position.
void apply_subprogram_run(const MacroCall* call, const MacroSpec* spec, const ModalState& before, ModalState& s) {
    s.feed = Val<double>{};
    const bool shop_subprogram = spec && spec->kind == SpecKind::Macro && spec->m52 == M52Mode::IgnoredUsePM52;
    if (shop_subprogram) {
        // The shop's cycle macros work "like the equivalent fixed cycle" (back
        // counterboring manual, common rule (1)) and leave the interpolation mode
        // as it was: the manuals' warning about G60 with NCYL during them (common
        // rule (9)) presupposes that G60 stays modal across their runs.
        // Seeds 000-002: the macro starts the spindle itself and keeps a running one.
        if (!(before.spindle.is(3) || before.spindle.is(4))) s.spindle = Val<int>{};
        s.spindle_stopped_by = Val<uint32_t>::of(0);
        const MacroArg* ps = call ? call->arg("PS") : nullptr;
        if (ps) {
            s.spindle_speed = ps->value;
            s.speed_commanded = Val<bool>::of(true);
        }
        // The macro feeds at PF, which stays the modal F after it.
        if (call && call->arg("PF")) s.feed_commanded = Val<bool>::of(true);
        return;
    }
    // Anything else may leave the interpolation mode, the spindle, the coolant
    // and the synchronised-tapping mode changed; a user subprogram the engine
    // analysed sets what its summary says.
    const Val<int> motion = s.motion;
    s.motion = Val<int>{};
    if (call && call->summary) {
        s.motion = motion;  // apply_block applies the summary at the end
    } else {
        s.g60_from.clear();
    }
    s.spindle = Val<int>{};
    s.spindle_stopped_by = Val<uint32_t>{};
    s.spindle_speed = Val<double>{};
    s.speed_commanded = Val<bool>{};
    s.feed_commanded = Val<bool>{};
    s.sync_tap = Val<bool>{};
    s.coolant = Val<bool>{};
}

void erase_reserved_common(ModalState& s) {
    // VC120 ... VC128 sort together (with longer names such as VC1200 between them).
    if (s.vars.empty()) return;
    const std::string first = "VC120", last = "VC128";
    for (auto it = s.vars.lower_bound(first); it != s.vars.end() && it->first <= last;)
        it = it->first.size() == first.size() ? s.vars.erase(it) : std::next(it);
}

void erase_all_common(ModalState& s) {
    for (auto it = s.vars.begin(); it != s.vars.end();)
        it = common_variable_number(it->first) ? s.vars.erase(it) : std::next(it);
}

// What the steps of apply_block read about a block: its G and M codes and the
// macro it runs, worked out once, in the state before the block.
struct BlockFacts {
    const Block& b;
    const MacroCall* call;
    const ModalState& before;
    bool unknown_g = false, unknown_m = false;  // a G/M word whose value cannot be known
    CodeList g, m;                              // in the written order
    CodeSet gs;                                 // `g` as a set, for `has`
    bool is_call;        // CALL or MODIN statement on the block
    bool g80;
    bool interpolation;  // G0/G1/G2/G3
    // The macro this block runs, if any, and whether it is the declaration of
    // a G-code macro cycle (G114 -> OG84L) or the M-code macro that cancels one.
    bool runs_program;
    bool cycle_declaration;
    bool cycle_cancel_macro;

    BlockFacts(const Block& block, const MacroCall* c, const ModalState& st) : b(block), call(c), before(st) {
        g = block_codes(b, 'G', before, unknown_g);
        m = block_codes(b, 'M', before, unknown_m);
        gs = CodeSet(g);
        is_call = is_call_block(b);
        g80 = has(gs, 80);
        interpolation = has(gs, 0) || has(gs, 1) || has(gs, 2) || has(gs, 3);
        runs_program = call && (call->kind == CallKind::Call || call->kind == CallKind::ModinPositioning ||
                                call->kind == CallKind::GCode || call->kind == CallKind::MCode);
        cycle_declaration = call && call->kind == CallKind::GCode && call->spec && is_cycle_macro(*call->spec);
        cycle_cancel_macro = call && call->kind == CallKind::MCode && call->spec && !call->spec->cancels.empty();
    }
};

// G80: the fixed cycle ends.
void end_fixed_cycle(const Block& b, ModalState& s) {
    if (!s.cycle.known) {
        // Perhaps a G114 mode: the spindle may have stopped.
        s.spindle = Val<int>{};
        s.spindle_stopped_by = Val<uint32_t>{};
    } else if (s.cycle.value && !s.cycle.value->macro.empty()) {
        // Ending G114 (OG84L): "the spindle stops too!" (tap cycle manual).
        s.spindle = Val<int>::of(5);
        s.spindle_stopped_by = Val<uint32_t>::of(b.line);
    }
    s.cycle = Val<std::optional<ActiveCycle>>::of(std::nullopt);
    s.uncancelled = Val<std::optional<OpenCycle>>::of(std::nullopt);
    s.cycle_from.clear();
    // Whether G80 resets M52/M53/M54 is not documented: a return level
    // stays known only when none was commanded.
    if (!s.return_level.is(0)) s.return_level = Val<int>{};
}

// The last G word of the block that commands `code`, the one whose mode
// stays (an empty range when the code comes from an expression).
ByteRange g_word_range(const Block& b, int code) {
    ByteRange r;
    for (const auto& w : b.words)
        if (w.address == "G" && w.number && *w.number == code) r = w.range;
    return r;
}

// The G codes and the modes they set. Returns whether the block leaves the
// tool-tip position unknown (a new coordinate system, a home return, ...).
bool apply_g_codes(const BlockFacts& f, ModalState& s) {
    bool positions_unknown = false;
    for (int c : f.g) {
        if ((c >= 17 && c <= 21) || c == 60 || c == 90 || c == 91) s.modes_from = nullptr;  // set here, in sight
        switch (c) {
            case 0: case 1: case 2: case 3: case 60:
                s.motion = Val<int>::of(c);
                s.g60_from.set(c == 60, f.b.line, g_word_range(f.b, c));
                break;
            case 17: case 18: case 19:
                s.plane = Val<Plane>::of(c == 17 ? Plane::G17 : c == 18 ? Plane::G18 : Plane::G19);
                s.plane_from.set(c != 17, f.b.line, g_word_range(f.b, c));
                break;
            case 20: case 21: {
                const Units u = c == 20 ? Units::Inch : Units::Mm;
                s.units = Val<Units>::of(u);
                s.g20_from.set(u, f.b.line, g_word_range(f.b, c));
                break;
            }
            case 90: case 91: {
                const Distance d = c == 90 ? Distance::Absolute : Distance::Incremental;
                s.distance = Val<Distance>::of(d);
                s.g91_from.set(d, f.b.line, g_word_range(f.b, c));
                break;
            }
            case 98: s.cycle_return = Val<CycleReturn>::of(CycleReturn::Initial); break;
            case 99: s.cycle_return = Val<CycleReturn>::of(CycleReturn::R); break;
            case 40: case 41: case 42: s.cutter_comp = Val<int>::of(c); break;
            case 53: s.length_offset = Val<bool>::of(false); break;
            case 56: s.length_offset = Val<bool>::of(true); break;
            case 15:
                // A new work coordinate system moves the program origin.
                positions_unknown = true;
                s.work_offset = Val<double>{};
                break;
            case 16:  // one-shot coordinate system: the move's program coordinates are unknown
            case 10: case 11:  // coordinate shift / rotation (cancel)
            case 30:  // home position
                positions_unknown = true;
                break;
            case 80: end_fixed_cycle(f.b, s); break;
            default: break;
        }
    }
    if (f.unknown_g) {
        // A G code whose value is not known may have changed any G-code mode.
        s.modes_from = nullptr;
        s.plane = Val<Plane>{};
        s.distance = Val<Distance>{};
        s.g91_from.clear();
        s.units = Val<Units>{};
        s.g20_from.clear();
        s.g60_from.clear();
        s.plane_from.clear();
        s.motion = Val<int>{};
        s.cycle_return = Val<CycleReturn>{};
        s.cutter_comp = Val<int>{};
        s.length_offset = Val<bool>{};
        s.cycle = Val<std::optional<ActiveCycle>>{};
        s.uncancelled = Val<std::optional<OpenCycle>>{};
        s.cycle_from.clear();
        positions_unknown = true;
    }
    if (has(f.gs, 20) && f.b.find("HP")) positions_unknown = true;  // G20 HP=n: home position (Multus)
    return positions_unknown;
}

// The words that set modal values: H (G15 work offset, G56 length offset),
// D (cutter compensation), S, F, and the Z of G71 (the M53 return level).
void apply_modal_words(const BlockFacts& f, ModalState& s) {
    const Block& b = f.b;
    for (const auto& w : b.words) {
        if (w.address.size() != 1) continue;
        auto v = word_value(b, w, f.before);
        switch (w.address[0]) {
            case 'H':
                if (has(f.gs, 15)) s.work_offset = known_or_unknown(v);
                if (has(f.gs, 56)) s.length_offset_h = known_or_unknown(v);
                break;
            case 'D':
                if (has(f.gs, 41) || has(f.gs, 42)) s.cutter_comp_d = known_or_unknown(v);
                break;
            case 'S':
                if (!f.is_call) {
                    s.spindle_speed = known_or_unknown(v);
                    s.speed_commanded = Val<bool>::of(true);
                }
                break;
            case 'F':
                if (!f.is_call && !has(f.gs, 4)) {
                    s.feed = known_or_unknown(v);
                    s.feed_commanded = Val<bool>::of(true);
                }
                break;
            case 'Z':
                if (has(f.gs, 71)) s.g71_level = known_or_unknown(v);
                break;
            default: break;
        }
    }
}

// The M codes: spindle, coolant, return level, synchronised tapping.
void apply_m_codes(const BlockFacts& f, ModalState& s) {
    for (int c : f.m) {
        switch (c) {
            case 3: case 4: case 5:
                s.spindle = Val<int>::of(c);
                s.spindle_stopped_by = Val<uint32_t>::of(0);
                break;
            case 0: case 1: case 6:
                // Program stop / optional stop / tool change: what the spindle and
                // the coolant do here depends on the machine.
                s.spindle = Val<int>{};
                s.spindle_stopped_by = Val<uint32_t>::of(0);
                s.coolant = Val<bool>{};
                break;
            case 19:  // spindle orientation
                s.spindle = Val<int>{};
                s.spindle_stopped_by = Val<uint32_t>::of(0);
                break;
            case 7: case 8: case 12: s.coolant = Val<bool>::of(true); break;
            case 9: s.coolant = Val<bool>::of(false); break;
            case 52: case 53: case 54: s.return_level = Val<int>::of(c); break;
            case 843:
                s.spindle = Val<int>::of(3);
                s.spindle_stopped_by = Val<uint32_t>::of(0);
                s.sync_tap = Val<bool>::of(true);
                break;
            case 845:
                s.spindle = Val<int>::of(5);
                s.spindle_stopped_by = Val<uint32_t>::of(0);
                s.sync_tap = Val<bool>::of(false);
                break;
            default: break;
        }
    }
    if (f.unknown_m) {
        s.spindle = Val<int>{};
        s.spindle_stopped_by = Val<uint32_t>{};
        s.coolant = Val<bool>{};
        s.return_level = Val<int>{};
        s.sync_tap = Val<bool>{};
    }
}

// The cycle a block commands: the code of its fixed-cycle G word (or of the
// G-code macro it declares) and that word's range; code 0 when none.
struct CycleWord {
    int code = 0;
    ByteRange range;
};

CycleWord commanded_cycle(const BlockFacts& f, const Catalog& catalog, bool& positions_unknown) {
    const Block& b = f.b;
    CycleWord cw;
    for (const auto& w : b.words) {
        if (w.address != "G") continue;
        auto c = code_of(w);
        if (c && is_fixed_cycle_code(catalog, *c)) {
            cw.code = *c;
            cw.range = w.range;
        }
    }
    if (cw.code >= 85 && cw.code <= 89 && b.find("N")) {
        // `G85 N0207 D7 ...` names a contour: a lathe LAP cycle, not a fixed
        // cycle. It machines the contour and ends where it ends.
        cw.code = 0;
        positions_unknown = true;
    }
    if (f.cycle_declaration) {
        for (const auto& w : b.words)
            if (w.range == f.call->name_range)
                if (auto c = code_of(w)) {
                    cw.code = *c;
                    cw.range = w.range;
                }
    }
    return cw;
}

// The fixed-cycle slot: fixed cycles and the G-code macro cycle (OG84L via
// G114), started, continued with new modal words, or ended by the M-code
// macro that cancels it. Returns the code of the cycle the block commands (0: none).
int apply_cycle_slot(const BlockFacts& f, const Catalog& catalog, ModalState& s, bool& positions_unknown) {
    const Block& b = f.b;
    const ModalState& before = f.before;
    const CycleWord cw = commanded_cycle(f, catalog, positions_unknown);
    std::string cycle_macro;
    if (f.cycle_declaration) {
        cycle_macro = f.call->spec->name;
        s.overrides_disabled = Val<bool>::of(true);
    }
    if (f.cycle_cancel_macro) {
        s.cycle = Val<std::optional<ActiveCycle>>::of(std::nullopt);
        s.uncancelled = Val<std::optional<OpenCycle>>::of(std::nullopt);
        s.cycle_from.clear();
        s.overrides_disabled = Val<bool>::of(false);
        s.spindle = Val<int>::of(5);  // "the spindle stops too" (tap cycle manual; M204 as well)
        s.spindle_stopped_by = Val<uint32_t>::of(b.line);
        if (!s.return_level.is(0)) s.return_level = Val<int>{};
    }
    const char cyc_axis = s.plane.known ? plane_axes(s.plane.value).cycle : 0;
    if (cw.code) {
        ActiveCycle c;
        // Whether the block carries on the cycle already modal: known unless
        // the paths that reach it disagree on the modal cycle. Then the block
        // may start a cycle or carry one on, and what the two have in common
        // is kept: the code and what the block itself commands. Taking it as
        // a start would claim, on the paths where the cycle carries on, a
        // start and an initial point that they do not have.
        const bool carry_known = f.g80 || before.cycle.known;
        const bool same = !f.g80 && before.cycle.known && before.cycle.value &&
                          before.cycle.value->code == cw.code && before.cycle.value->macro == cycle_macro;
        if (same) {
            c = *before.cycle.value;  // the same cycle commanded again: the modal values carry over
        } else {
            c.code = cw.code;
            c.macro = cycle_macro;
            if (carry_known) {
                c.start_line = b.line;
                c.start_range = cw.range;
                if (cyc_axis) c.initial = before.axis(cyc_axis);
            } else {
                c.words_known = false;  // an earlier block may have given the others
            }
        }
        c.command_range = cw.range;
        if (carry_known) {
            if (!same || !s.cycle_from.find()) s.cycle_from.set(true, b.line, cw.range);
        } else {
            ModeOrigin<bool, true> here;  // a start here, or the earlier one carried on
            here.set(true, b.line, cw.range);
            s.cycle_from.merge(here);
        }
        update_cycle(c, b, before, cyc_axis);
        if (carry_known)
            s.uncancelled = Val<std::optional<OpenCycle>>::of(OpenCycle{c.code, c.macro, c.start_range, c.via});
        else
            s.uncancelled = Val<std::optional<OpenCycle>>{};  // started where is not known
        s.cycle = Val<std::optional<ActiveCycle>>::of(std::move(c));
    } else if (s.cycle.known && s.cycle.value && !f.g80) {
        if (f.interpolation) {
            // Whether G0/G1/G2/G3 ends a fixed cycle on this control is not
            // documented: the cycle may or may not still be modal.
            s.cycle = Val<std::optional<ActiveCycle>>{};
        } else {
            // In place: the values are read in `before`, a copy of its own.
            update_cycle(*s.cycle.value, b, before, cyc_axis);
        }
    }
    return cw.code;
}

// Where the hole of the active cycle leaves the tool on the cycle axis: the
// return level of M53 (the G71 level) / M54 (R) / G98 (initial point) / G99
// (R), unknown when it cannot be told (M52: the upper limit).
Val<double> hole_return_position(const ModalState& before, const ModalState& s, char cyc_axis) {
    const ActiveCycle& c = *s.cycle.value;
    const Val<double> i_point = before.axis(cyc_axis);
    Val<double> r_abs;
    if (s.distance.is(Distance::Absolute))
        r_abs = c.r;
    else if (s.distance.is(Distance::Incremental) && i_point.known && c.r.known)
        r_abs = Val<double>::of(i_point.value + c.r.value);
    Val<double> ret;
    if (s.return_level.known) {
        switch (s.return_level.value) {
            case 53:
                if (s.distance.is(Distance::Absolute)) ret = s.g71_level;
                break;
            case 54: ret = r_abs; break;
            case 0:
                if (s.cycle_return.is(CycleReturn::Initial)) ret = c.initial;
                else if (s.cycle_return.is(CycleReturn::R)) ret = r_abs;
                break;
            default: break;  // M52: the upper limit
        }
    }
    return ret;
}

// Whether a cycle is modal, and the cycle axis, as the tool-tip step sees them.
struct CycleContext {
    bool in_cycle;     // a cycle is known to be modal after the block
    bool maybe_cycle;  // whether a cycle is modal is not known
    char axis;         // the cycle axis of the plane (0: plane not known)
};

// The axis words of a block that moves the tool (no coordinate setting, no
// G71/G4): each X/Y/Z in G90/G91, then what a hole pattern or a hole of the
// cycle does to the positions.
void move_tool(const BlockFacts& f, const CycleContext& cc, int cycle_code, ModalState& s) {
    const Block& b = f.b;
    const ModalState& before = f.before;
    const Distance* dist = s.distance.known ? &s.distance.value : nullptr;
    for (const auto& w : b.words) {
        if (w.address.size() != 1) continue;
        Val<double>* ax = s.axis_ref(w.address[0]);
        if (!ax || is_coord_calc_operand(b, w)) continue;  // pattern operands: handled below
        if (cc.in_cycle && cc.axis && w.address[0] == cc.axis) continue;  // cycle depth, not a move
        if ((cc.maybe_cycle || cc.in_cycle) && (!cc.axis || w.address[0] == cc.axis)) {
            *ax = Val<double>{};  // perhaps a depth, perhaps a move
            continue;
        }
        auto v = word_value(b, w, before);
        if (!v || !dist || s.noex) {
            *ax = Val<double>{};
        } else if (*dist == Distance::Absolute) {
            *ax = Val<double>::of(*v);
        } else {
            Val<double> old = before.axis(w.address[0]);
            *ax = old.known ? Val<double>::of(old.value + *v) : Val<double>{};
        }
    }
    if ((has(f.gs, 56) || has(f.gs, 53)) && !b.find("Z")) s.z = Val<double>{};  // the offset changes the tip's Z
    if (has_coord_calc(b)) {
        // A hole pattern: the positioning-plane axes end at its last point.
        if (s.plane.known) {
            const PlaneAxes pa = plane_axes(s.plane.value);
            *s.axis_ref(pa.first) = Val<double>{};
            *s.axis_ref(pa.second) = Val<double>{};
        } else {
            all_positions_unknown(s);
        }
    }
    if (cc.maybe_cycle && (has_axis_word(b) || find_address(b, "R") || has_coord_calc(b))) {
        // Perhaps a hole: the cycle axis may end at a return level.
        if (cc.axis)
            *s.axis_ref(cc.axis) = Val<double>{};
        else
            all_positions_unknown(s);
    }
    if (cc.in_cycle && cc.axis) {
        // A hole is machined unless the block only positions (NCYL, G100, the
        // G114 declaration block, NOEX) or has no positioning at all.
        const bool positions = cycle_code || has_axis_word(b) || find_address(b, "R") || has_coord_calc(b);
        const bool hole = positions && !s.ncyl && !s.g100 && !s.noex && !f.cycle_declaration;
        if (hole) *s.axis_ref(cc.axis) = hole_return_position(before, s, cc.axis);
    }
}

// The tool-tip position, including where the hole of a fixed cycle leaves it.
void apply_tool_position(const BlockFacts& f, int cycle_code, bool positions_unknown, ModalState& s) {
    const Block& b = f.b;
    CycleContext cc;
    // `G80 G83 X.. Z.. R..` ends the old cycle and starts a new one, whose
    // first hole is machined in that block.
    cc.in_cycle = s.cycle.known && s.cycle.value && (!f.g80 || cycle_code != 0);
    // Whether a cycle is modal is not known: the block may machine a hole,
    // unless it commands an interpolation (then its words are a move).
    cc.maybe_cycle = !s.cycle.known && !f.g80 && !f.interpolation;
    cc.axis = s.plane.known ? plane_axes(s.plane.value).cycle : 0;
    if (f.runs_program && !f.cycle_declaration && !f.cycle_cancel_macro) {
        // A subprogram or macro moves the tool in ways this evaluator does not follow.
        positions_unknown = true;
    }
    // A MODIN line only declares the modal call: the tool does not move there.
    if (b.statement(StmtKind::Call)) positions_unknown = true;
    if (positions_unknown) {
        all_positions_unknown(s);
    } else if (has(f.gs, 92) || has(f.gs, 50) || has(f.gs, 22) || has(f.gs, 23)) {
        // Coordinate setting and the like: the named axes get values this
        // evaluator does not model.
        for (const auto& w : b.words)
            if (w.address.size() == 1)
                if (Val<double>* ax = s.axis_ref(w.address[0])) *ax = Val<double>{};
    } else if (!has(f.gs, 71) && !has(f.gs, 4)) {
        move_tool(f, cc, cycle_code, s);
    }
}

// A subprogram or macro run, and the common variables it may change.
void run_program(const MacroCall* call, const MacroSpec* spec, const ModalState& before, ModalState& s) {
    apply_subprogram_run(call, spec, before, s);
    if (!spec && !(call && call->summary)) {
        // An unknown subprogram may change any common variable (one with a
        // summary changes those the summary names).
        erase_all_common(s);
    } else if (spec && spec->has(Hazard::OverwritesVc120To128)) {
        erase_reserved_common(s);
    }
}

// The statements (MODIN, MODOUT, CALL) and the macro runs of MODIN
// positioning blocks and G/M-code macros.
void apply_statements(const BlockFacts& f, const Catalog& catalog, ModalState& s) {
    const Block& b = f.b;
    const MacroCall* call = f.call;
    for (const auto& st : b.statements) {
        switch (st.kind) {
            case StmtKind::Modin: {
                ActiveModin am;
                am.macro = st.name;
                am.line = b.line;
                if (call && call->kind == CallKind::Modin) {
                    ModinArgs& args = am.args_to_edit();
                    for (const auto& a : call->args) {
                        args.given.push_back(a.name);
                        if (a.value.known) args.values[a.name] = a.value.value;
                    }
                }
                s.modin = Val<std::optional<ActiveModin>>::of(std::move(am));
                s.modin_from.set(true, b.line, st.head_range());
                break;
            }
            case StmtKind::Modout:
                s.modin = Val<std::optional<ActiveModin>>::of(std::nullopt);
                s.modin_from.clear();
                break;
            case StmtKind::Call: {
                const MacroCall* own = call && call->kind == CallKind::Call && call->name == st.name ? call : nullptr;
                // resolve_call found the macro of this CALL already: no second search by name.
                run_program(call && call->kind == CallKind::Call ? call : nullptr,
                            own ? own->spec : catalog.find(st.name), f.before, s);
                break;
            }
            default: break;
        }
    }
    if (call && call->kind == CallKind::ModinPositioning) run_program(call, call->spec, f.before, s);
    if (call && (call->kind == CallKind::GCode || call->kind == CallKind::MCode) && !f.cycle_declaration &&
        !f.cycle_cancel_macro)
        run_program(call, call->spec, f.before, s);
}

// Assignments: variables, and plain locals (`PX=0` on a block with no G/M
// code or call).
void apply_assignments(const BlockFacts& f, ModalState& s) {
    const Block& b = f.b;
    for (const auto& a : b.assignments) {
        auto key = variable_key(b, a.target, f.before);
        if (!key) {
            // Unknown subscript: any variable of that family may change.
            const ExprNode* t = b.expr(a.target);
            std::string base = t ? t->text : std::string();
            for (auto it = s.vars.begin(); it != s.vars.end();)
                it = it->first.rfind(base, 0) == 0 ? s.vars.erase(it) : std::next(it);
            continue;
        }
        auto v = evaluate(b, a.value, f.before);
        if (v)
            s.vars[*key] = *v;
        else
            s.vars.erase(*key);
    }
    if (!f.is_call && f.g.empty() && f.m.empty() && !f.call && !f.unknown_g && !f.unknown_m) {
        for (const auto& w : b.words) {
            if (w.address.size() < 2 || !w.equals) continue;
            auto v = word_value(b, w, f.before);
            if (v)
                s.vars[w.address] = *v;
            else
                s.vars.erase(w.address);
        }
    }
}

}  // namespace

namespace {

// A CALL of a catalog macro alone on its block with `Pname=value` words
// only: what apply_block does with it depends on the state before it, the
// macro, PS and whether PF is given, and its end point (CallTransferMemo).
bool plain_catalog_call(const Block& b, const MacroCall* call) {
    if (!call || call->kind != CallKind::Call || !call->spec || call->spec->kind != SpecKind::Macro || call->summary)
        return false;
    if (b.program_name || b.sequence || b.block_delete || !b.assignments.empty() || !b.errors.empty() ||
        b.statements.size() != 1 || b.statements[0].kind != StmtKind::Call || b.statements[0].name != call->name)
        return false;
    for (const auto& w : b.words)
        if (w.address.size() < 2 || w.address[0] != 'P') return false;
    return true;
}

// The end of apply_block: the end point of a catalog macro's run, and what a
// user subprogram leaves behind.
void finish_block(const Block& b, const ModalState& before, const MacroCall* call, bool runs_program,
                  MacroEndMemo* ends, ModalState& s, bool repeat) {
    // A catalog macro's action sequence says where it leaves the cycle axis;
    // the other axes stay unknown after it.
    if (runs_program)
        if (auto end = macro_end(b, before, s, call, ends, repeat))
            if (Val<double>* ax = s.axis_ref(end->first)) *ax = Val<double>::of(end->second);
    // What a user subprogram this block calls leaves behind; the modes it sets
    // are set at the call.
    if (call && call->summary) {
        apply_summary(*call->summary, b.line, call->name_range, s);
        auto origin = [&](const auto& effect, auto& origins) {
            using K = typename std::decay_t<decltype(effect)>::Kind;
            if (effect.kind == K::Set) origins.set(effect.value, b.line, call->name_range);
            else if (effect.kind == K::Unknown) origins.clear();
        };
        origin(call->summary->distance, s.g91_from);
        origin(call->summary->units, s.g20_from);
        const ModeEffect<int>& m = call->summary->motion;
        if (m.kind == ModeEffect<int>::Kind::Set) s.g60_from.set(m.value == 60, b.line, call->name_range);
        else if (m.kind == ModeEffect<int>::Kind::Unknown) s.g60_from.clear();
    }
}

}  // namespace

void apply_block(const Block& b, const MacroCall* call, const Catalog& catalog, ModalState& s, MacroEndMemo* ends,
                 CallTransferMemo* calls) {
    if (b.kind != LineKind::Block) return;
    ModalState before = s;  // values of the block are read in the state before it
    before.clear_one_shots();
    apply_block(b, call, catalog, before, s, ends, calls);
}

void apply_block(const Block& b, const MacroCall* call, const Catalog& catalog, const ModalState& before,
                 ModalState& s, MacroEndMemo* ends, CallTransferMemo* calls, bool repeat) {
    assert(&before != &s);
    const bool fresh = calls && calls->fresh;
    if (calls) calls->fresh = false;
    if (b.kind != LineKind::Block) {
        s = before;
        return;
    }
    if (before.ncyl || before.noex || before.g100) {
        // The one-shots of the block before are not the state this block reads.
        ModalState clean = before;
        clean.clear_one_shots();
        if (calls) calls->fresh = fresh;
        apply_block(b, call, catalog, clean, s, ends, calls, repeat);
        return;
    }
    const bool plain = calls && plain_catalog_call(b, call);
    if (plain && calls->spec == call->spec) {
        // The position is not part of what the block reads but for its end point.
        CallTransferMemo& m = *calls;
        m.before.x = before.x;
        m.before.y = before.y;
        m.before.z = before.z;
        // A repeat of the call the memo last served reads what that one read.
        const MacroArg* ps = repeat && fresh ? nullptr : call->arg("PS");
        if ((repeat && fresh) ||
            (ArgSeen::of(ps) == m.ps && (call->arg("PF") != nullptr) == m.pf && m.before == before)) {
            s = m.partial;
            ++m.hits;
            m.fresh = true;
            finish_block(b, m.before, call, true, ends, s, repeat);
            return;
        }
    }
    s = before;
    const BlockFacts f(b, call, before);
    s.ncyl = b.statement(StmtKind::Ncyl) != nullptr;
    s.noex = b.statement(StmtKind::Noex) != nullptr;
    s.g100 = has(f.gs, 100);

    bool positions_unknown = apply_g_codes(f, s);
    apply_modal_words(f, s);
    apply_m_codes(f, s);
    const int cycle_code = apply_cycle_slot(f, catalog, s, positions_unknown);
    apply_tool_position(f, cycle_code, positions_unknown, s);
    apply_statements(f, catalog, s);
    apply_assignments(f, s);
    if (calls) {
        calls->spec = nullptr;
        if (plain && f.runs_program) {
            calls->spec = call->spec;
            calls->ps = ArgSeen::of(call->arg("PS"));
            calls->pf = call->arg("PF") != nullptr;
            calls->before = before;
            calls->partial = s;
            calls->fresh = true;
        }
    }
    finish_block(b, before, call, f.runs_program, ends, s, repeat);
}

bool repeat_leaves_state(const MacroSpec& spec, const ModalState& before, const CallTransferMemo& calls,
                         const MacroEndMemo& ends) {
    return calls.fresh && calls.spec == &spec && !before.ncyl && !before.noex && !before.g100 &&
           macro_end_repeats(ends, spec, before);
}

bool repeat_keeps_state(const Block& b, const MacroCall* call, const ModalState& before, const MacroEndMemo& ends) {
    if (b.kind != LineKind::Block || !before.plane.known || before.ncyl || before.noex || before.g100) return false;
    if (call && (call->kind == CallKind::Call || call->kind == CallKind::Modin || call->summary)) return false;
    // The position in the plane unknown after the block, whatever its words' values.
    const PlaneAxes pa = plane_axes(before.plane.value);
    if (before.axis(pa.first).known || before.axis(pa.second).known) return false;
    if (!motion_detail::runs_macro(b, call)) return true;
    return call && call->spec && macro_end_repeats(ends, *call->spec, before);
}

bool repeat_sets_plane(const Block& b, const MacroCall* call, const ModalState& before) {
    if (b.kind != LineKind::Block || call || !b.statements.empty() || !before.plane.known || before.ncyl ||
        before.noex || before.g100 || !before.distance.is(Distance::Absolute))
        return false;
    const PlaneAxes pa = plane_axes(before.plane.value);
    bool moves = false;
    for (const auto& w : b.words) {
        if (w.address.size() != 1) continue;
        const char a = w.address[0];
        if (a == 'G') {
            const std::optional<int> g = code_of(w);
            if (!g) return false;
            for (int c : {4, 71, 92, 50, 22, 23})
                if (*g == c) return false;
        } else if (a == pa.first || a == pa.second) {
            if (!w.number || !(before.axis(a) == Val<double>::of(*w.number))) return false;
            moves = true;
        }
    }
    return moves;
}

bool is_plain_move_block(const Block& b) {
    if (b.kind != LineKind::Block || b.program_name || b.block_delete || b.words.empty() || !b.statements.empty() ||
        !b.assignments.empty() || !b.errors.empty())
        return false;
    for (const auto& w : b.words) {
        if (w.address.size() != 1 || w.equals || !w.number) return false;
        switch (w.address[0]) {
            case 'X': case 'Y': case 'Z': case 'F': break;
            case 'G': {
                const double g = *w.number;
                if (!(g == 0 || g == 1 || g == 2 || g == 3)) return false;
                break;
            }
            default: return false;
        }
    }
    return true;
}

bool is_plain_call(const BlockView& v) {
    const MacroCall* c = v.call;
    if (!v.reachable || !c || !c->spec || c->spec->kind != SpecKind::Macro || c->summary) return false;
    const Block& b = v.block;
    if (b.kind != LineKind::Block || b.program_name || b.block_delete || b.sequence || !b.assignments.empty() ||
        !b.comments.empty() || !b.errors.empty())
        return false;
    if (c->kind == CallKind::Call || c->kind == CallKind::Modin) {
        if (b.statements.size() != 1) return false;
        for (const auto& w : b.words)
            if (w.address.size() < 2 || w.address[0] != 'P') return false;
    } else if (c->kind == CallKind::ModinPositioning) {
        // A positioning block of an open MODIN (`X56. Y10.`): axis words with numbers.
        if (!b.statements.empty()) return false;
        for (const auto& w : b.words)
            if (w.address.size() != 1 || (w.address[0] != 'X' && w.address[0] != 'Y' && w.address[0] != 'Z') ||
                !w.number)
                return false;
    } else {
        return false;
    }
    return no_cycle(v.before) && no_cycle(v.after);
}

bool plain_moves_possible(const Catalog& catalog) {
    for (const char* code : {"G0", "G1", "G2", "G3"})
        if (catalog.find_by_code(code)) return false;
    return true;
}

namespace {

// What a plain move's word is made of, from a block or from a PlainMove.
char address_of(const Word& w) { return w.address[0]; }
double number_of(const Word& w) { return *w.number; }
char address_of(const PlainMoveWord& w) { return w.address; }
double number_of(const PlainMoveWord& w) { return w.number; }

template <class Words>
void apply_plain_words(const Words& words, uint32_t line, ModalState& s) {
    // apply_block on such a block: no G code but the motion mode, no M code, no
    // call, no cycle (known), so every X/Y/Z is a move read in the state before
    // the block, and F sets the feed.
    s.clear_one_shots();
    const bool known = s.distance.known;
    const bool absolute = s.distance.value == Distance::Absolute;
    // An incremental move adds to the position before the block (read only
    // then: in absolute mode, the common one, no axis reads the old value).
    Val<double> before[3];
    if (known && !absolute) {
        before[0] = s.x;
        before[1] = s.y;
        before[2] = s.z;
    }
    for (const auto& w : words) {
        const double v = number_of(w);
        int axis = 0;
        switch (address_of(w)) {
            case 'G':
                s.motion = Val<int>::of(static_cast<int>(v));
                s.g60_from.set(false, line, w.range);
                continue;
            case 'F':
                s.feed = Val<double>::of(v);
                s.feed_commanded = Val<bool>::of(true);
                continue;
            case 'X': axis = 0; break;
            case 'Y': axis = 1; break;
            default: axis = 2; break;
        }
        Val<double>& ax = axis == 0 ? s.x : axis == 1 ? s.y : s.z;
        if (!known) ax = Val<double>{};
        else if (absolute) ax = Val<double>::of(v);
        else ax = before[axis].known ? Val<double>::of(before[axis].value + v) : Val<double>{};
    }
}

}  // namespace

void apply_plain_move(const Block& b, ModalState& s) { apply_plain_words(b.words, b.line, s); }

void apply_plain_move(const PlainMove& move, uint32_t line, ModalState& s) {
    apply_plain_words(std::span<const PlainMoveWord>(move.words.data(), move.count), line, s);
}

bool ends_program(const Block& b) {
    if (b.statement(StmtKind::Rts)) return true;
    for (const auto& w : b.words)
        if (w.address.size() == 1 && w.address[0] == 'M' && w.number && (*w.number == 2 || *w.number == 30))
            return true;
    return false;
}

void flow_out(const Block& block, const ModalState& before, ModalState& after) {
    if (block.block_delete) after.merge(before);  // BLOCK SKIP may be on or off
    after.clear_one_shots();                      // NCYL, NOEX, G100 belong to their block only
}

}  // namespace osplint
