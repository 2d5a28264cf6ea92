// Small helpers shared by the macro-contract rules (OSP1xx). They read the
// MacroCall the analyzer resolved and the catalog entry; nothing here walks
// the program or knows a particular macro.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>
#include <string_view>

#include "catalog/catalog.h"
#include "catalog/citations.h"
#include "engine/rule.h"
#include "semantics/summary.h"

namespace osplint::macro {

// A line that invokes a macro itself (CALL, MODIN, G-code or M-code macro),
// as opposed to a positioning block that triggers an open MODIN.
inline bool is_invocation(const MacroCall& c) {
    return c.kind == CallKind::Call || c.kind == CallKind::Modin || c.kind == CallKind::GCode ||
           c.kind == CallKind::MCode;
}

// A catalog macro (not a fixed cycle, not an unknown subprogram).
inline const MacroSpec* shop_macro(const MacroCall* c) {
    if (!c || !c->spec || c->spec->kind != SpecKind::Macro) return nullptr;
    return c->spec;
}

// The catalog macro a line invokes itself, when the catalog documents its
// arguments (the argument rules judge only those); nullptr otherwise.
inline const MacroSpec* documented_invocation(const MacroCall* c) {
    const MacroSpec* spec = shop_macro(c);
    return spec && is_invocation(*c) && spec->args_documented ? spec : nullptr;
}

// The subprogram macros that read their arguments as locals and cannot see
// M52 on the call line (the back counterboring, wall finishing and keyway
// manuals), as opposed to G-code cycle macros.
inline bool is_subprogram_macro(const MacroSpec& s) { return s.m52 == M52Mode::IgnoredUsePM52; }

// The M word `code` written on the call line, or nullptr.
inline const Word* m_code(const MacroCall& c, double code) {
    for (const Word* w : c.m_codes)
        if (w->number && *w->number == code) return w;
    return nullptr;
}

// The sides of relation `i` of `spec` (RelationSides): the catalog's, else
// read into `local`. `cycle_order` tells OSP302's relations (PR > PZ) from
// OSP103's (FA > F, Q > K).
inline const RelationSides& sides_of(const MacroSpec& spec, size_t i, RelationSides& local) {
    if (const RelationSides* s = spec.sides(i)) return *s;
    local = relation_sides(spec.relations[i], spec);
    return local;
}

// Calls `add(index)` for each argument of `spec` a relation or its
// condition names (a relation names arguments of its own macro only: the
// catalog refuses others); an index may come more than once.
template <class Add>
void relation_args(const MacroSpec& spec, Add&& add) {
    RelationSides local;
    for (size_t i = 0; i < spec.relations.size(); ++i) {
        const RelationSides& sides = sides_of(spec, i, local);
        for (int k : sides.left_args)
            if (k >= 0) add(static_cast<size_t>(k));
        for (int k : sides.right_args)
            if (k >= 0) add(static_cast<size_t>(k));
        for (const ConditionAtom* at : spec.relations[i].when.atoms())
            if (const ArgSpec* a = at->arg.empty() ? nullptr : spec.arg(at->arg))
                add(static_cast<size_t>(a - spec.args.data()));
    }
}

// The last call a rule found nothing to say about, by all the rule read of
// it: the macro, the kind of call, the plane, and of each argument the rule
// reads (`names`, listed once per macro) whether it is given and its value.
// A call that agrees on all of them has nothing to say either: a posted
// program calls a macro thousands of times with only its position changed.
// A cache, not state: a rule's same_as leaves it out.
class QuietCall {
public:
    bool same(const MacroSpec& s, const MacroCall& c, std::optional<Plane> p) const {
        if (spec_ != &s || kind_ != c.kind || plane_ != p) return false;
        for (size_t i = 0; i < named_.size(); ++i)
            if (!(ArgSeen::of(c.given(s.args[named_[i]])) == args_[i])) return false;
        return true;
    }
    // Whether a call that repeats `c` but for the values of `varying` (the
    // engine's repeats, repeat_args) is one same() holds: c is the call
    // remembered, and the rule reads none of `varying`.
    bool holds_repeat(const MacroSpec& s, const MacroCall& c, std::optional<Plane> p,
                      const std::array<const ArgSpec*, 2>& varying) const {
        if (!same(s, c, p)) return false;
        for (const ArgSpec* a : varying)
            if (a && std::find(named_.begin(), named_.end(), static_cast<size_t>(a - s.args.data())) != named_.end())
                return false;
        return true;
    }
    // `names(s, add)` calls add(index) for each argument the rule reads.
    template <class Names>
    void remember(const MacroSpec& s, const MacroCall& c, std::optional<Plane> p, Names&& names) {
        if (spec_ != &s) {
            named_.clear();
            std::vector<bool> in(s.args.size(), false);
            names(s, [&](size_t i) {
                if (i >= in.size() || in[i]) return;
                in[i] = true;
                named_.push_back(i);
            });
        }
        spec_ = &s;
        kind_ = c.kind;
        plane_ = p;
        args_.clear();
        for (size_t i : named_) args_.push_back(ArgSeen::of(c.given(s.args[i])));
    }

private:
    const MacroSpec* spec_ = nullptr;
    CallKind kind_ = CallKind::None;
    std::optional<Plane> plane_;
    std::vector<size_t> named_;  // the arguments the rule reads of spec_
    std::vector<ArgSeen> args_;  // of each of them
};

// The argument as given (by its name or one of its aliases), or nullptr.
inline const MacroArg* given(const MacroCall& c, const ArgSpec& a) { return c.given(a); }

// Whether `a`, an argument of `spec`, may give a position in the plane: a
// positioning-plane argument (ArgRole::Position), or one written X, Y or Z
// (a fixed cycle's address, or a G-code macro's through its address map).
inline bool gives_position(const MacroSpec& spec, const ArgSpec& a) {
    const auto axis = [](std::string_view n) { return n == "X" || n == "Y" || n == "Z"; };
    if (a.role == ArgRole::Position || axis(a.name)) return true;
    for (const auto& alias : a.aliases)
        if (axis(alias)) return true;
    for (const char* address : {"X", "Y", "Z"})
        if (spec.arg_for_address(address) == &a) return true;
    return false;
}

// Whether a value constraint, a relation, a condition or an at-least-one
// requirement of `spec` reads the value of an argument `pick` picks.
// Whether an argument is given does not count: a repeat gives the same ones.
template <class Pick>
bool reads_value_of(const MacroSpec& spec, Pick&& pick) {
    for (const ArgSpec& a : spec.args)
        if ((!a.allowed.empty() || a.sign != ArgSign::Any) && pick(a)) return true;
    const auto names = [&](const std::string& name) {
        const ArgSpec* a = spec.arg(name);
        return a && pick(*a);
    };
    const auto condition = [&](const Condition& c) {
        for (const ConditionAtom* at : c.atoms())
            if (at->kind == ConditionAtom::Kind::ArgEquals && names(at->arg)) return true;
        return false;
    };
    RelationSides local;
    for (size_t i = 0; i < spec.relations.size(); ++i) {
        const RelationSides& sides = sides_of(spec, i, local);
        for (const std::vector<int>* args : {&sides.left_args, &sides.right_args})
            for (int k : *args)
                if (k >= 0 && pick(spec.args[static_cast<size_t>(k)])) return true;
        if (condition(spec.relations[i].when)) return true;
    }
    for (const Caution& c : spec.cautions)
        if (condition(c.when)) return true;
    for (const auto& req : spec.at_least_one)
        for (const auto& n : req.args)
            if (names(n)) return true;
    return false;
}

// Whether they read the value of an argument that may give a position in
// the plane, in any plane and form (gives_position): a rule that checks them
// cannot say a block moved in the plane repeats the one before
// (Rule::quiet_on_repeat).
inline bool reads_position_value(const MacroSpec& spec) {
    return reads_value_of(spec, [&](const ArgSpec& a) { return gives_position(spec, a); });
}

// The arguments a repeat of a CALL of `spec` in `plane` gives other values
// (the engine's repeats): its positioning arguments of the plane's two axes.
inline std::array<const ArgSpec*, 2> repeat_args(const MacroSpec& spec, Plane plane) {
    const int number = plane_number(plane);
    const PlaneAxes pa = plane_axes(plane);
    return {spec.position_arg(number, pa.first), spec.position_arg(number, pa.second)};
}

// Whether they read the value of one of those: for a CALL of `spec` in a
// known plane, a rule that checks only them (and is quiet on the call) is
// quiet on its repeats (Rule::quiet_on_repeat_of).
inline bool reads_repeat_value(const MacroSpec& spec, Plane plane) {
    const auto varying = repeat_args(spec, plane);
    return reads_value_of(spec, [&](const ArgSpec& a) { return &a == varying[0] || &a == varying[1]; });
}

// For a rule that checks the values of a macro's arguments against its
// constraints and nothing else on a CALL: whether it is quiet on the repeats
// of the CALL `v` it was quiet on (Rule::quiet_on_repeat_of). Only in a known
// plane, and only when the constraints read neither argument a repeat changes.
inline bool quiet_on_call_repeats(const MacroSpec& spec, const BlockView& v) {
    return v.call->kind == CallKind::Call && v.before.plane.known && !reads_repeat_value(spec, v.before.plane.value);
}

// The same for a block that runs `spec`, or (nullptr) no catalog macro: then
// of every fixed cycle, which such a block may run.
inline bool reads_position_value(const Catalog& catalog, const MacroSpec* spec) {
    if (spec) return reads_position_value(*spec);
    for (const CycleSpec& c : catalog.cycles())
        if (reads_position_value(c)) return true;
    return false;
}

// Where a fact of the catalog is printed, as a citation: the manual and the
// section holding `line_source` (else the macro's own source). A shop's
// macro from a manual outside the citation table is named as its entry says.
inline std::string source_ref(const MacroSpec& s, std::string_view line_source) {
    std::string_view where = line_source.empty() ? std::string_view(s.source) : line_source;
    if (std::string c = cite_source(where); !c.empty()) return c;
    if (const Manual* m = find_manual(s.manual)) return std::string(m->title);
    return s.manual;
}

// The manual of a macro by its title ("Keyway macros manual"), or the
// catalog entry's own text for a manual outside the citation table.
inline std::string manual_name(const MacroSpec& s) {
    if (const Manual* m = find_manual(s.manual)) return std::string(m->title);
    return s.manual.empty() ? std::string("its manual") : s.manual;
}

// Where the macro's notes, or else the common rules of its manual, say
// something containing `needle`, as a citation; the macro's section when
// neither does.
inline std::string note_ref(const Catalog& catalog, const MacroSpec& s, std::string_view needle) {
    for (const auto& n : s.notes)
        if (n.text.find(needle) != std::string::npos) return source_ref(s, n.source);
    if (const CommonRules* common = s.common.empty() ? nullptr : catalog.common_rules(s.common))
        for (const auto& n : common->notes)
            if (n.text.find(needle) != std::string::npos) return source_ref(s, n.source);
    return source_ref(s, "");
}

// As note_ref, but the manual's common rules first: the citation of a rule
// every macro of the manual shares.
inline std::string common_ref(const Catalog& catalog, const MacroSpec& s, std::string_view needle) {
    if (const CommonRules* common = s.common.empty() ? nullptr : catalog.common_rules(s.common))
        for (const auto& n : common->notes)
            if (n.text.find(needle) != std::string::npos) return source_ref(s, n.source);
    return note_ref(catalog, s, needle);
}

// Where the macro's command format is printed, as a citation.
inline std::string format_ref(const MacroSpec& s) {
    return source_ref(s, s.formats.empty() ? std::string_view() : std::string_view(s.formats.front().source));
}

// Where the macro's argument table is printed, as a citation.
inline std::string args_ref(const MacroSpec& s) {
    for (const auto& a : s.args)
        if (!a.source.empty() && !a.undocumented) return source_ref(s, a.source);
    return source_ref(s, "");
}

// Where to point a finding about the whole call.
inline ByteRange call_range(const MacroCall& c, const Block& b) {
    if (!c.name_range.empty()) return c.name_range;
    return b.range;
}

inline std::string_view call_kind_name_short(CallKind k) {
    switch (k) {
        case CallKind::Call: return "CALL";
        case CallKind::Modin: return "MODIN";
        default: return "macro";
    }
}

// Where a mode came from when a user subprogram set it out of sight: "G91
// comes from the subprogram O100 (SUB.SSB, line 1), which leaves G91 in
// effect", or "" when a block of this program set it (or paths disagree).
// `mode` is G90, G91, G17, G18, G19, G20, G21 or G60.
inline std::string mode_from_subprogram(const ModalState& s, std::string_view mode) {
    const SubprogramSummary* sum = s.modes_from;
    if (!sum) return "";
    using K = ModeEffect<Distance>::Kind;
    bool set = false;
    if (mode == "G90" || mode == "G91")
        set = sum->distance.kind == K::Set && s.distance.is(sum->distance.value) &&
              (sum->distance.value == Distance::Incremental) == (mode == "G91");
    else if (mode == "G20" || mode == "G21")
        set = sum->units.kind == ModeEffect<Units>::Kind::Set && s.units.is(sum->units.value) &&
              (sum->units.value == Units::Inch) == (mode == "G20");
    else if (mode == "G60")
        set = sum->motion.kind == ModeEffect<int>::Kind::Set && sum->motion.value == 60 && s.motion.is(60);
    else
        set = sum->plane.kind == ModeEffect<Plane>::Kind::Set && s.plane.is(sum->plane.value) &&
              plane_name(sum->plane.value) == mode;
    if (!set) return "";
    const std::string file = std::filesystem::path(sum->file).filename().string();
    return std::string(mode) + " comes from the subprogram " + sum->name + " (" + file + ", line " +
           std::to_string(sum->line) + "), which " + sum->describe();
}

// For a "may" finding: how a mode some paths bring gets here. "G91 is set at
// line 7 and reaches this call through the jump at line 10".
inline std::string may_path(const Origin& o, std::string_view mode, std::string_view here) {
    std::string s = std::string(mode) + (o.line ? " is set at line " + std::to_string(o.line) : " is in effect at the start");
    if (o.via_line) s += " and reaches " + std::string(here) + " through the jump at line " + std::to_string(o.via_line);
    return s;
}
// Its notes: the block that sets the mode, and the jump that brings it.
inline void add_may_notes(RuleContext& ctx, Diagnostic& d, const Origin& o, std::string_view mode) {
    if (o.line && !o.range.empty()) d.notes.push_back({std::string(mode) + " is set here", ctx.resolve(o.range)});
    if (o.via_line && !o.via_range.empty())
        d.notes.push_back({"the path with " + std::string(mode) + " jumps here", ctx.resolve(o.via_range)});
}

using osplint::plane_number;

// Levenshtein distance, for "did you mean" suggestions.
inline size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (size_t j = 1; j <= b.size(); ++j)
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

// A value in a message; one that is not finite (which the state never holds:
// Val::of) shows as unknown, never as "inf" or "nan".
inline std::string format_number(double v) {
    if (!std::isfinite(v)) return "?";
    std::string s = std::to_string(v);
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
}

}  // namespace osplint::macro
