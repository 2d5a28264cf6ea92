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

std::string_view category_name(RuleCategory c) {
    switch (c) {
        case RuleCategory::Alarm: return "alarm";
        case RuleCategory::WrongMotion: return "wrong-motion";
        case RuleCategory::Suspicious: return "suspicious";
        case RuleCategory::Directive: return "directive";
    }
    return "suspicious";
}

std::string_view status_name(RuleStatus s) { return s == RuleStatus::Preview ? "preview" : "stable"; }

std::string rule_doc_header(const RuleMeta& m) {
    const std::string id(m.id);
    const std::string severity(severity_name(m.severity));
    std::string h = "**Default severity:** " + severity + ". **Category:** [" + std::string(category_name(m.category)) +
                    "](README.md#categories). **Since:** " + std::string(m.since) + ".";
    if (m.status == RuleStatus::Preview)
        h += "\nPreview: its findings may still change; it runs only when a configuration or `--select` names it.";
    if (!m.enabled_by_default)
        h += "\nOff by default: enable it with `[rules] " + id + " = \"" + severity + "\"`" +
             (m.analysis_switch.empty() ? std::string() : ", `[analysis] " + std::string(m.analysis_switch) + " = true`") +
             " or `--select " + id + "`.";
    if (m.fix == FixSafety::Safe) h += "\nFix available (safe: `osplint check --fix` applies it).";
    if (m.fix == FixSafety::Unsafe)
        h += "\nFix available (unsafe: it changes what the machine does; `--fix --unsafe-fixes` applies it, editors "
             "offer it).";
    if (m.reports_may)
        h += "\nAlso reports what may happen on some paths only ([may findings](README.md#what-holds-on-some-paths-only-may-findings)).";
    if (!m.suppressible) h += "\nCannot be suppressed by a directive.";
    if (!m.selected_by_prefix)
        h += " `--ignore` and ID prefixes leave it on; `[rules] " + id + " = \"off\"` turns it off.";
    return h;
}

const std::vector<RetiredRule>& RuleRegistry::retired() const {
    static const std::vector<RetiredRule> none;
    return none;
}

RuleIdentities RuleRegistry::identities() const {
    RuleIdentities v;
    for (const auto& m : all())
        v.push_back({m.id, m.name, m.severity, m.enabled_by_default, m.selected_by_prefix, false, {},
                     m.analysis_switch});
    for (const auto& r : retired()) v.push_back({r.id, r.name, Severity::Warning, false, false, true, r.replaced_by, {}});
    return v;
}

const RuleMeta* RuleRegistry::resolve(std::string_view key) const {
    const RuleIdentities ids = identities();
    const RuleIdentity* r = resolve_rule(ids, key);
    return r ? find(r->id) : nullptr;
}

bool RuleRegistry::is_retired(std::string_view key) const {
    const RuleIdentities ids = identities();
    return retired_rule(ids, key) != nullptr;
}

std::string RuleRegistry::suggestion(std::string_view key) const { return rule_suggestion(identities(), key); }

bool rule_matches(std::string_view id, std::string_view pattern) {
    return !pattern.empty() && id.substr(0, pattern.size()) == pattern;
}

}  // namespace osplint
