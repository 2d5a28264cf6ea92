#include "registry.h"

namespace osplint {

#define OSPLINT_RULE(id) std::unique_ptr<Rule> make_rule_##id();
#include "rules_list.inc"
#undef OSPLINT_RULE

std::vector<std::unique_ptr<Rule>> make_rules() {
    std::vector<std::unique_ptr<Rule>> out;
#define OSPLINT_RULE(id) out.push_back(make_rule_##id());
#include "rules_list.inc"
#undef OSPLINT_RULE
    return out;
}

const std::vector<RuleMeta>& all_rules() {
    static const std::vector<RuleMeta> metas = [] {
        std::vector<RuleMeta> v;
        for (const auto& r : make_rules()) v.push_back(r->meta());
        return v;
    }();
    return metas;
}

const RuleMeta* find_rule(std::string_view id) {
    for (const auto& m : all_rules())
        if (m.id == id) return &m;
    return nullptr;
}

bool rule_matches(std::string_view id, std::string_view pattern) {
    return !pattern.empty() && id.substr(0, pattern.size()) == pattern;
}

}  // namespace osplint
