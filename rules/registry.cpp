#include "rules/registry.h"

namespace osplint {

#define OSPLINT_RULE(id) std::unique_ptr<Rule> make_rule_##id();
#include "rules_list.inc"
#undef OSPLINT_RULE

namespace {

class BuiltinRules final : public RuleRegistry {
public:
    BuiltinRules() {
        for (const auto& r : make_all()) metas_.push_back(r->meta());
    }
    const std::vector<RuleMeta>& all() const override { return metas_; }
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
