// OSP901 unknown-rule-in-suppression: an osplint directive that cannot be
// honoured (unknown rule ID, a rule that cannot be suppressed, malformed text).
//
// The findings come from the suppression filter (src/engine/suppress.cpp),
// which reads the file's directives before the walk and reports at the end of
// the file; this rule only carries the metadata so that the rule is listed,
// documented and configurable.
#include "engine/rule.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = kBadSuppressionRule,
    .name = "unknown-rule-in-suppression",
    .severity = Severity::Warning,
    .summary = "An osplint suppression directive names an unknown or unsuppressible rule, or is malformed",
    .category = RuleCategory::Directive,
    .suppressible = false,
};

class UnknownRuleInSuppression final : public RuleBase<UnknownRuleInSuppression> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): it sees no block.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP901() { return std::make_unique<UnknownRuleInSuppression>(); }

}  // namespace osplint
