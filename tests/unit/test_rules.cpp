// Rule fixtures, rule docs and examples.
//
// * tests/rules/OSPnnn/*: each program runs with ONLY that rule enabled and the
//   configuration of its directory (an osplint.toml there, else the defaults);
//   every finding must be expected inline and every expectation found.
// * docs/rules/OSPnnn.md: the "Problematic program" example fires the rule and
//   the "Correct program" example does not.
// * examples/: with every rule enabled, findings match the inline expectations
//   exactly; the clean examples have none at warning or error.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>

#include "support/embedded.h"
#include "engine/workspace.h"
#include "expectations.h"
#include "rules/registry.h"

namespace fs = std::filesystem;
using namespace osplint;
using namespace osplint::testing;

namespace {

fs::path source_dir() { return fs::path(OSPLINT_SOURCE_DIR); }

Config config_for(const fs::path& dir) {
    if (fs::exists(dir / "osplint.toml")) return load_config(dir / "osplint.toml");
    return Config{};
}

std::vector<fs::path> programs_in(const fs::path& dir) {
    std::vector<fs::path> out;
    if (!fs::exists(dir)) return out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && e.path().extension() != ".toml" && e.path().extension() != ".md") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

// Fenced ```osp blocks under a heading of the doc.
std::optional<std::string> example_under(std::string_view doc, std::string_view heading) {
    size_t h = doc.find(heading);
    if (h == std::string_view::npos) return std::nullopt;
    size_t open = doc.find("```osp", h);
    if (open == std::string_view::npos) return std::nullopt;
    size_t start = doc.find('\n', open);
    size_t close = doc.find("\n```", start);
    if (start == std::string_view::npos || close == std::string_view::npos) return std::nullopt;
    return std::string(doc.substr(start + 1, close - start));
}

bool cli_is_program(const fs::path& p) {
    std::string ext = p.extension().string();
    for (auto& c : ext) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return ext == ".MIN" || ext == ".SSB" || ext == ".SUB" || ext == ".SDF" || ext == ".LIB" || ext == ".NC";
}

// The fixes of a rule's findings are what its metadata says.
void check_fixes_agree(const RuleMeta& meta, const std::vector<Diagnostic>& found) {
    for (const auto& d : found) {
        if (meta.fix == FixSafety::None) CHECK_MESSAGE(d.fixes.empty(), d.rule << " offers a fix its metadata does not declare");
        for (const auto& f : d.fixes)
            CHECK_MESSAGE(f.safe == (meta.fix == FixSafety::Safe),
                          "fix '" << f.title << "' is " << (f.safe ? "safe" : "unsafe") << ", not as its metadata says");
    }
}

// The rules the rule tests look at: every one, or the one OSPLINT_ONLY_RULE
// names (scripts/quick-test OSP104).
std::vector<RuleMeta> rules_under_test() {
    std::vector<RuleMeta> out;
    const char* only = std::getenv("OSPLINT_ONLY_RULE");
    for (const auto& m : all_rules())
        if (!only || !*only || m.id == only || m.name == only) out.push_back(m);
    REQUIRE_MESSAGE(!out.empty(), "no rule " << std::string(only ? only : ""));
    return out;
}

}  // namespace

TEST_CASE("every rule doc's header is the one its metadata makes") {
    // OSPLINT_UPDATE_SNAPSHOTS=1 writes the headers instead (scripts/update-snapshots).
    const char* update = std::getenv("OSPLINT_UPDATE_SNAPSHOTS");
    const bool updating = update && *update && std::string(update) != "0";
    for (const auto& meta : rules_under_test()) {
        CAPTURE(meta.id);
        if (meta.status == RuleStatus::Preview)
            CHECK_MESSAGE(!meta.enabled_by_default, "a preview rule must be off by default");
        const fs::path file = source_dir() / "docs" / "rules" / (std::string(meta.id) + ".md");
        std::string doc = read_file(file);
        REQUIRE_MESSAGE(!doc.empty(), "missing " << file.string());
        CHECK(doc.substr(0, doc.find('\n')) == "# " + std::string(meta.id) + " " + std::string(meta.name));
        const size_t at = doc.find("**Default severity:** ");
        REQUIRE_MESSAGE(at != std::string::npos, "no **Default severity:** paragraph in " << file.string());
        const size_t end = doc.find("\n\n", at);
        REQUIRE(end != std::string::npos);
        const std::string header = doc.substr(at, end - at);
        const std::string expected = rule_doc_header(meta);
        if (header == expected) continue;
        if (updating) {
            doc.replace(at, end - at, expected);
            std::ofstream(file, std::ios::binary) << doc;
            MESSAGE("updated the header of " << file.string());
            continue;
        }
        FAIL_CHECK(file.string() << ": the header is not the one the rule's metadata makes\n-- written:\n"
                                 << header << "\n-- expected:\n"
                                 << expected << "\n(scripts/update-snapshots " << meta.id << " writes it)");
    }
}

TEST_CASE("every rule has fixtures that pass with only that rule enabled") {
    for (const auto& meta : rules_under_test()) {
        fs::path dir = source_dir() / "tests" / "rules" / std::string(meta.id);
        CAPTURE(meta.id);
        auto files = programs_in(dir);
        CHECK_MESSAGE(!files.empty(), "no fixtures in " << dir.string());
        size_t expected_total = 0;
        for (const auto& f : files) {
            CAPTURE(f.string());
            Config config = config_for(f.parent_path());
            AnalysisOptions options;
            options.only_rules = {std::string(meta.id)};
            ProgramNames names;
            SubprogramDirectories().add_names(f.parent_path(), names);
            options.known_programs = &names;
            std::string text = read_file(f);
            auto expected = parse_expectations(text);
            for (const auto& e : expected) CHECK_MESSAGE(e.rule == meta.id, "fixture expects another rule: " << e.rule);
            expected_total += expected.size();
            FileResult r = check_text(f.string(), text, config, options);
            auto problems = compare(expected, r.diagnostics, {});
            for (const auto& p : problems) FAIL_CHECK(p);
            check_fixes_agree(meta, r.diagnostics);
        }
        CHECK_MESSAGE(expected_total > 0, "the fixtures of " << meta.id << " never expect it to fire");
    }
}

TEST_CASE("every rule doc's problematic example fires the rule and its correct example does not") {
    for (const auto& meta : rules_under_test()) {
        CAPTURE(meta.id);
        auto doc = embedded::find("docs/rules/" + std::string(meta.id) + ".md");
        REQUIRE_MESSAGE(doc.has_value(), "missing docs/rules/" << meta.id << ".md");
        for (auto heading : {"## What it does", "## Why", "## Problematic program", "## Correct program"})
            CHECK_MESSAGE(doc->find(heading) != std::string_view::npos, "doc lacks " << heading);
        auto bad = example_under(*doc, "## Problematic program");
        auto good = example_under(*doc, "## Correct program");
        REQUIRE(bad.has_value());
        REQUIRE(good.has_value());
        Config config;  // docs use the default configuration unless they say [machine.travel]
        if (meta.id == "OSP301") config.travel['Z'] = {-300.0, 150.0};
        AnalysisOptions options;
        options.only_rules = {std::string(meta.id)};
        auto rb = check_text("problematic.MIN", *bad, config, options);
        auto rg = check_text("correct.MIN", *good, config, options);
        CHECK_MESSAGE(!rb.diagnostics.empty(), "problematic example does not fire");
        check_fixes_agree(meta, rb.diagnostics);
        for (const auto& d : rg.diagnostics) FAIL_CHECK("correct example fires: " << d.message);
    }
}

TEST_CASE("examples: findings match their inline expectations with every rule enabled") {
    fs::path dir = source_dir() / "examples";
    auto files = programs_in(dir);
    REQUIRE(!files.empty());
    for (const auto& f : files) {
        if (!cli_is_program(f)) continue;
        CAPTURE(f.string());
        Config config = config_for(dir);
        std::string text = read_file(f);
        auto expected = parse_expectations(text);
        FileResult r = check_text(f.string(), text, config);
        // Info-level findings are reported but not part of the contract of clean examples.
        std::vector<Diagnostic> relevant;
        std::set<Expected> expected_set(expected.begin(), expected.end());
        for (const auto& d : r.diagnostics) {
            bool is_expected = expected_set.count(Expected{d.range.start.line, d.rule, std::nullopt});
            if (d.severity != Severity::Info || is_expected) relevant.push_back(d);
        }
        for (const auto& p : compare(expected, relevant, {})) FAIL_CHECK(p);
    }
}

TEST_CASE("the manual's example OEX01: OSP101 for the missing PQ on each call, nothing else at warning or above") {
    fs::path f = source_dir() / "tests" / "programs" / "OEX01.MIN";
    FileResult r = check_text(f.string(), read_file(f), Config{});
    std::vector<uint32_t> lines;
    for (const auto& d : r.diagnostics) {
        if (d.severity == Severity::Info) continue;
        CHECK_MESSAGE(d.rule == "OSP101", "unexpected " << d.rule << ": " << d.message);
        CHECK(d.message.find("PQ") != std::string::npos);
        lines.push_back(d.range.start.line);
    }
    CHECK(lines == std::vector<uint32_t>{9, 14, 19, 24});  // the four OLAPX/OLAPY calls
}
