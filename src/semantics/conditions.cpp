#include "semantics/conditions.h"

namespace osplint {

namespace {
template <class T>
Tri is(const Val<T>& v, const T& want) {
    if (!v.known) return Tri::Unknown;
    return v.value == want ? Tri::True : Tri::False;
}
}  // namespace

Tri modal_atom(const ConditionAtom& a, const ModalState& before) {
    using K = ConditionAtom::Kind;
    switch (a.kind) {
        case K::Plane:
            return is(before.plane, a.number == 17 ? Plane::G17 : a.number == 18 ? Plane::G18 : Plane::G19);
        case K::Distance:
            return is(before.distance, a.number == 90 ? Distance::Absolute : Distance::Incremental);
        case K::Spindle: {
            // M843 turns the spindle forward and M845 stops it (modal.h).
            return is(before.spindle, a.number);
        }
        case K::CutterComp: return is(before.cutter_comp, a.number);
        case K::MCode:
        case K::Given:
        case K::ArgEquals: return Tri::Unknown;
    }
    return Tri::Unknown;
}

}  // namespace osplint
