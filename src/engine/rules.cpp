#include <algorithm>

#include "engine/rule.h"
#include "semantics/config.h"

namespace osplint {

bool rule_runs(const RuleMeta& meta, const Config& config, const std::vector<std::string>& only) {
    if (!only.empty()) return std::find(only.begin(), only.end(), meta.id) != only.end();
    return config.severity_of(meta.id, meta.severity, meta.enabled_by_default).has_value();
}

std::vector<std::unique_ptr<Rule>> select_rules(const RuleRegistry& registry, const Config& config,
                                                const std::vector<std::string>& only) {
    std::vector<std::unique_ptr<Rule>> out;
    for (auto& r : registry.make_all())
        if (rule_runs(r->meta(), config, only)) out.push_back(std::move(r));
    return out;
}

RuleIdentities RuleRegistry::identities() const {
    RuleIdentities v;
    for (const auto& m : all()) v.push_back({m.id, m.name, m.severity, m.enabled_by_default});
    return v;
}

const RuleMeta* RuleRegistry::resolve(std::string_view key) const {
    const RuleIdentities ids = identities();
    const RuleIdentity* r = resolve_rule(ids, key);
    return r ? find(r->id) : nullptr;
}

std::string RuleRegistry::suggestion(std::string_view key) const { return rule_suggestion(identities(), key); }

bool rule_matches(std::string_view id, std::string_view pattern) {
    return !pattern.empty() && id.substr(0, pattern.size()) == pattern;
}

}  // namespace osplint
