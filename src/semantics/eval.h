// Constant evaluation of expressions against known variable values.
#pragma once

#include <optional>
#include <string>

#include "semantics/modal.h"
#include "syntax/model.h"

namespace osplint {

// The key a variable node names when its subscripts are known: "VC12" for VC12
// and VC[12] (and VC[VC1] when VC1 is known), "PX" for a local, "VTOFX[16]" for
// a subscripted system variable. nullopt when a subscript is unknown.
std::optional<std::string> variable_key(const Block& block, ExprId var, const ModalState& state);

// Numeric value of an expression, or nullopt when any part is unknown (system
// variables, unset locals, EMPTY, strings, division by zero, a literal or a
// result too large for a double, ...). A value is always finite.
std::optional<double> evaluate(const Block& block, ExprId e, const ModalState& state);

// Common variable number of a key ("VC120" -> 120), or nullopt.
std::optional<int> common_variable_number(std::string_view key);

}  // namespace osplint
