#include "semantics/transfer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "catalog/catalog.h"
#include "semantics/eval.h"

namespace osplint {

std::string_view call_kind_name(CallKind k) {
    switch (k) {
        case CallKind::None: return "none";
        case CallKind::Call: return "CALL";
        case CallKind::Modin: return "MODIN";
        case CallKind::ModinPositioning: return "MODIN positioning";
        case CallKind::GCode: return "G-code macro";
        case CallKind::MCode: return "M-code macro";
    }
    return "?";
}

std::optional<double> word_value(const Block& b, const Word& w, const ModalState& s) {
    if (w.number) return w.number;
    if (w.value != kNoExpr) return evaluate(b, w.value, s);
    return std::nullopt;
}

std::optional<int> code_of(const Word& w) {
    if (!w.number) return std::nullopt;
    double v = *w.number;
    if (v < 0 || v > 100000 || v != std::floor(v)) return std::nullopt;
    return static_cast<int>(v);
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

bool is_axis_address(std::string_view a) {
    return a.size() == 1 && (a[0] == 'X' || a[0] == 'Y' || a[0] == 'Z' || a[0] == 'A' || a[0] == 'B' ||
                             a[0] == 'C' || a[0] == 'U' || a[0] == 'V' || a[0] == 'W');
}

std::vector<int> codes(const Block& b, char address) {
    std::vector<int> out;
    for (const auto& w : b.words)
        if (w.address.size() == 1 && w.address[0] == address)
            if (auto c = code_of(w)) out.push_back(*c);
    return out;
}

// Membership in a sorted, de-duplicated code list (see `code_set`): blocks with
// very many words stay linear.
bool has(const std::vector<int>& sorted, int x) { return std::binary_search(sorted.begin(), sorted.end(), x); }
std::vector<int> code_set(std::vector<int> v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return v;
}

// Blocks whose X/Y/Z words are not a move of the tool tip in program coordinates.
bool non_motion_axes(const std::vector<int>& g) {
    for (int c : g)
        if (c == 71 || c == 4 || c == 11 || c == 10 || c == 30 || c == 50 || c == 92 || c == 20 ||
            c == 22 || c == 23)
            return true;
    return false;
}

bool is_call_block(const Block& b) {
    return b.statement(StmtKind::Call) || b.statement(StmtKind::Modin);
}

}  // namespace

std::optional<MacroCall> resolve_call(const Block& b, const ModalState& before, const Catalog& catalog) {
    if (b.kind != LineKind::Block) return std::nullopt;
    const Statement* st = b.statement(StmtKind::Call);
    if (!st) st = b.statement(StmtKind::Modin);
    MacroCall call;
    if (st) {
        call.kind = st->kind == StmtKind::Call ? CallKind::Call : CallKind::Modin;
        call.name = st->name;
        call.name_range = st->name_range;
        call.spec = catalog.find(st->name);
        for (const auto& w : b.words) {
            if (w.address == "M") {
                call.m_codes.push_back(&w);
            } else if (w.address == "Q" && !call.repeat) {
                call.repeat = &w;
            } else if (w.range.begin > st->keyword_range.begin) {
                call.args.push_back(MacroArg{w.address, &w, {}});
            }
        }
    } else {
        // A registered G- or M-code macro.
        for (const auto& w : b.words) {
            if (w.address != "G" && w.address != "M") continue;
            auto c = code_of(w);
            if (!c) continue;
            std::string code = w.address + std::to_string(*c);
            const MacroSpec* spec = catalog.find_by_code(code);
            if (!spec) continue;
            call.kind = w.address == "G" ? CallKind::GCode : CallKind::MCode;
            call.name = spec->name;
            call.name_range = w.range;
            call.spec = spec;
            for (const auto& a : b.words) {
                if (&a == &w) continue;
                if (a.address == "M") {
                    call.m_codes.push_back(&a);
                    continue;
                }
                if (a.address == "G") continue;  // other G codes of the block (G90, G98 ...)
                const ArgSpec* as = spec->arg_for_address(a.address);
                call.args.push_back(MacroArg{as ? as->name : a.address, &a, {}});
            }
            break;
        }
        if (call.kind == CallKind::None) {
            // A positioning block while a MODIN is open runs the modal macro.
            if (!before.modin.known || !before.modin.value) return std::nullopt;
            if (b.statement(StmtKind::Modout) || b.statement(StmtKind::Modin)) return std::nullopt;
            auto g = codes(b, 'G');
            if (non_motion_axes(g)) return std::nullopt;
            bool moves = false;
            for (const auto& w : b.words)
                if (is_axis_address(w.address)) moves = true;
            for (const auto& s : b.statements)
                if (s.kind == StmtKind::CoordCalc) moves = true;
            if (!moves) return std::nullopt;
            const ActiveModin& m = *before.modin.value;
            call.kind = CallKind::ModinPositioning;
            call.name = m.macro;
            call.spec = catalog.find(m.macro);
            call.modin_line = m.line;
            for (const auto& name : m.given) {
                MacroArg a{name, nullptr, {}};
                if (auto it = m.values.find(name); it != m.values.end()) a.value = Val<double>::of(it->second);
                call.args.push_back(std::move(a));
            }
            for (const auto& w : b.words)
                if (w.address == "M") call.m_codes.push_back(&w);
            return call;
        }
    }
    for (auto& a : call.args)
        if (a.word)
            if (auto v = word_value(b, *a.word, before)) a.value = Val<double>::of(*v);
    return call;
}

ModalState initial_state(const Config& config, bool subprogram) {
    ModalState s;
    if (subprogram) {
        // A subprogram inherits whatever its caller had: nothing is known.
        return s;
    }
    s.plane = Val<Plane>::of(config.plane);
    s.units = Val<Units>::of(config.units);
    s.distance = Val<Distance>::of(config.distance);
    s.cycle = Val<std::optional<ActiveCycle>>::of(std::nullopt);
    s.modin = Val<std::optional<ActiveModin>>::of(std::nullopt);
    s.overrides_disabled = Val<bool>::of(false);
    s.return_level = Val<int>::of(0);
    s.spindle_stopped_by = Val<uint32_t>::of(0);
    s.speed_commanded = Val<bool>::of(false);
    s.sync_tap = Val<bool>::of(false);
    return s;
}

namespace {

// G or M codes of a block, literal or evaluated in the state before it.
// `unknown` is set when a G/M word has a value that cannot be known.
std::vector<int> block_codes(const Block& b, char address, const ModalState& before, bool& unknown) {
    std::vector<int> out;
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
        c.words[w.address] = known_or_unknown(word_value(b, w, before));
    }
}

bool has_axis_word(const Block& b) {
    for (const auto& w : b.words)
        if (is_axis_address(w.address)) return true;
    return false;
}

bool has_coord_calc(const Block& b) {
    for (const auto& s : b.statements)
        if (s.kind == StmtKind::CoordCalc) return true;
    return false;
}

void all_positions_unknown(ModalState& s) { s.x = s.y = s.z = Val<double>{}; }

// What a subprogram or macro run does to the state, beyond the tool position.
void apply_subprogram_run(const MacroCall* call, const MacroSpec* spec, const ModalState& before, ModalState& s) {
    s.feed = Val<double>{};
    const bool shop_subprogram = spec && spec->kind == SpecKind::Macro && spec->m52 == M52Mode::IgnoredUsePM52;
    if (shop_subprogram) {
        // The shop's cycle macros work "like the equivalent fixed cycle" (seed 000
        // L18-20) and leave the interpolation mode as it was: the manuals' warning
        // about G60 with NCYL during them (000 L54-56) presupposes that G60 stays
        // modal across their runs.
        // Seeds 000-002: the macro starts the spindle itself and keeps a running one.
        if (!(before.spindle.is(3) || before.spindle.is(4))) s.spindle = Val<int>{};
        s.spindle_stopped_by = Val<uint32_t>::of(0);
        const MacroArg* ps = call ? call->arg("PS") : nullptr;
        if (ps) {
            s.spindle_speed = ps->value;
            s.speed_commanded = Val<bool>::of(true);
        }
        return;
    }
    // Anything else may leave the interpolation mode, the spindle, the coolant
    // and the synchronised-tapping mode changed.
    s.motion = Val<int>{};
    s.spindle = Val<int>{};
    s.spindle_stopped_by = Val<uint32_t>{};
    s.spindle_speed = Val<double>{};
    s.speed_commanded = Val<bool>{};
    s.sync_tap = Val<bool>{};
    s.coolant = Val<bool>{};
}

void erase_reserved_common(ModalState& s) {
    for (int n = 120; n <= 128; ++n) s.vars.erase("VC" + std::to_string(n));
}

void erase_all_common(ModalState& s) {
    for (auto it = s.vars.begin(); it != s.vars.end();)
        it = common_variable_number(it->first) ? s.vars.erase(it) : std::next(it);
}

}  // namespace

void apply_block(const Block& b, const MacroCall* call, const Catalog& catalog, ModalState& s) {
    if (b.kind != LineKind::Block) return;
    s.clear_one_shots();
    const ModalState before = s;  // values of the block are read in the state before it
    bool unknown_g = false, unknown_m = false;
    const auto g = block_codes(b, 'G', before, unknown_g);
    const auto m = block_codes(b, 'M', before, unknown_m);
    const auto gs = code_set(g);  // for membership tests; `g` keeps the written order
    const bool is_call = is_call_block(b);  // CALL or MODIN statement on the block
    const bool g80 = has(gs, 80);
    const bool interpolation = has(gs, 0) || has(gs, 1) || has(gs, 2) || has(gs, 3);
    s.ncyl = b.statement(StmtKind::Ncyl) != nullptr;
    s.noex = b.statement(StmtKind::Noex) != nullptr;
    s.g100 = has(gs, 100);

    // The macro this block runs, if any, and whether it is the declaration of
    // a G-code macro cycle (G114 -> OG84L).
    const bool runs_program = call && (call->kind == CallKind::Call || call->kind == CallKind::ModinPositioning ||
                                       call->kind == CallKind::GCode || call->kind == CallKind::MCode);
    const bool cycle_declaration =
        call && call->kind == CallKind::GCode && call->spec && is_cycle_macro(*call->spec);
    const bool cycle_cancel_macro =
        call && call->kind == CallKind::MCode && call->spec && !call->spec->cancels.empty();

    // --- G codes ------------------------------------------------------------
    bool positions_unknown = false;
    for (int c : g) {
        switch (c) {
            case 0: case 1: case 2: case 3: case 60: s.motion = Val<int>::of(c); break;
            case 17: s.plane = Val<Plane>::of(Plane::G17); break;
            case 18: s.plane = Val<Plane>::of(Plane::G18); break;
            case 19: s.plane = Val<Plane>::of(Plane::G19); break;
            case 20: s.units = Val<Units>::of(Units::Inch); break;
            case 21: s.units = Val<Units>::of(Units::Mm); break;
            case 90: s.distance = Val<Distance>::of(Distance::Absolute); break;
            case 91: s.distance = Val<Distance>::of(Distance::Incremental); break;
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
            case 80:
                if (!s.cycle.known) {
                    // Perhaps a G114 mode: the spindle may have stopped.
                    s.spindle = Val<int>{};
                    s.spindle_stopped_by = Val<uint32_t>{};
                } else if (s.cycle.value && !s.cycle.value->macro.empty()) {
                    // Ending G114 (OG84L): "the spindle stops too!" (seed 003 L193).
                    s.spindle = Val<int>::of(5);
                    s.spindle_stopped_by = Val<uint32_t>::of(b.line);
                }
                s.cycle = Val<std::optional<ActiveCycle>>::of(std::nullopt);
                // Whether G80 resets M52/M53/M54 is not documented: a return level
                // stays known only when none was commanded.
                if (!s.return_level.is(0)) s.return_level = Val<int>{};
                break;
            default: break;
        }
    }
    if (unknown_g) {
        // A G code whose value is not known may have changed any G-code mode.
        s.plane = Val<Plane>{};
        s.distance = Val<Distance>{};
        s.units = Val<Units>{};
        s.motion = Val<int>{};
        s.cycle_return = Val<CycleReturn>{};
        s.cutter_comp = Val<int>{};
        s.length_offset = Val<bool>{};
        s.cycle = Val<std::optional<ActiveCycle>>{};
        positions_unknown = true;
    }
    if (has(gs, 20) && b.find("HP")) positions_unknown = true;  // G20 HP=n: home position (Multus)

    // --- Words that set modal values ------------------------------------------
    for (const auto& w : b.words) {
        if (w.address.size() != 1) continue;
        auto v = word_value(b, w, before);
        switch (w.address[0]) {
            case 'H':
                if (has(gs, 15)) s.work_offset = known_or_unknown(v);
                if (has(gs, 56)) s.length_offset_h = known_or_unknown(v);
                break;
            case 'D':
                if (has(gs, 41) || has(gs, 42)) s.cutter_comp_d = known_or_unknown(v);
                break;
            case 'S':
                if (!is_call) {
                    s.spindle_speed = known_or_unknown(v);
                    s.speed_commanded = Val<bool>::of(true);
                }
                break;
            case 'F':
                if (!is_call && !has(gs, 4)) s.feed = known_or_unknown(v);
                break;
            case 'Z':
                if (has(gs, 71)) s.g71_level = known_or_unknown(v);
                break;
            default: break;
        }
    }

    // --- M codes --------------------------------------------------------------
    for (int c : m) {
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
    if (unknown_m) {
        s.spindle = Val<int>{};
        s.spindle_stopped_by = Val<uint32_t>{};
        s.coolant = Val<bool>{};
        s.return_level = Val<int>{};
        s.sync_tap = Val<bool>{};
    }

    // --- Fixed cycles and the G-code macro cycle (OG84L via G114) ----------------
    int cycle_code = 0;
    ByteRange cycle_word;
    for (const auto& w : b.words) {
        if (w.address != "G") continue;
        auto c = code_of(w);
        if (c && is_fixed_cycle_code(catalog, *c)) {
            cycle_code = *c;
            cycle_word = w.range;
        }
    }
    if (cycle_code >= 85 && cycle_code <= 89 && b.find("N")) {
        // `G85 N0207 D7 ...` names a contour: a lathe LAP cycle, not a fixed
        // cycle. It machines the contour and ends where it ends.
        cycle_code = 0;
        positions_unknown = true;
    }
    std::string cycle_macro;
    if (cycle_declaration) {
        for (const auto& w : b.words)
            if (w.range == call->name_range)
                if (auto c = code_of(w)) {
                    cycle_code = *c;
                    cycle_word = w.range;
                }
        cycle_macro = call->spec->name;
        s.overrides_disabled = Val<bool>::of(true);
    }
    if (cycle_cancel_macro) {
        s.cycle = Val<std::optional<ActiveCycle>>::of(std::nullopt);
        s.overrides_disabled = Val<bool>::of(false);
        s.spindle = Val<int>::of(5);  // "the spindle stops too" (seed 003 L193, A-45)
        s.spindle_stopped_by = Val<uint32_t>::of(b.line);
        if (!s.return_level.is(0)) s.return_level = Val<int>{};
    }
    const char cyc_axis = s.plane.known ? plane_axes(s.plane.value).cycle : 0;
    if (cycle_code) {
        ActiveCycle c;
        const bool same = !g80 && before.cycle.known && before.cycle.value &&
                          before.cycle.value->code == cycle_code && before.cycle.value->macro == cycle_macro;
        if (same) {
            c = *before.cycle.value;  // the same cycle commanded again: the modal values carry over
        } else {
            c.code = cycle_code;
            c.macro = cycle_macro;
            c.start_line = b.line;
            c.start_range = cycle_word;
            if (cyc_axis) c.initial = before.axis(cyc_axis);
        }
        update_cycle(c, b, before, cyc_axis);
        s.cycle = Val<std::optional<ActiveCycle>>::of(std::move(c));
    } else if (s.cycle.known && s.cycle.value && !g80) {
        if (interpolation) {
            // Whether G0/G1/G2/G3 ends a fixed cycle on this control is not
            // documented: the cycle may or may not still be modal.
            s.cycle = Val<std::optional<ActiveCycle>>{};
        } else {
            ActiveCycle c = *s.cycle.value;
            update_cycle(c, b, before, cyc_axis);
            s.cycle = Val<std::optional<ActiveCycle>>::of(std::move(c));
        }
    }

    // --- Tool-tip position -------------------------------------------------------
    const bool in_cycle = s.cycle.known && s.cycle.value && !g80;
    // Whether a cycle is modal is not known: the block may machine a hole,
    // unless it commands an interpolation (then its words are a move).
    const bool maybe_cycle = !s.cycle.known && !g80 && !interpolation;
    if (runs_program && !cycle_declaration && !cycle_cancel_macro) {
        // A subprogram or macro moves the tool in ways this evaluator does not follow.
        positions_unknown = true;
    }
    // A MODIN line only declares the modal call: the tool does not move there.
    if (b.statement(StmtKind::Call)) positions_unknown = true;
    if (positions_unknown) {
        all_positions_unknown(s);
    } else if (has(gs, 92) || has(gs, 50) || has(gs, 22) || has(gs, 23)) {
        // Coordinate setting and the like: the named axes get values this
        // evaluator does not model.
        for (const auto& w : b.words)
            if (w.address.size() == 1)
                if (Val<double>* ax = s.axis_ref(w.address[0])) *ax = Val<double>{};
    } else if (!has(gs, 71) && !has(gs, 4)) {
        const Distance* dist = s.distance.known ? &s.distance.value : nullptr;
        for (const auto& w : b.words) {
            if (w.address.size() != 1) continue;
            Val<double>* ax = s.axis_ref(w.address[0]);
            if (!ax || is_coord_calc_operand(b, w)) continue;  // pattern operands: handled below
            if (in_cycle && cyc_axis && w.address[0] == cyc_axis) continue;  // cycle depth, not a move
            if ((maybe_cycle || in_cycle) && (!cyc_axis || w.address[0] == cyc_axis)) {
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
        if ((has(gs, 56) || has(gs, 53)) && !b.find("Z")) s.z = Val<double>{};  // the offset changes the tip's Z
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
        if (maybe_cycle && (has_axis_word(b) || find_address(b, "R") || has_coord_calc(b))) {
            // Perhaps a hole: the cycle axis may end at a return level.
            if (cyc_axis)
                *s.axis_ref(cyc_axis) = Val<double>{};
            else
                all_positions_unknown(s);
        }
        if (in_cycle && cyc_axis) {
            // A hole is machined unless the block only positions (NCYL, G100, the
            // G114 declaration block, NOEX) or has no positioning at all.
            const bool positions = cycle_code || has_axis_word(b) || find_address(b, "R") || has_coord_calc(b);
            const bool hole = positions && !s.ncyl && !s.g100 && !s.noex && !cycle_declaration;
            if (hole) {
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
                *s.axis_ref(cyc_axis) = ret;
            }
        }
    }

    // --- Statements -----------------------------------------------------------
    for (const auto& st : b.statements) {
        switch (st.kind) {
            case StmtKind::Modin: {
                ActiveModin am;
                am.macro = st.name;
                am.line = b.line;
                if (call && call->kind == CallKind::Modin) {
                    for (const auto& a : call->args) {
                        am.given.push_back(a.name);
                        if (a.value.known) am.values[a.name] = a.value.value;
                    }
                }
                s.modin = Val<std::optional<ActiveModin>>::of(std::move(am));
                break;
            }
            case StmtKind::Modout:
                s.modin = Val<std::optional<ActiveModin>>::of(std::nullopt);
                break;
            case StmtKind::Call: {
                const MacroSpec* spec = catalog.find(st.name);
                apply_subprogram_run(call && call->kind == CallKind::Call ? call : nullptr, spec, before, s);
                if (!spec) {
                    // An unknown subprogram may change any common variable.
                    erase_all_common(s);
                } else if (spec->vc120_128_clobbered) {
                    erase_reserved_common(s);
                }
                break;
            }
            default: break;
        }
    }
    if (call && call->kind == CallKind::ModinPositioning) {
        apply_subprogram_run(call, call->spec, before, s);
        if (!call->spec) erase_all_common(s);
        else if (call->spec->vc120_128_clobbered) erase_reserved_common(s);
    }
    if (call && (call->kind == CallKind::GCode || call->kind == CallKind::MCode) && !cycle_declaration &&
        !cycle_cancel_macro) {
        apply_subprogram_run(call, call->spec, before, s);
        if (!call->spec) erase_all_common(s);
        else if (call->spec->vc120_128_clobbered) erase_reserved_common(s);
    }

    // --- Assignments: variables and plain locals (`PX=0` on a block with no G/M code or call)
    for (const auto& a : b.assignments) {
        auto key = variable_key(b, a.target, before);
        if (!key) {
            // Unknown subscript: any variable of that family may change.
            const ExprNode* t = b.expr(a.target);
            std::string base = t ? t->text : std::string();
            for (auto it = s.vars.begin(); it != s.vars.end();)
                it = it->first.rfind(base, 0) == 0 ? s.vars.erase(it) : std::next(it);
            continue;
        }
        auto v = evaluate(b, a.value, before);
        if (v)
            s.vars[*key] = *v;
        else
            s.vars.erase(*key);
    }
    if (!is_call && g.empty() && m.empty() && !call && !unknown_g && !unknown_m) {
        for (const auto& w : b.words) {
            if (w.address.size() < 2 || !w.equals) continue;
            auto v = word_value(b, w, before);
            if (v)
                s.vars[w.address] = *v;
            else
                s.vars.erase(w.address);
        }
    }
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

bool plain_moves_possible(const Catalog& catalog) {
    for (const char* code : {"G0", "G1", "G2", "G3"})
        if (catalog.find_by_code(code)) return false;
    return true;
}

void apply_plain_move(const Block& b, ModalState& s) {
    // apply_block on such a block: no G code but the motion mode, no M code, no
    // call, no cycle (known), so every X/Y/Z is a move read in the state before
    // the block, and F sets the feed.
    s.clear_one_shots();
    const Val<double> before[3] = {s.x, s.y, s.z};
    const bool known = s.distance.known;
    const bool absolute = s.distance.value == Distance::Absolute;
    for (const auto& w : b.words) {
        const double v = *w.number;
        int axis = 0;
        switch (w.address[0]) {
            case 'G': s.motion = Val<int>::of(static_cast<int>(v)); continue;
            case 'F': s.feed = Val<double>::of(v); continue;
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
