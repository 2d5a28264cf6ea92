// Subprogram summaries (see summary.h).
#include "semantics/summary.h"

#include <iterator>
#include <vector>

#include "semantics/eval.h"

namespace osplint {

namespace {

template <class T>
ModeEffect<T> effect(const Val<T>& in0, const Val<T>& in1, const ModalState* end0, const ModalState* end1,
                     Val<T> ModalState::*field) {
    ModeEffect<T> e;
    if (!end0 || !end1) {
        e.kind = ModeEffect<T>::Kind::Unknown;
        return e;
    }
    const Val<T>& a = end0->*field;
    const Val<T>& b = end1->*field;
    if (a.known && b.known && a.value == b.value) {
        e.kind = ModeEffect<T>::Kind::Set;
        e.value = a.value;
    } else if (a == in0 && b == in1) {
        e.kind = ModeEffect<T>::Kind::Kept;
    } else {
        e.kind = ModeEffect<T>::Kind::Unknown;
    }
    return e;
}

template <class T>
void apply(const ModeEffect<T>& e, Val<T>& v) {
    if (e.kind == ModeEffect<T>::Kind::Set) v = Val<T>::of(e.value);
    else if (e.kind == ModeEffect<T>::Kind::Unknown) v = Val<T>{};
}

// A fixed cycle or a MODIN the subprogram leaves open is open for the caller
// from the CALL at `line` on (`place` moves it there); one it closes, or may
// close, is as the effect says.
template <class T, class Place>
void apply_open(const ModeEffect<std::optional<T>>& e, Val<std::optional<T>>& v, ModeOrigin<bool, true>& from,
                uint32_t line, ByteRange range, Place place) {
    using K = typename ModeEffect<std::optional<T>>::Kind;
    if (e.kind == K::Set && e.value) {
        T x = *e.value;
        place(x);
        v = Val<std::optional<T>>::of(std::move(x));
        from.set(true, line, range);
    } else {
        apply(e, v);
        if (e.kind != K::Kept) from.clear();
    }
}

}  // namespace

ModalState summary_probe(int which) {
    ModalState s;  // a subprogram's entry: nothing known
    s.distance = Val<Distance>::of(which == 0 ? Distance::Absolute : Distance::Incremental);
    s.plane = Val<Plane>::of(which == 0 ? Plane::G17 : Plane::G18);
    s.units = Val<Units>::of(which == 0 ? Units::Mm : Units::Inch);
    s.motion = Val<int>::of(which == 0 ? 0 : 1);
    if (which == 0) {  // no cycle, no MODIN; the other walk has both unknown
        s.cycle = Val<std::optional<ActiveCycle>>::of(std::nullopt);
        s.uncancelled = Val<std::optional<OpenCycle>>::of(std::nullopt);
        s.modin = Val<std::optional<ActiveModin>>::of(std::nullopt);
    }
    return s;
}

SubprogramSummary summarize(const ModalState* end0, const ModalState* end1) {
    const ModalState in0 = summary_probe(0), in1 = summary_probe(1);
    SubprogramSummary s;
    s.distance = effect(in0.distance, in1.distance, end0, end1, &ModalState::distance);
    s.plane = effect(in0.plane, in1.plane, end0, end1, &ModalState::plane);
    s.units = effect(in0.units, in1.units, end0, end1, &ModalState::units);
    s.motion = effect(in0.motion, in1.motion, end0, end1, &ModalState::motion);
    // The cycle a subprogram leaves modal is the same in both walks, but its
    // depth and return level depend on the plane, which the walks vary: the
    // cycle is set when the walks agree on which cycle, its values as they merge.
    s.cycle = effect(in0.cycle, in1.cycle, end0, end1, &ModalState::cycle);
    if (end0 && end1 && s.cycle.kind == ModeEffect<std::optional<ActiveCycle>>::Kind::Unknown) {
        ModalState merged = *end0;
        merged.merge(*end1);
        if (merged.cycle.known) {
            s.cycle.kind = ModeEffect<std::optional<ActiveCycle>>::Kind::Set;
            s.cycle.value = merged.cycle.value;
        }
    }
    s.uncancelled = effect(in0.uncancelled, in1.uncancelled, end0, end1, &ModalState::uncancelled);
    s.modin = effect(in0.modin, in1.modin, end0, end1, &ModalState::modin);
    return s;
}

void apply_summary(const SubprogramSummary& summary, uint32_t line, ByteRange range, ModalState& s) {
    if (summary.changes_anything()) s.modes_from = &summary;
    apply(summary.distance, s.distance);
    apply(summary.plane, s.plane);
    apply(summary.units, s.units);
    apply(summary.motion, s.motion);
    // A cycle or a MODIN left open starts, for the caller, at the CALL: the
    // subprogram's own lines are in another program (often another file).
    using CK = ModeEffect<std::optional<ActiveCycle>>::Kind;
    if (summary.cycle.kind == CK::Set && summary.cycle.value) {
        ActiveCycle c = *summary.cycle.value;
        c.start_line = 0;  // no block of this program commands it: rules that read the starting block skip it
        c.start_range = range;
        c.command_range = range;
        c.initial = Val<double>{};
        c.via = summary.name;
        s.cycle = Val<std::optional<ActiveCycle>>::of(std::move(c));
    } else {
        apply(summary.cycle, s.cycle);
    }
    apply_open(summary.uncancelled, s.uncancelled, s.cycle_from, line, range, [&](OpenCycle& o) {
        o.start = range;
        o.via = summary.name;
    });
    // The common variables it writes.
    if (summary.writes_any) {
        for (auto it = s.vars.begin(); it != s.vars.end();)
            it = common_variable_number(it->first) ? s.vars.erase(it) : std::next(it);
    } else {
        for (const auto& [n, v] : summary.writes) {
            const std::string key = "VC" + std::to_string(n);
            if (v) s.vars[key] = *v;
            else s.vars.erase(key);
        }
        if (!summary.clobbers_reserved.empty())
            for (int n = 120; n <= 128; ++n) s.vars.erase("VC" + std::to_string(n));
    }
    apply_open(summary.modin, s.modin, s.modin_from, line, range, [&](ActiveModin& m) {
        m.line = line;
        m.via = summary.name;
    });
}

bool same_effect(const SubprogramSummary& a, const SubprogramSummary& b) {
    SubprogramSummary x = a, y = b;
    x.file = y.file;
    x.line = y.line;
    return x == y;
}

bool SubprogramSummary::changes_anything() const {
    return distance.kind != ModeEffect<Distance>::Kind::Kept || plane.kind != ModeEffect<Plane>::Kind::Kept ||
           units.kind != ModeEffect<Units>::Kind::Kept || motion.kind != ModeEffect<int>::Kind::Kept ||
           uncancelled.kind != ModeEffect<std::optional<OpenCycle>>::Kind::Kept ||
           modin.kind != ModeEffect<std::optional<ActiveModin>>::Kind::Kept;
}

std::string SubprogramSummary::describe() const {
    std::vector<std::string> parts;
    using D = ModeEffect<Distance>::Kind;
    if (distance.kind == D::Set) parts.push_back(distance.value == Distance::Absolute ? "G90" : "G91");
    if (plane.kind == ModeEffect<Plane>::Kind::Set) parts.push_back(plane_name(plane.value));
    if (units.kind == ModeEffect<Units>::Kind::Set) parts.push_back(units.value == Units::Mm ? "G21 (mm)" : "G20 (inch)");
    if (motion.kind == ModeEffect<int>::Kind::Set) parts.push_back("G" + std::to_string(motion.value));
    if (uncancelled.kind == ModeEffect<std::optional<OpenCycle>>::Kind::Set && uncancelled.value)
        parts.push_back("the fixed cycle G" + std::to_string(uncancelled.value->code));
    if (modin.kind == ModeEffect<std::optional<ActiveModin>>::Kind::Set && modin.value)
        parts.push_back("MODIN " + modin.value->macro);
    std::string out;
    if (!parts.empty()) {
        out = "leaves ";
        for (size_t i = 0; i < parts.size(); ++i) out += (i ? (i + 1 == parts.size() ? " and " : ", ") : "") + parts[i];
        out += " in effect";
    }
    std::vector<std::string> unknown;
    if (distance.kind == D::Unknown) unknown.push_back("G90/G91");
    if (plane.kind == ModeEffect<Plane>::Kind::Unknown) unknown.push_back("the plane");
    if (units.kind == ModeEffect<Units>::Kind::Unknown) unknown.push_back("the units");
    if (motion.kind == ModeEffect<int>::Kind::Unknown) unknown.push_back("the interpolation mode");
    if (uncancelled.kind == ModeEffect<std::optional<OpenCycle>>::Kind::Unknown) unknown.push_back("the fixed cycle");
    if (modin.kind == ModeEffect<std::optional<ActiveModin>>::Kind::Unknown) unknown.push_back("the modal call (MODIN)");
    if (!unknown.empty()) {
        if (!out.empty()) out += "; ";
        out += "may change ";
        for (size_t i = 0; i < unknown.size(); ++i)
            out += (i ? (i + 1 == unknown.size() ? " and " : ", ") : "") + unknown[i];
    }
    return out;
}

}  // namespace osplint
