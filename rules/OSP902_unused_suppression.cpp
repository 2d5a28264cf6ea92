// OSP902 unused-suppression: a rule ID in an osplint directive that silenced
// no finding. Off by default.
//
// The findings come from the suppression filter (src/engine/suppress.cpp); this
// rule only carries the metadata.
#include "engine/rule.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{"OSP902", "unused-suppression", Severity::Info,
                         "An osplint suppression directive silences no finding", false, FixSafety::Safe};

class UnusedSuppression final : public RuleBase<UnusedSuppression> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    bool sees_plain_moves(const Config&) const override { return false; }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP902() { return std::make_unique<UnusedSuppression>(); }

}  // namespace osplint
