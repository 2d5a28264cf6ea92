#include "rules/registry.h"

namespace osplint {

#define OSPLINT_RULE(id) std::unique_ptr<Rule> make_rule_##id();
#include "rules_list.inc"
#undef OSPLINT_RULE

namespace {

// Rule IDs that name no rule any more (IDs are never reused). To retire a
// rule: delete its file, keep its doc page with a note of what became of it,
// and add it here, with the ID that replaces it when it was renamed or merged
// (configurations, command lines and directives that name it then keep
// working, and OSP901 asks to write the new ID), or none when it was removed
// (they are then told so).
const std::vector<RetiredRule> kRetired = {};

class BuiltinRules final : public RuleRegistry {
public:
    BuiltinRules() {
        for (const auto& r : make_all()) metas_.push_back(r->meta());
    }
    const std::vector<RuleMeta>& all() const override { return metas_; }
    const std::vector<RetiredRule>& retired() const override { return kRetired; }
    std::vector<std::unique_ptr<Rule>> make_all() const override {
        std::vector<std::unique_ptr<Rule>> out;
#define OSPLINT_RULE(id) out.push_back(make_rule_##id());
#include "rules_list.inc"
#undef OSPLINT_RULE
        return out;
    }

private:
    std::vector<RuleMeta> metas_;
};

}  // namespace

const RuleRegistry& builtin_rules() {
    static const BuiltinRules rules;
    return rules;
}

}  // namespace osplint
