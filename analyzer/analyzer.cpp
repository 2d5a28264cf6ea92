#include "analyzer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <queue>
#include <unordered_map>

#include <fmt/format.h>

#include "catalog.h"
#include "eval.h"
#include "rules/registry.h"

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

SourceRange RuleContext::resolve(ByteRange r) const {
    const auto& src = source();
    SourceRange out;
    out.bytes = r;
    out.start = src.position(r.begin);
    out.end = src.position(r.end);
    return out;
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

std::optional<double> word_value(const Block& b, const Word& w, const ModalState& s) {
    if (w.number) return w.number;
    if (w.value != kNoExpr) return evaluate(b, w.value, s);
    return std::nullopt;
}

// Integer code of a G/M word when it is a plain literal (G00 -> 0, M52 -> 52).
std::optional<int> code_of(const Word& w) {
    if (!w.number) return std::nullopt;
    double v = *w.number;
    if (v < 0 || v > 100000 || v != std::floor(v)) return std::nullopt;
    return static_cast<int>(v);
}

std::vector<int> codes(const Block& b, char address) {
    std::vector<int> out;
    for (const auto& w : b.words)
        if (w.address.size() == 1 && w.address[0] == address)
            if (auto c = code_of(w)) out.push_back(*c);
    return out;
}

bool has(const std::vector<int>& v, int x) { return std::find(v.begin(), v.end(), x) != v.end(); }

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
    return s;
}

void apply_block(const Block& b, const MacroCall* call, const Catalog& catalog, ModalState& s) {
    if (b.kind != LineKind::Block) return;
    const ModalState before = s;  // values of the block are read in the state before it
    auto g = codes(b, 'G');
    auto m = codes(b, 'M');
    bool is_call = is_call_block(b);

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
                s.x = s.y = s.z = Val<double>{};
                s.work_offset = Val<double>{};
                break;
            case 16:  // one-shot coordinate system: the move's program coordinates are unknown
                s.x = s.y = s.z = Val<double>{};
                break;
            case 80:
                if (s.cycle.known && s.cycle.value && s.cycle.value->code == 114) s.spindle = Val<int>::of(5);
                s.cycle = Val<std::optional<ActiveCycle>>::of(std::nullopt);
                s.return_level = Val<int>{};  // whether G80 resets M52/M53/M54 is not documented
                break;
            default: break;
        }
    }
    for (const auto& w : b.words) {
        if (w.address.size() != 1) continue;
        auto v = word_value(b, w, before);
        switch (w.address[0]) {
            case 'H':
                if (has(g, 15)) s.work_offset = v ? Val<double>::of(*v) : Val<double>{};
                if (has(g, 56)) s.length_offset_h = v ? Val<double>::of(*v) : Val<double>{};
                break;
            case 'D':
                if (has(g, 41) || has(g, 42)) s.cutter_comp_d = v ? Val<double>::of(*v) : Val<double>{};
                break;
            case 'S':
                if (!is_call) s.spindle_speed = v ? Val<double>::of(*v) : Val<double>{};
                break;
            case 'F':
                if (!is_call && !has(g, 4)) s.feed = v ? Val<double>::of(*v) : Val<double>{};
                break;
            case 'Z':
                if (has(g, 71)) s.g71_level = v ? Val<double>::of(*v) : Val<double>{};
                break;
            default: break;
        }
    }
    for (int c : m) {
        switch (c) {
            case 3: case 4: case 5: s.spindle = Val<int>::of(c); break;
            case 7: case 8: case 12: s.coolant = Val<bool>::of(true); break;
            case 9: s.coolant = Val<bool>::of(false); break;
            case 52: case 53: case 54: s.return_level = Val<int>::of(c); break;
            case 843: s.spindle = Val<int>::of(3); break;
            case 845: s.spindle = Val<int>::of(5); break;
            default: break;
        }
    }

    // Fixed cycles and the G-code macro cycle (OG84L via G114).
    int cycle_code = 0;
    std::string cycle_macro;
    for (int c : g)
        if (is_fixed_cycle_code(catalog, c)) cycle_code = c;
    if (call && call->kind == CallKind::GCode && call->spec && is_cycle_macro(*call->spec)) {
        for (const auto& w : b.words)
            if (w.range == call->name_range)
                if (auto c = code_of(w)) cycle_code = *c;
        cycle_macro = call->spec->name;
        s.overrides_disabled = Val<bool>::of(true);
    }
    if (call && call->kind == CallKind::MCode && call->spec && !call->spec->cancels.empty()) {
        s.cycle = Val<std::optional<ActiveCycle>>::of(std::nullopt);
        s.overrides_disabled = Val<bool>::of(false);
        s.spindle = Val<int>::of(5);
        s.return_level = Val<int>{};
    }
    const bool in_cycle_before = before.cycle.known && before.cycle.value;
    const char cyc_axis = before.plane.known ? plane_axes(before.plane.value).cycle : 0;
    if (cycle_code) {
        ActiveCycle c;
        c.code = cycle_code;
        c.macro = cycle_macro;
        c.start_line = b.line;
        if (in_cycle_before && before.cycle.value->code == cycle_code) {
            c = *before.cycle.value;  // same cycle commanded again: values carry over
        } else if (cyc_axis) {
            c.initial = before.axis(cyc_axis);
        }
        if (const Word* r = b.find("R")) {
            auto v = word_value(b, *r, before);
            c.r = v ? Val<double>::of(*v) : Val<double>{};
        }
        if (cyc_axis)
            if (const Word* z = b.find(std::string(1, cyc_axis))) {
                auto v = word_value(b, *z, before);
                c.z = v ? Val<double>::of(*v) : Val<double>{};
            }
        s.cycle = Val<std::optional<ActiveCycle>>::of(std::move(c));
    } else if (in_cycle_before && cyc_axis && !has(g, 80)) {
        // R and Z may be changed on later hole blocks of the same cycle.
        ActiveCycle c = *before.cycle.value;
        if (const Word* r = b.find("R")) {
            auto v = word_value(b, *r, before);
            c.r = v ? Val<double>::of(*v) : Val<double>{};
        }
        if (const Word* z = b.find(std::string(1, cyc_axis))) {
            auto v = word_value(b, *z, before);
            c.z = v ? Val<double>::of(*v) : Val<double>{};
        }
        if (s.cycle.known && s.cycle.value) s.cycle = Val<std::optional<ActiveCycle>>::of(std::move(c));
    }

    // Tool-tip position.
    const bool cycle_block = (s.cycle.known && s.cycle.value) && !has(g, 80);
    if (is_call || (call && call->kind == CallKind::ModinPositioning) ||
        (call && call->kind == CallKind::GCode && !cycle_code)) {
        // A subprogram or macro moves the tool in ways this evaluator does not follow.
        s.x = s.y = s.z = Val<double>{};
    } else if (!non_motion_axes(g) && !has(g, 15) && !has(g, 16)) {
        for (const auto& w : b.words) {
            if (w.address.size() != 1) continue;
            Val<double>* ax = s.axis_ref(w.address[0]);
            if (!ax) continue;
            if (cycle_block && cyc_axis && w.address[0] == cyc_axis) continue;  // cycle depth, not a move
            auto v = word_value(b, w, before);
            if (!v || !before.distance.known) {
                *ax = Val<double>{};
            } else if (before.distance.value == Distance::Absolute) {
                *ax = Val<double>::of(*v);
            } else {
                Val<double> old = before.axis(w.address[0]);
                *ax = old.known ? Val<double>::of(old.value + *v) : Val<double>{};
            }
        }
        if (cycle_block && cyc_axis) {
            // After a hole the tool waits at the initial point (G98) or at R (G99).
            const ActiveCycle& c = *s.cycle.value;
            Val<double>* ax = s.axis_ref(cyc_axis);
            if (ax) {
                bool absolute = before.distance.is(Distance::Absolute);
                if (s.cycle_return.is(CycleReturn::R) && c.r.known && absolute)
                    *ax = c.r;
                else if (s.cycle_return.is(CycleReturn::Initial) && c.initial.known)
                    *ax = c.initial;
                else
                    *ax = Val<double>{};
            }
        }
    }

    // Statements.
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
                if (spec && !spec->vc120_128_clobbered) break;
                if (spec) {
                    for (int n = 120; n <= 128; ++n) s.vars.erase("VC" + std::to_string(n));
                } else {
                    // An unknown subprogram may change any common variable.
                    for (auto it = s.vars.begin(); it != s.vars.end();)
                        it = common_variable_number(it->first) ? s.vars.erase(it) : std::next(it);
                }
                break;
            }
            default: break;
        }
    }
    if (call && call->kind == CallKind::ModinPositioning && call->spec &&
        call->spec->vc120_128_clobbered)
        for (int n = 120; n <= 128; ++n) s.vars.erase("VC" + std::to_string(n));

    // Assignments: variables and plain locals (`PX=0` on a block with no G/M code or call).
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
    if (!is_call && g.empty() && m.empty() && !call) {
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

}  // namespace osplint
