// Rule fixtures, rule docs and examples.
//
// * tests/rules/OSPnnn/*: each program runs with ONLY that rule enabled and the
//   configuration of its directory (an osplint.toml there, else the defaults);
//   every finding must be expected inline and every expectation found.
// * Beside each of those programs, NAME.snap pins every finding in full
//   (snapshot.h), and NAME.fixed, when the rule offers fixes there, the program
//   with all of them applied. OSPLINT_UPDATE_SNAPSHOTS=1 rewrites both
//   (scripts/update-snapshots [OSPnnn]).
// * docs/rules/OSPnnn.md: the "Problematic program" example fires the rule and
//   the "Correct program" example does not.
// * examples/: with every rule enabled, findings match the inline expectations
//   exactly; the clean examples have none at warning or error.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>

#include "api/fix.h"
#include "support/embedded.h"
#include "engine/summaries.h"
#include "engine/workspace.h"
#include "expectations.h"
#include "rules/registry.h"
#include "snapshot.h"

namespace fs = std::filesystem;
using namespace osplint;
using namespace osplint::testing;

namespace {

fs::path source_dir() { return fs::path(OSPLINT_SOURCE_DIR); }

Config config_for(const fs::path& dir) {
    if (fs::exists(dir / "osplint.toml")) return load_config(dir / "osplint.toml");
    return Config{};
}

// The snapshot and the fixed program pinned beside a fixture.
constexpr std::string_view kSnapshotSuffix = ".snap";
constexpr std::string_view kFixedSuffix = ".fixed";

bool is_pinned_output(const fs::path& p) { return p.extension() == kSnapshotSuffix || p.extension() == kFixedSuffix; }

std::vector<fs::path> programs_in(const fs::path& dir) {
    std::vector<fs::path> out;
    if (!fs::exists(dir)) return out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && !is_pinned_output(e.path()) && e.path().extension() != ".toml" &&
            e.path().extension() != ".md")
            out.push_back(e.path());
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

// How a fixture of `rule` runs: only that rule, the osplint.toml of its
// folder, and the names of the subprograms beside it.
// A fixture is checked as `osplint check` checks a file: the subprograms it
// calls, of its own or in the subprogram files beside it, are summarised.
struct FixtureRun {
    Config config;
    ProgramNames names;
    SubprogramDirectories dirs;
    SubprogramSummaries summaries{builtin_rules(), dirs};
    AnalysisOptions options;
    FixtureRun(const fs::path& fixture, std::string_view rule) : config(config_for(fixture.parent_path())) {
        options.only_rules = {std::string(rule)};
        dirs.add_names(fixture.parent_path(), names);
        options.known_programs = &names;
        options.summaries = &summaries;
    }
    FixtureRun(const FixtureRun&) = delete;
    FixtureRun& operator=(const FixtureRun&) = delete;
};

fs::path relative_to_source(const fs::path& p) { return fs::relative(p, source_dir()); }

// OSPLINT_UPDATE_SNAPSHOTS=1: the snapshot tests rewrite the pinned files
// rather than compare them.
bool updating_snapshots() {
    const char* u = std::getenv("OSPLINT_UPDATE_SNAPSHOTS");
    return u && *u && std::string_view(u) != "0";
}

std::string update_command(std::string_view rule) { return "scripts/update-snapshots " + std::string(rule); }

void write_file(const fs::path& p, std::string_view text) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << text;
    REQUIRE_MESSAGE(out.flush().good(), "cannot write " << p.string());
}

// Compares what a fixture gives now with the file that pins it (or rewrites
// the file when updating).
void check_pinned(const fs::path& pinned, const std::string& actual, std::string_view rule, const fs::path& fixture) {
    const fs::path shown = relative_to_source(pinned);
    const bool exists = fs::exists(pinned);
    if (updating_snapshots()) {
        if (!exists || read_file(pinned) != actual) {
            write_file(pinned, actual);
            MESSAGE(std::string(exists ? "updated " : "wrote ") << shown.string());
        }
        return;
    }
    if (!exists) {
        FAIL_CHECK(shown.string() << " is missing: run `" << update_command(rule) << "` to write it, and read it");
        return;
    }
    const std::string expected = read_file(pinned);
    if (expected != actual)
        FAIL_CHECK(shown.string() << " does not match what " << relative_to_source(fixture).string()
                                  << " gives now (- the file, + now):\n"
                                  << line_diff(expected, actual) << "If the change is intended, run `"
                                  << update_command(rule) << "` and read the new file.");
}

// A pinned file that should not be there (its fixture is gone, or it no
// longer has fixes): a failure, or removed when updating.
void check_unwanted(const fs::path& pinned, std::string_view rule, std::string_view why) {
    if (!fs::exists(pinned)) return;
    if (updating_snapshots()) {
        fs::remove(pinned);
        MESSAGE("removed " << relative_to_source(pinned).string());
        return;
    }
    FAIL_CHECK(relative_to_source(pinned).string() << " should not be there (" << why << "): run `"
                                                   << update_command(rule) << "` to remove it");
}

uint32_t newlines(std::string_view s) { return static_cast<uint32_t>(std::count(s.begin(), s.end(), '\n')); }

// The line that `line` (starting at byte `offset` of `original`) becomes once
// `edits` are applied.
uint32_t line_after_edits(std::string_view original, const std::vector<Edit>& edits, uint32_t offset, uint32_t line) {
    int64_t shift = 0;
    for (const auto& e : edits)
        if (e.end <= offset)
            shift += int64_t(newlines(e.text)) - int64_t(newlines(original.substr(e.begin, e.end - e.begin)));
    return static_cast<uint32_t>(int64_t(line) + shift);
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
            const FixtureRun run(f, meta.id);
            std::string text = read_file(f);
            auto expected = parse_expectations(text);
            for (const auto& e : expected) CHECK_MESSAGE(e.rule == meta.id, "fixture expects another rule: " << e.rule);
            expected_total += expected.size();
            FileResult r = check_text(f.string(), text, run.config, run.options);
            auto problems = compare(expected, r.diagnostics, {});
            for (const auto& p : problems) FAIL_CHECK(p);
            check_fixes_agree(meta, r.diagnostics);
        }
        CHECK_MESSAGE(expected_total > 0, "the fixtures of " << meta.id << " never expect it to fire");
    }
}

TEST_CASE("every rule fixture's findings and fixed program are what its .snap and .fixed files pin") {
    for (const auto& meta : rules_under_test()) {
        CAPTURE(meta.id);
        const fs::path dir = source_dir() / "tests" / "rules" / std::string(meta.id);
        const auto files = programs_in(dir);
        std::set<fs::path> fixtures(files.begin(), files.end());
        // A pinned file belongs to a fixture.
        if (fs::exists(dir))
            for (const auto& e : fs::recursive_directory_iterator(dir))
                if (e.is_regular_file() && is_pinned_output(e.path()) &&
                    !fixtures.count(fs::path(e.path()).replace_extension()))
                    check_unwanted(e.path(), meta.id, "no fixture of that name");
        for (const auto& f : files) {
            CAPTURE(f.string());
            const FixtureRun run(f, meta.id);
            const std::string text = read_file(f);
            const FileResult r = check_text(f.string(), text, run.config, run.options);
            const std::string name = fs::relative(f, dir).generic_string();
            check_pinned(f.string() + std::string(kSnapshotSuffix), snapshot_of(meta.id, name, r.diagnostics), meta.id, f);

            const fs::path fixed_path = f.string() + std::string(kFixedSuffix);
            const bool any_fix = std::any_of(r.diagnostics.begin(), r.diagnostics.end(),
                                             [](const Diagnostic& d) { return !d.fixes.empty(); });
            if (!any_fix) {
                check_unwanted(fixed_path, meta.id, "the rule offers no fix on its fixture");
                continue;
            }
            // Every fix, safe and unsafe, as `osplint check --fix --unsafe-fixes` applies them.
            MemorySource original(text);
            const FixPlan plan = plan_fixes(f.string(), original, run.config, run.options, true);
            REQUIRE_MESSAGE(plan.refused.empty(), "the fixes are not applied: " << plan.refused);
            REQUIRE_MESSAGE(!plan.edits.empty(), "the findings offer fixes, and none is applied");
            std::string fixed, error;
            REQUIRE_MESSAGE(apply_edits(original, plan.edits, [&](std::string_view piece) {
                fixed += piece;
                return true;
            }, error), error);
            check_pinned(fixed_path, fixed, meta.id, f);

            // The fixed program parses.
            AnalysisOptions syntax = run.options;
            syntax.only_rules = {std::string(kSyntaxErrorRule)};
            for (const auto& d : check_text(f.string(), fixed, run.config, syntax).diagnostics)
                FAIL_CHECK("the fixed program has a syntax error on line " << d.range.start.line << ": " << d.message);

            // Checked again, it has exactly the findings that had no fix, each
            // on its line as the edits moved it: every finding with a fix is
            // gone, and the fixes made no new one.
            std::multiset<std::pair<uint32_t, std::string>> left, expected_left;
            for (const auto& d : r.diagnostics)
                if (d.fixes.empty())
                    expected_left.insert({line_after_edits(text, plan.edits, d.range.bytes.begin, d.range.start.line),
                                          d.message});
            for (const auto& d : check_text(f.string(), fixed, run.config, run.options).diagnostics)
                left.insert({d.range.start.line, d.message});
            std::vector<std::pair<uint32_t, std::string>> made, gone;
            std::set_difference(left.begin(), left.end(), expected_left.begin(), expected_left.end(),
                                std::back_inserter(made));
            std::set_difference(expected_left.begin(), expected_left.end(), left.begin(), left.end(),
                                std::back_inserter(gone));
            for (const auto& [line, message] : made)
                FAIL_CHECK("the fixed program still has, or now has, a finding on line " << line << ": " << message);
            for (const auto& [line, message] : gone)
                FAIL_CHECK("a finding without a fix is gone from the fixed program (line " << line << "): " << message);
        }
    }
}

TEST_CASE("a finding's line after the fixes: moved by the lines the edits before it add or remove") {
    const std::string text = "A\nB\nC\n";
    CHECK(line_after_edits(text, {{2, 2, "X\n"}}, 2, 2) == 3);  // a line inserted where the finding starts
    CHECK(line_after_edits(text, {{2, 2, "X\n"}}, 0, 1) == 1);
    CHECK(line_after_edits(text, {{0, 2, ""}, {4, 4, "Y\nZ\n"}}, 4, 3) == 4);
    CHECK(line_after_edits(text, {{0, 2, ""}}, 2, 2) == 1);
    CHECK(line_after_edits(text, {{4, 5, "C"}}, 2, 2) == 2);  // an edit after it
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
