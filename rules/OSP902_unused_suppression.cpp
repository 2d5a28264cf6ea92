// OSP902 unused-suppression: a rule ID in an osplint directive that silenced
// no finding. Off by default.
//
// The findings come from the suppression filter (src/engine/suppress.cpp); this
// rule only carries the metadata.
#include "engine/rule.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = kUnusedSuppressionRule,
    .name = "unused-suppression",
    .severity = Severity::Info,
    .summary = "An osplint suppression directive silences no finding",
    .category = RuleCategory::Directive,
    .enabled_by_default = false,
    .fix = FixSafety::Safe,
    .suppressible = false,
};

class UnusedSuppression final : public RuleBase<UnusedSuppression> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): it sees no block.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP902() { return std::make_unique<UnusedSuppression>(); }

}  // namespace osplint
