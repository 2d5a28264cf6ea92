// Every rule osplint has, in ID order. The list is generated at configure time
// from the rule files (rules/OSPnnn_*.cpp, each defining make_rule_OSPnnn()),
// so adding a rule is adding its file, its doc (docs/rules/OSPnnn.md) and its
// fixtures (tests/rules/OSPnnn/).
#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "engine/rule.h"

namespace osplint {

// The built-in rules.
const RuleRegistry& builtin_rules();

// Shorthands on the built-in set.
inline const std::vector<RuleMeta>& all_rules() { return builtin_rules().all(); }
inline const RuleMeta* find_rule(std::string_view id) { return builtin_rules().find(id); }

}  // namespace osplint
