// Suppression directives: the grammar, every form, OSP901/OSP902, and the
// fingerprints baselines rely on.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include "output/baseline.h"
#include "engine/fingerprint.h"
#include "engine/suppress.h"
#include "api/check.h"
#include "api/config.h"

using namespace osplint;

namespace {

std::vector<const Diagnostic*> of_rule(const FileResult& r, std::string_view rule) {
    std::vector<const Diagnostic*> out;
    for (const auto& d : r.diagnostics)
        if (d.rule == rule) out.push_back(&d);
    return out;
}

std::vector<const SuppressedDiagnostic*> suppressed_of(const FileResult& r, std::string_view rule) {
    std::vector<const SuppressedDiagnostic*> out;
    for (const auto& s : r.suppressed)
        if (s.diagnostic.rule == rule) out.push_back(&s);
    return out;
}

Config with_unused() {
    Config c;
    c.rule_severity["OSP902"] = Severity::Info;
    return c;
}

DirectiveParse parse(std::string_view comment) { return parse_directive(comment, {0, static_cast<uint32_t>(comment.size())}); }

const std::string kM52 = "CALL OZAGR PR=5 PZ=-20 PI=12 M52";

}  // namespace

TEST_CASE("directive grammar: well-formed directives") {
    auto p = parse("(osplint: disable=OSP104,OSP108 -- checked with the setter )");
    REQUIRE(p.is_directive);
    REQUIRE(p.directive);
    CHECK(p.directive->action == SuppressionDirective::Action::Disable);
    REQUIRE(p.directive->ids.size() == 2);
    CHECK(p.directive->ids[0].text == "OSP104");
    CHECK(p.directive->ids[0].range.begin == 18);
    CHECK(p.directive->ids[0].range.end == 24);
    CHECK(p.directive->ids[1].text == "OSP108");
    CHECK(p.directive->reason == "checked with the setter");

    auto q = parse("(  OSPLINT :DISABLE-FILE = osp202 ,  OSP005)");
    REQUIRE(q.directive);
    CHECK(q.directive->action == SuppressionDirective::Action::DisableFile);
    REQUIRE(q.directive->ids.size() == 2);
    CHECK(q.directive->ids[0].text == "osp202");
    CHECK(q.directive->ids[1].text == "OSP005");
    CHECK(q.directive->reason.empty());

    // Without the closing parenthesis (an unterminated comment) the text still reads.
    auto u = parse("(osplint: disable=OSP104");
    REQUIRE(u.directive);
    CHECK(u.directive->ids[0].text == "OSP104");
}

TEST_CASE("directive grammar: comments that are not directives, and malformed ones") {
    CHECK_FALSE(parse("(T31 BACK BORE BAR)").is_directive);
    CHECK_FALSE(parse("(OSPLINT CHECKED 2024)").is_directive);
    CHECK_FALSE(parse("(OSPLINT)").is_directive);
    CHECK_FALSE(parse("(osplintx: disable=OSP104)").is_directive);

    auto no_eq = parse("(osplint: disable OSP104)");
    CHECK(no_eq.is_directive);
    CHECK_FALSE(no_eq.directive);
    CHECK(no_eq.error.find("'='") != std::string::npos);
    CHECK(no_eq.error_range.begin == 18);

    auto action = parse("(osplint: enable=OSP104)");
    CHECK_FALSE(action.directive);
    CHECK(action.error.find("'enable'") != std::string::npos);
    CHECK(action.error_range.begin == 10);
    CHECK(action.error_range.end == 16);

    auto no_comma = parse("(osplint: disable=OSP104 OSP108)");
    CHECK_FALSE(no_comma.directive);
    CHECK(no_comma.error_range.begin == 25);

    auto empty = parse("(osplint: disable=)");
    CHECK_FALSE(empty.directive);
    CHECK(empty.error.find("rule ID") != std::string::npos);

    auto trailing_comma = parse("(osplint: disable=OSP104, -- why)");
    CHECK_FALSE(trailing_comma.directive);
}

TEST_CASE("disable on a block with code silences the rule on that block only") {
    std::string text = "O1000\nG0 X50 Y30\n" + kM52 + " (osplint: disable=OSP104 -- setter checked the Z limit)\n" +
                       kM52 + "\nM30\n";
    FileResult r = check_text("A.MIN", text, Config{});
    auto left = of_rule(r, "OSP104");
    REQUIRE(left.size() == 1);
    CHECK(left[0]->range.start.line == 4);
    auto s = suppressed_of(r, "OSP104");
    REQUIRE(s.size() == 1);
    CHECK(s[0]->diagnostic.range.start.line == 3);
    CHECK(s[0]->reason == "setter checked the Z limit");
    CHECK(s[0]->kind == SuppressedDiagnostic::Kind::InSource);
    CHECK_FALSE(s[0]->file_scope);
    REQUIRE(s[0]->directive);
    CHECK(s[0]->directive->start.line == 3);
}

TEST_CASE("a directive alone on a line silences the next block with code") {
    std::string text = "O1000\nG0 X50 Y30\n(osplint: disable=OSP104,OSP108 -- both reviewed)\n\n(T31 BAR)\n" + kM52 +
                       " M8\n" + kM52 + " M8\nM30\n";
    FileResult r = check_text("A.MIN", text, Config{});
    // Line 6 is the next block with code: both rules silenced there; line 7 is not covered.
    for (const char* rule : {"OSP104", "OSP108"}) {
        CAPTURE(rule);
        auto left = of_rule(r, rule);
        REQUIRE(left.size() == 1);
        CHECK(left[0]->range.start.line == 7);
        auto s = suppressed_of(r, rule);
        REQUIRE(s.size() == 1);
        CHECK(s[0]->diagnostic.range.start.line == 6);
        CHECK(s[0]->reason == "both reviewed");
    }
}

TEST_CASE("disable-file silences the rule anywhere in the file, before and after the directive") {
    std::string text = "O1000\n" + kM52 + "\n(osplint: disable-file=OSP104 -- legacy programs)\nG0 X0\n" + kM52 +
                       "\nM30\n";
    FileResult r = check_text("A.MIN", text, Config{});
    CHECK(of_rule(r, "OSP104").empty());
    auto s = suppressed_of(r, "OSP104");
    REQUIRE(s.size() == 2);
    for (auto* x : s) {
        CHECK(x->file_scope);
        CHECK(x->reason == "legacy programs");
    }
}

TEST_CASE("an unknown rule ID is OSP901 at the ID's exact range") {
    std::string text = "O1000\nG0 X50 Y30 (osplint: disable=OSP104,OSP1O8 -- typo)\nM30\n";
    FileResult r = check_text("A.MIN", text, Config{});
    auto u = of_rule(r, "OSP901");
    REQUIRE(u.size() == 1);
    CHECK(u[0]->severity == Severity::Warning);
    CHECK(u[0]->name == "unknown-rule-in-suppression");
    CHECK(u[0]->range.bytes.begin == text.find("OSP1O8"));
    CHECK(u[0]->range.bytes.end == text.find("OSP1O8") + 6);
    CHECK(u[0]->range.start.line == 2);
    CHECK(u[0]->message.find("OSP1O8") != std::string::npos);
    CHECK_FALSE(u[0]->fingerprint.empty());
}

TEST_CASE("OSP001 cannot be suppressed, and naming it is OSP901 saying why") {
    std::string text = "O1000\n(osplint: disable=OSP001 -- I know)\nG1 X XPOS+25. F300\n"
                       "G1 X XPOS+25. F300 (osplint: disable-file=OSP001)\nM30\n";
    FileResult r = check_text("A.MIN", text, Config{});
    auto syntax = of_rule(r, "OSP001");
    CHECK(syntax.size() >= 2);
    CHECK(suppressed_of(r, "OSP001").empty());
    auto u = of_rule(r, "OSP901");
    REQUIRE(u.size() == 2);
    for (auto* d : u) CHECK(d->message.find("cannot be suppressed") != std::string::npos);
    CHECK(u[0]->range.bytes.begin == text.find("OSP001"));
}

TEST_CASE("OSP902 unused-suppression: off by default, then reported per unused ID") {
    std::string text = "O1000\nG0 X50 Y30 (osplint: disable=OSP104 -- old)\n" + kM52 +
                       " (osplint: disable=OSP104,OSP108)\nM30\n(osplint: disable=OSP104)\n";
    FileResult off = check_text("A.MIN", text, Config{});
    CHECK(of_rule(off, "OSP902").empty());
    CHECK(suppressed_of(off, "OSP104").size() == 1);

    FileResult on = check_text("A.MIN", text, with_unused());
    auto u = of_rule(on, "OSP902");
    REQUIRE(u.size() == 3);
    // Line 2: nothing to silence on that block; the fix drops the whole directive.
    CHECK(u[0]->range.start.line == 2);
    CHECK(u[0]->severity == Severity::Info);
    CHECK(u[0]->message.find("no OSP104 finding on this block") != std::string::npos);
    REQUIRE(u[0]->notes.size() == 1);
    CHECK(u[0]->notes[0].message == "reason given: old");
    REQUIRE(u[0]->fixes.size() == 1);
    REQUIRE(u[0]->fixes[0].edits.size() == 1);
    const auto& cut = u[0]->fixes[0].edits[0].range.bytes;
    CHECK(text.substr(cut.begin, cut.size()) == " (osplint: disable=OSP104 -- old)");
    // Line 3: OSP104 is used, OSP108 is not (no M8): the fix drops only OSP108.
    CHECK(u[1]->range.start.line == 3);
    CHECK(u[1]->range.bytes.begin == text.find("OSP108"));
    REQUIRE(u[1]->fixes.size() == 1);
    const auto& cut2 = u[1]->fixes[0].edits[0].range.bytes;
    CHECK(text.substr(cut2.begin, cut2.size()) == ",OSP108");
    // Line 5: no block follows the directive.
    CHECK(u[2]->range.start.line == 5);
    CHECK(u[2]->message.find("no block follows") != std::string::npos);
}

TEST_CASE("OSP902 says when the suppressed rule did not run") {
    std::string text = "O1000\n" + kM52 + " (osplint: disable=OSP104)\nM30\n";
    Config c = with_unused();
    c.rule_severity["OSP104"] = std::nullopt;
    FileResult r = check_text("A.MIN", text, c);
    auto u = of_rule(r, "OSP902");
    REQUIRE(u.size() == 1);
    CHECK(u[0]->message.find("did not run") != std::string::npos);
}

TEST_CASE("a block directive takes the credit before a file directive") {
    std::string text = "(osplint: disable-file=OSP104)\nO1000\n" + kM52 + " (osplint: disable=OSP104)\nM30\n";
    FileResult r = check_text("A.MIN", text, with_unused());
    CHECK(of_rule(r, "OSP104").empty());
    auto u = of_rule(r, "OSP902");
    REQUIRE(u.size() == 1);
    CHECK(u[0]->range.start.line == 1);  // the file directive silenced nothing the block one did not
}

TEST_CASE("suppressions follow only_rules like every other rule") {
    std::string text = "O1000\n" + kM52 + " (osplint: disable=OSP104)\nG0 X0 (osplint: disable=OSP999)\nM30\n";
    AnalysisOptions only104;
    only104.only_rules = {"OSP104"};
    FileResult r = check_text("A.MIN", text, Config{}, only104);
    CHECK(r.diagnostics.empty());
    CHECK(r.suppressed.size() == 1);
    AnalysisOptions only901;
    only901.only_rules = {"OSP901"};
    FileResult u = check_text("A.MIN", text, Config{}, only901);
    REQUIRE(u.diagnostics.size() == 1);
    CHECK(u.diagnostics[0].rule == "OSP901");
}

TEST_CASE("fingerprints ignore line shifts and comments added to the block") {
    std::string base = "O1000\nG0 X50 Y30\n" + kM52 + " M8\nM30\n";
    std::string shifted = "(NEW HEADER LINE)\n\nO1000\nG0 X50 Y30\n" + kM52 +
                          " M8 (osplint: disable=OSP108 -- coolant checked)\nM30\n";
    FileResult a = check_text("A.MIN", base, Config{});
    FileResult b = check_text("A.MIN", shifted, Config{});
    auto fa = of_rule(a, "OSP104");
    auto fb = of_rule(b, "OSP104");
    REQUIRE(fa.size() == 1);
    REQUIRE(fb.size() == 1);
    CHECK(fa[0]->range.start.line == 3);
    CHECK(fb[0]->range.start.line == 5);
    CHECK(fa[0]->fingerprint == fb[0]->fingerprint);
    // A second identical block is a different finding (occurrence).
    std::string twice = "O1000\n" + kM52 + "\n" + kM52 + "\nM30\n";
    FileResult t = check_text("A.MIN", twice, Config{});
    auto ft = of_rule(t, "OSP104");
    REQUIRE(ft.size() == 2);
    CHECK(ft[0]->fingerprint != ft[1]->fingerprint);
}

TEST_CASE("baseline: findings survive a shifted file; a new mistake is reported") {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / "osplint-baseline-unit";
    fs::create_directories(dir);
    fs::path file = dir / "P.MIN";
    std::string before = "O1000\nG0 X50 Y30\n" + kM52 + "\nM30\n";
    std::vector<FileResult> first{check_text(file.string(), before, Config{})};
    REQUIRE_FALSE(first[0].diagnostics.empty());
    Baseline b = make_baseline(first, dir / "baseline.json");
    CHECK(b.entries.size() == first[0].diagnostics.size());
    CHECK(b.entries[0].path == "P.MIN");
    Baseline round = parse_baseline(render_baseline(b), "memory");
    CHECK(round.entries == b.entries);

    std::string after = "(REVISION B)\n" + before;
    after.insert(after.find("M30"), "CALL OZAGR PR=5 PZ=-20 PI=40 M52\n");
    std::vector<FileResult> second{check_text(file.string(), after, Config{})};
    size_t moved = apply_baseline(second, round, dir / "baseline.json");
    CHECK(moved == b.entries.size());
    auto left = of_rule(second[0], "OSP104");
    REQUIRE(left.size() == 1);
    CHECK(left[0]->range.start.line == 5);
    for (const auto& d : second[0].diagnostics) CHECK(d.range.start.line == 5);
    for (const auto& s : second[0].suppressed) CHECK(s.kind == SuppressedDiagnostic::Kind::Baseline);

    CHECK_THROWS(parse_baseline("{\"version\": 2, \"entries\": []}", "x"));
    CHECK_THROWS(parse_baseline("not json", "x"));
    fs::remove_all(dir);
}

TEST_CASE("baseline: a version other than 1 is rejected, however large") {
    for (const char* v : {"4294967297", "18446744073709551617", "-4294967295", "1.0", "\"1\"", "0", "2"}) {
        const std::string text = std::string("{\"version\": ") + v + ", \"entries\": []}";
        CHECK_THROWS_WITH_AS(parse_baseline(text, "b.json"), doctest::Contains("unsupported version"),
                             std::runtime_error);
    }
    CHECK_THROWS_WITH_AS(parse_baseline("{\"entries\": []}", "b.json"), doctest::Contains("no \"version\""),
                         std::runtime_error);
    CHECK(parse_baseline("{\"version\": 1, \"entries\": []}", "b.json").entries.empty());
}

TEST_CASE("a directive may name the rule by its name, and a mistyped one gets a suggestion") {
    std::string text = "O1000\n" + kM52 + " (osplint: disable=m52-on-call-line)\n" + kM52 +
                       " (osplint: disable=m52-on-cal-line)\nM30\n";
    FileResult r = check_text("A.MIN", text, Config{});
    auto left = of_rule(r, "OSP104");
    REQUIRE(left.size() == 1);
    CHECK(left[0]->range.start.line == 3);
    REQUIRE(suppressed_of(r, "OSP104").size() == 1);
    auto unknown = of_rule(r, "OSP901");
    REQUIRE(unknown.size() == 1);
    CHECK(unknown[0]->message.find("did you mean 'm52-on-call-line'?") != std::string::npos);
}

TEST_CASE("occurrences: exact up to the limit, then a sketch of fixed size that keeps them unique") {
    // Below the limit: 1, 2, 3 ... for each combination, exactly.
    OccurrenceCounter exact;
    CHECK(exact.next("OSP104", "O1", "G0X1") == 1);
    CHECK(exact.next("OSP104", "O1", "G0X1") == 2);
    CHECK(exact.next("OSP104", "O1", "G0X2") == 1);
    CHECK(exact.next("OSP301", "O1", "G0X1") == 1);
    CHECK(exact.next("OSP104", "O1", "G0X1") == 3);
    CHECK_FALSE(exact.sketched());

    // Past the limit (64 here): every key, new or seen, is counted in the
    // sketch; a key's occurrences still rise one by one.
    auto feed = [](OccurrenceCounter& c, uint64_t keys, std::vector<std::pair<uint64_t, int>>& out) {
        for (uint64_t k = 1; k <= keys; ++k)
            for (uint64_t again = 0; again < 1 + k % 3; ++again) out.push_back({k, c.next(k * 0x100000001B3ull)});
    };
    OccurrenceCounter a(64), b(64);
    std::vector<std::pair<uint64_t, int>> ra, rb;
    feed(a, 50, ra);
    CHECK_FALSE(a.sketched());
    for (const auto& [k, n] : ra) CHECK(n >= 1);
    feed(a, 200000, ra);
    CHECK(a.sketched());
    feed(b, 50, rb);
    feed(b, 200000, rb);
    CHECK(ra == rb);  // the same for the same findings
    CHECK(a.same_counts(b));
    // The memory stops growing: the same after twice as many keys, those
    // counted exactly before the sketch among them.
    const size_t at = a.bytes();
    CHECK(at <= OccurrenceCounter::kSketchRows * OccurrenceCounter::kSketchWidth * 4 + 4096);
    feed(a, 400000, ra);
    CHECK(a.bytes() == at);
    CHECK_FALSE(a.same_counts(b));
    // Unique: no (key, occurrence) twice, and each key's occurrences rise.
    std::map<uint64_t, int> last;
    std::set<std::pair<uint64_t, int>> seen;
    bool unique = true, rising = true;
    for (const auto& [k, n] : ra) {
        unique = unique && seen.insert({k, n}).second;
        rising = rising && n > last[k];
        last[k] = n;
    }
    CHECK(unique);
    CHECK(rising);
    // Cleared, it counts exactly again.
    a.clear();
    CHECK_FALSE(a.sketched());
    CHECK(a.next(7) == 1);
    CHECK(a.next(7) == 2);
}
