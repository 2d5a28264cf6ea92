// Subprogram summaries (see summary.h).
#include "semantics/summary.h"

#include <vector>

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

}  // namespace

ModalState summary_probe(int which) {
    ModalState s;  // a subprogram's entry: nothing known
    s.distance = Val<Distance>::of(which == 0 ? Distance::Absolute : Distance::Incremental);
    s.plane = Val<Plane>::of(which == 0 ? Plane::G17 : Plane::G18);
    s.units = Val<Units>::of(which == 0 ? Units::Mm : Units::Inch);
    s.motion = Val<int>::of(which == 0 ? 0 : 1);
    return s;
}

SubprogramSummary summarize(const ModalState* end0, const ModalState* end1) {
    const ModalState in0 = summary_probe(0), in1 = summary_probe(1);
    SubprogramSummary s;
    s.distance = effect(in0.distance, in1.distance, end0, end1, &ModalState::distance);
    s.plane = effect(in0.plane, in1.plane, end0, end1, &ModalState::plane);
    s.units = effect(in0.units, in1.units, end0, end1, &ModalState::units);
    s.motion = effect(in0.motion, in1.motion, end0, end1, &ModalState::motion);
    return s;
}

void apply_summary(const SubprogramSummary& summary, ModalState& s) {
    if (summary.changes_anything()) s.modes_from = &summary;
    apply(summary.distance, s.distance);
    apply(summary.plane, s.plane);
    apply(summary.units, s.units);
    apply(summary.motion, s.motion);
}

bool SubprogramSummary::changes_anything() const {
    return distance.kind != ModeEffect<Distance>::Kind::Kept || plane.kind != ModeEffect<Plane>::Kind::Kept ||
           units.kind != ModeEffect<Units>::Kind::Kept || motion.kind != ModeEffect<int>::Kind::Kept;
}

std::string SubprogramSummary::describe() const {
    std::vector<std::string> parts;
    using D = ModeEffect<Distance>::Kind;
    if (distance.kind == D::Set) parts.push_back(distance.value == Distance::Absolute ? "G90" : "G91");
    if (plane.kind == ModeEffect<Plane>::Kind::Set) parts.push_back(plane_name(plane.value));
    if (units.kind == ModeEffect<Units>::Kind::Set) parts.push_back(units.value == Units::Mm ? "G21 (mm)" : "G20 (inch)");
    if (motion.kind == ModeEffect<int>::Kind::Set) parts.push_back("G" + std::to_string(motion.value));
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
    if (!unknown.empty()) {
        if (!out.empty()) out += "; ";
        out += "may change ";
        for (size_t i = 0; i < unknown.size(); ++i)
            out += (i ? (i + 1 == unknown.size() ? " and " : ", ") : "") + unknown[i];
    }
    return out;
}

}  // namespace osplint
