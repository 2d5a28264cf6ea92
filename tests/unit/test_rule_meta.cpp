// Rule metadata as data: categories and statuses, which blocks a rule is
// handed, and retired IDs (a renamed rule's old ID still names it; a removed
// one is said to be removed) in every place a user names a rule.
#include <doctest/doctest.h>

#include <string>

#include "api/config.h"
#include "engine/suppress.h"
#include "rules/registry.h"
#include "support/errors.h"
#include "syntax/outline.h"

using namespace osplint;

namespace {

// The built-in rules, with two retired IDs: OSP199 renamed to OSP104, OSP198 removed.
class WithRetired final : public RuleRegistry {
public:
    const std::vector<RuleMeta>& all() const override { return builtin_rules().all(); }
    std::vector<std::unique_ptr<Rule>> make_all() const override { return builtin_rules().make_all(); }
    const std::vector<RetiredRule>& retired() const override { return retired_; }

private:
    std::vector<RetiredRule> retired_ = {{"OSP199", "m52-in-call", "OSP104", "0.2.0"},
                                         {"OSP198", "old-check", "", "0.2.0"}};
};

}  // namespace

TEST_CASE("rule metadata: every rule has a category, a version, and sees plain moves only when it says so") {
    for (const auto& meta : builtin_rules().all()) {
        CAPTURE(meta.id);
        CHECK(!category_name(meta.category).empty());
        CHECK(!meta.since.empty());
        if (meta.status == RuleStatus::Preview) CHECK_FALSE(meta.enabled_by_default);
        if (meta.id.substr(0, 4) == "OSP9") CHECK(meta.category == RuleCategory::Directive);
    }
    // The rule that reports what does not parse, and the rules about the
    // directives themselves, cannot be silenced by a directive.
    CHECK_FALSE(builtin_rules().find(kSyntaxErrorRule)->suppressible);
    CHECK_FALSE(builtin_rules().find("OSP901")->suppressible);
    CHECK(builtin_rules().find("OSP104")->suppressible);
    // The same rule is out of reach of ID prefixes, --select and --ignore, by
    // its metadata: a prefix turns every other rule of its range off, not it.
    CHECK_FALSE(builtin_rules().find(kSyntaxErrorRule)->selected_by_prefix);
    const Config off = read_config_text("[rules]\nOSP0 = \"off\"\n", "osplint.toml", builtin_rules().identities());
    for (const auto& meta : builtin_rules().all()) {
        if (meta.id.substr(0, 4) != "OSP0") continue;
        CAPTURE(meta.id);
        CHECK(off.rule_severity.count(std::string(meta.id)) == (meta.selected_by_prefix ? 1u : 0u));
    }
    // A rule is handed plain moves (all, or those with a sequence name) when
    // its metadata says so (OSP301 decides from the configuration: only with
    // travel limits). A rule of the names takes them from their values.
    const Config config;
    int named = 0;
    for (const auto& rule : builtin_rules().make_all()) {
        const RuleBlocks blocks = rule->meta().blocks;
        if (rule->meta().id != "OSP301")
            CHECK_MESSAGE(rule->sees_plain_moves(config) == (blocks != RuleBlocks::Statements), rule->meta().id);
        if (blocks == RuleBlocks::Named) {
            ++named;
            CHECK_MESSAGE(rule->takes_plain_values(), rule->meta().id);
        }
    }
    CHECK(named == 2);  // OSP003, OSP006
}

TEST_CASE("retired rule IDs: a renamed one still names its rule, a removed one is said to be removed") {
    const WithRetired rules;
    REQUIRE(rules.resolve("OSP199"));
    CHECK(rules.resolve("OSP199")->id == "OSP104");
    CHECK(rules.resolve("m52-in-call")->id == "OSP104");
    CHECK(rules.is_retired("osp199"));
    CHECK_FALSE(rules.is_retired("OSP104"));
    CHECK(rules.resolve("OSP198") == nullptr);
    CHECK(rules.suggestion("OSP198") == " (OSP198 old-check was removed)");
    // Retired IDs are not suggested for a typo.
    CHECK(rules.suggestion("OSP19").find("OSP199") == std::string::npos);

    SUBCASE("in a configuration") {
        const RuleIdentities ids = rules.identities();
        const Config c = read_config_text("[rules]\nOSP199 = \"off\"\n", "osplint.toml", ids);
        REQUIRE(c.rule_severity.count("OSP104"));
        CHECK_FALSE(c.rule_severity.at("OSP104").has_value());
        CHECK_THROWS_WITH_AS(read_config_text("[rules]\nOSP198 = \"off\"\n", "osplint.toml", ids),
                             doctest::Contains("OSP198 old-check was removed"), ConfigError);
        // A prefix does not reach a retired ID.
        const Config p = read_config_text("[rules]\nOSP1 = \"off\"\n", "osplint.toml", ids);
        CHECK_FALSE(p.rule_severity.count("OSP199"));
    }
    SUBCASE("in a suppression directive") {
        const std::string text = "O1\nCALL OZAGR PR=5 PZ=-20 PI=12 M52 (osplint: disable=OSP199)\nM30\n";
        MemorySource src(text);
        const FileOutline outline = outline_file(src, {});
        Config config;
        config.rule_severity["OSP901"] = Severity::Warning;
        SuppressionFilter filter(outline, rules, config, {});
        Diagnostic d;
        d.rule = "OSP104";
        d.range.start.line = 2;
        d.range.end.line = 2;
        SuppressedDiagnostic out;
        CHECK(filter.silence(d, out));  // the old ID still silences the rule
        const std::vector<Diagnostic> notes = filter.finish();
        REQUIRE(notes.size() == 1);
        CHECK(notes[0].rule == "OSP901");
        CHECK(notes[0].message.find("'OSP199' is a retired name of OSP104") != std::string::npos);
    }
}

TEST_CASE("rules: every rule that keeps state of its own compares it (an analysis after an edit may then end early)") {
    for (const auto& r : builtin_rules().make_all()) {
        INFO(r->meta().id);
        CHECK(r->compares_state());
        const auto copy = r->clone();
        CHECK(r->same_state(*copy));
    }
}
