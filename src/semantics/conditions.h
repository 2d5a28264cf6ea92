// Deciding the atoms of the catalog's `when` conditions (catalog/condition.h)
// that read the modal state at a call: the plane, G90/G91, the spindle and
// cutter-radius compensation. What the state does not know is Unknown.
#pragma once

#include "catalog/condition.h"
#include "semantics/modal.h"

namespace osplint {

// Tri::Unknown as well for atoms that are not about the modal state (given:,
// NAME=value, M52/M53/M54): their callers decide those from the call.
Tri modal_atom(const ConditionAtom& atom, const ModalState& before);

}  // namespace osplint
