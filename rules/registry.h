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

// Fresh instances of every rule (rules may keep state while a file is checked).
std::vector<std::unique_ptr<Rule>> make_rules();
// Metadata of every rule, in ID order.
const std::vector<RuleMeta>& all_rules();
const RuleMeta* find_rule(std::string_view id);
// Rule IDs selected by a list of IDs or prefixes ("OSP2", "OSP104").
bool rule_matches(std::string_view id, std::string_view pattern);

}  // namespace osplint
