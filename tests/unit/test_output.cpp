// Output formats for CI: SARIF structure, gcc lines, GitHub workflow commands
// and their escaping, the JSON report's suppressed findings, the HTML page.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "output/html.h"
#include "output/json_text.h"
#include "output/ordered.h"
#include "output/pipeline.h"
#include "output/sideview.h"
#include "output/render.h"
#include "output/writer.h"
#include "osplint/osplint.h"
#include "api/check.h"
#include "api/config.h"
#include "rules/registry.h"

using namespace osplint;
using nlohmann::json;

namespace {

const std::string kProgram =
    "O1000\n"
    "N10 G0 X50 Y30\n"
    "(\xF0\x9F\x93\x90 TOOL) CALL OZAGR PR=5 PZ=-20 PI=12 M52\n"  // an emoji: 1 code point, 2 UTF-16 units
    "N10 G0 X0 Y0\n"
    "CALL OZAGA PR=5 PZ=-20 PI=12\n"
    "CALL OZAGR PR=5 PZ=-20 PI=12 M52 M8 (osplint: disable=OSP104 -- reviewed with the setter)\n"
    "G0 X20 (osplint: disable=OSP1O4)\n"
    "M30\n";

// OSP003 (off by default) is turned on: its note with a place is what the
// formats' related locations are checked on.
std::vector<FileResult> check(const std::string& path, const std::string& text) {
    Config config;
    config.rule_severity["OSP003"] = Severity::Warning;
    return {check_text(path, text, config)};
}

json sarif_of(const std::vector<FileResult>& r, const std::string& root = "/proj") {
    WriterOptions o;
    o.sarif_root = root;
    return json::parse(render_report(r, Format::Sarif, o));
}

std::map<std::string, std::string> fingerprints_by_rule_and_text(const json& log) {
    std::map<std::string, std::string> out;
    for (const auto& r : log["runs"][0]["results"])
        out[r["ruleId"].get<std::string>() + "|" + r["message"]["text"].get<std::string>()] =
            r["partialFingerprints"][std::string(kFingerprintKey)].get<std::string>();
    return out;
}

}  // namespace

TEST_CASE("GitHub escaping: data escapes % CR LF, properties also : and ,") {
    CHECK(github_escape_data("100% done\r\nnext: a, b") == "100%25 done%0D%0Anext: a, b");
    CHECK(github_escape_property("C:\\dir,x/100%\n") == "C%3A\\dir%2Cx/100%25%0A");
    CHECK(github_escape_data("%25") == "%2525");  // already-escaped text is escaped again
    CHECK(github_escape_property("") == "");
}

TEST_CASE("github format: one command per finding, escaped") {
    auto results = check("dir,with:odd%/P.MIN", kProgram);
    std::string out = render_report(results, Format::Github);
    std::vector<std::string> lines;
    for (size_t i = 0; i < out.size();) {
        size_t e = out.find('\n', i);
        lines.push_back(out.substr(i, e - i));
        i = e + 1;
    }
    REQUIRE(lines.size() == results[0].diagnostics.size());
    for (const auto& l : lines) {
        CAPTURE(l);
        // GitHub limits annotations per kind and step, not their order: they
        // come as the findings are made.
        const bool command = l.rfind("::error ", 0) == 0 || l.rfind("::warning ", 0) == 0 || l.rfind("::notice ", 0) == 0;
        REQUIRE(command);
        CHECK(l.find("file=dir%2Cwith%3Aodd%25/P.MIN,line=") != std::string::npos);
        CHECK(l.find('\r') == std::string::npos);
    }
    // The OSP104 error: position, end, title, and the note on a second (escaped) line.
    const std::string* m52 = nullptr;
    for (const auto& l : lines)
        if (l.find("title=OSP104") != std::string::npos) m52 = &l;
    REQUIRE(m52);
    CHECK(m52->rfind("::error file=dir%2Cwith%3Aodd%25/P.MIN,line=3,col=39,endLine=3,endColumn=42,title=OSP104::M52 on the CALL line", 0) == 0);
    CHECK(m52->find("%0Anote: ") != std::string::npos);
    CHECK(m52->find("%0Afix: Replace M52 by PM=52") != std::string::npos);
    // The unknown-subprogram info is a notice; the duplicate sequence name a warning.
    CHECK(out.find("::notice file=dir%2Cwith%3Aodd%25/P.MIN,line=5,") != std::string::npos);
    CHECK(out.find("::warning file=dir%2Cwith%3Aodd%25/P.MIN,line=4,col=1,endLine=4,endColumn=4,title=OSP003::") !=
          std::string::npos);
    // The suppressed finding is not annotated (its block still has OSP108 for the M8).
    int line6 = 0;
    for (const auto& l : lines)
        if (l.find(",line=6,") != std::string::npos) {
            ++line6;
            CHECK(l.find("title=OSP104") == std::string::npos);
        }
    CHECK(line6 == 1);
}

TEST_CASE("gcc format: path:line:col: severity: message [ID], one line each") {
    FileResult r;
    r.path = "A.MIN";
    Diagnostic d;
    d.rule = "OSP005";
    d.severity = Severity::Info;
    d.message = "first line\nsecond line";
    d.range.start = {7, 5, 5, 5};
    d.range.end = {7, 9, 9, 9};
    r.diagnostics.push_back(d);
    d.rule = "OSP104";
    d.severity = Severity::Error;
    d.message = "M52 on the CALL line";
    r.diagnostics.push_back(d);
    d.rule = "OSP003";
    d.severity = Severity::Warning;
    r.diagnostics.push_back(d);
    std::string out = render_report({r}, Format::Gcc);
    CHECK(out ==
          "A.MIN:7:6: note: first line second line [OSP005]\n"
          "A.MIN:7:6: error: M52 on the CALL line [OSP104]\n"
          "A.MIN:7:6: warning: M52 on the CALL line [OSP003]\n");

    auto real = check("P.MIN", kProgram);
    std::string g = render_report(real, Format::Gcc);
    CHECK(g.find("P.MIN:3:39: error: M52 on the CALL line of OZAGR") != std::string::npos);
    CHECK(g.find("[OSP104]\n") != std::string::npos);
    size_t lines = std::count(g.begin(), g.end(), '\n');
    CHECK(lines == real[0].diagnostics.size());
}

TEST_CASE("text format: the first finding of each rule in a run points at its explain page") {
    FileResult a;
    a.path = "A.MIN";
    Diagnostic d;
    d.rule = "OSP104";
    d.message = "M52 on the CALL line";
    d.range.start = {3, 5, 5, 5};
    d.range.end = {3, 8, 8, 8};
    a.diagnostics.push_back(d);
    a.diagnostics.push_back(d);
    d.rule = "OSP003";
    d.severity = Severity::Warning;
    a.diagnostics.push_back(d);
    FileResult b = a;  // a second file: its findings of the same rules get no hint
    b.path = "B.MIN";
    std::string out = render_report({a, b}, Format::Text);
    auto count = [&](const std::string& s) {
        size_t n = 0;
        for (size_t at = out.find(s); at != std::string::npos; at = out.find(s, at + 1)) ++n;
        return n;
    };
    CHECK(count("(run \"osplint explain OSP104\" for more)") == 1);
    CHECK(count("(run \"osplint explain OSP003\" for more)") == 1);
    // The hint ends the block of the first finding, before the next finding.
    size_t hint = out.find("(run \"osplint explain OSP104\" for more)");
    size_t second = out.find("A.MIN:3:6", out.find("A.MIN:3:6") + 1);
    CHECK(hint < second);
    // The other formats carry no hint.
    CHECK(render_report({a, b}, Format::Gcc).find("osplint explain") == std::string::npos);
}

TEST_CASE("text format: a long line is cut around its range, the carets stay under the range") {
    // A short line is shown whole, the carets under the range.
    ShownLine s = shown_line("G0 X10 Y20", 3, 6);
    CHECK(s.text == "G0 X10 Y20");
    CHECK(s.caret == 3);
    CHECK(s.carets == 3);
    // A range at the end of the line (an insertion point) gets one caret after it.
    s = shown_line("G0 X10", 6, 6);
    CHECK(s.caret == 6);
    CHECK(s.carets == 1);

    // A line of 5,000 code points with a range from column 3,000 to its end.
    std::string line = "G0 X";
    for (int i = 0; i < 4996; ++i) line += "\xC3\xA9";  // a 2-byte code point, one column
    const uint32_t cps = 5000;
    s = shown_line(line, 3000, cps);
    CHECK(s.text.substr(0, 3) == "...");
    CHECK(s.text.substr(s.text.size() - 3) == "...");
    // kShownColumns code points between the cuts, kShownBefore of them before the range.
    CHECK(s.text.size() == 3 + 2 * kShownColumns + 3);  // every code point shown is 2 bytes
    CHECK(s.caret == 3 + kShownBefore);
    CHECK(s.carets == kShownColumns - kShownBefore);  // up to the cut, not to the end of the line

    // Near the start, no cut before; near the end, no cut after and the window ends with the line.
    s = shown_line(line, 2, 3);
    CHECK(s.text.substr(0, 4) == "G0 X");
    CHECK(s.caret == 2);
    s = shown_line(line, cps - 1, cps);
    CHECK(s.text.substr(0, 3) == "...");
    CHECK(s.text.substr(s.text.size() - 2) == "\xC3\xA9");
    CHECK(s.caret == 3 + kShownColumns - 1);
    CHECK(s.carets == 1);
    // A range past the text kept: the line, cut, without carets.
    s = shown_line("G0 X10...", 4000, 4001);
    CHECK(s.carets == 0);

    // Through the renderer: the report of a finding on such a line stays a few lines of bounded width.
    Diagnostic d;
    d.rule = "OSP001";
    d.message = "too long";
    d.range.start = {1, 3000, 3000, 3000};
    d.range.end = {1, cps, cps, cps};
    d.line_text = line;
    const std::string out = render_text_diagnostic("A.MIN", d, false);
    size_t widest = 0, from = 0;
    for (size_t nl = out.find('\n'); nl != std::string::npos; from = nl + 1, nl = out.find('\n', from))
        widest = std::max(widest, nl - from);
    CHECK(widest < 2 * kShownColumns + 20);
}

TEST_CASE("JsonText writes the bytes nlohmann::json's dump gives for the same document") {
    // Strings of every kind: plain, quotes and backslashes, control bytes, DEL,
    // UTF-8, invalid UTF-8 (replaced), empty.
    std::vector<std::string> strings = {"OSP301", "say \"hi\" \\ there", std::string("a\0b\x01\x1f\t\n\r", 9), "\x7f",
                                        "caf\xC3\xA9 \xF0\x9F\x93\x90", "bad \xC3 \xFF\xFE end", ""};
    uint32_t seed = 7;
    for (int i = 0; i < 500; ++i) {  // random bytes, biased to the troublesome ones
        std::string r;
        for (int k = 0; k < 12; ++k) {
            seed = seed * 1103515245u + 12345u;
            const unsigned b = (seed >> 16) & 0xFF;
            r += static_cast<char>(b % 3 == 0 ? b : b % 3 == 1 ? 'A' + b % 26 : 0x80 | (b & 0x3F));
        }
        strings.push_back(r);
    }
    for (const auto& str : strings) {
        nlohmann::ordered_json doc = {{"s", str}, {"n", 42}, {"neg", -3}, {"b", false},
                                      {"list", {str, 0, true}}, {"empty", nlohmann::ordered_json::array()},
                                      {"obj", {{"k", str}}}};
        std::string text;
        JsonText j(text);
        j.begin_object().key("s").value(str).key("n").value(uint64_t{42}).key("neg").value(-3).key("b").value(false);
        j.key("list").begin_array().value(str).value(0).value(true).end_array();
        j.key("empty").begin_array().end_array();
        j.key("obj").begin_object().key("k").value(str).end_object();
        j.end_object();
        CHECK(text == doc.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace));
    }
}

TEST_CASE("SARIF: required structure, rules, ruleIndex, levels, columns, locations") {
    auto results = check("/proj/parts/P.MIN", kProgram);
    FileResult missing;
    missing.path = "/proj/parts/GONE.MIN";
    missing.io_error = "no such file";
    results.push_back(missing);
    json log = sarif_of(results);

    CHECK(log["$schema"] == std::string(kSarifSchema));
    CHECK(log["version"] == "2.1.0");
    REQUIRE(log["runs"].size() == 1);
    const json& run = log["runs"][0];
    const json& driver = run["tool"]["driver"];
    CHECK(driver["name"] == "osplint");
    CHECK(driver["version"] == std::string(version()));
    CHECK(driver["informationUri"] == "https://github.com/osplint/osplint");
    CHECK(run["columnKind"] == "utf16CodeUnits");
    CHECK(run["originalUriBaseIds"]["%SRCROOT%"]["uri"] == "file:///proj/");
    REQUIRE(run["invocations"].size() == 1);
    CHECK(run["invocations"][0]["executionSuccessful"] == false);  // a file could not be read
    CHECK(run["invocations"][0]["toolExecutionNotifications"][0]["level"] == "error");

    // Rules: every reported rule once (in the order they first appear), with
    // descriptions and help from the doc.
    const json& rules = driver["rules"];
    std::set<std::string> reported, listed;
    for (const auto& d : results[0].diagnostics) reported.insert(d.rule);
    for (const auto& s : results[0].suppressed) reported.insert(s.diagnostic.rule);
    REQUIRE(rules.size() == reported.size());
    for (const auto& r : rules) {
        std::string id = r["id"];
        CAPTURE(id);
        CHECK(listed.insert(id).second);
        const RuleMeta* m = find_rule(id);
        REQUIRE(m);
        CHECK(r["name"] == std::string(m->name));
        CHECK_FALSE(r["shortDescription"]["text"].get<std::string>().empty());
        CHECK_FALSE(r["fullDescription"]["text"].get<std::string>().empty());
        CHECK(r["help"]["markdown"].get<std::string>().rfind("# " + id, 0) == 0);
        CHECK_FALSE(r["help"]["text"].get<std::string>().empty());
        std::string level = r["defaultConfiguration"]["level"];
        CHECK(level == (m->severity == Severity::Error ? "error" : m->severity == Severity::Warning ? "warning" : "note"));
    }

    // Results: ruleIndex consistent with ruleId, level mapped, location relative to %SRCROOT%.
    const json& res = run["results"];
    REQUIRE(res.size() == results[0].diagnostics.size() + results[0].suppressed.size());
    std::set<std::string> levels;
    for (const auto& r : res) {
        std::string id = r["ruleId"];
        CAPTURE(id);
        size_t idx = r["ruleIndex"];
        REQUIRE(idx < rules.size());
        CHECK(rules[idx]["id"] == id);
        std::string level = r["level"];
        CHECK((level == "error" || level == "warning" || level == "note"));
        levels.insert(level);
        CHECK_FALSE(r["message"]["text"].get<std::string>().empty());
        const json& pl = r["locations"][0]["physicalLocation"];
        CHECK(pl["artifactLocation"]["uri"] == "parts/P.MIN");
        CHECK(pl["artifactLocation"]["uriBaseId"] == "%SRCROOT%");
        for (const char* k : {"startLine", "startColumn", "endLine", "endColumn"}) CHECK(pl["region"][k].is_number());
        CHECK(r["partialFingerprints"][std::string(kFingerprintKey)].get<std::string>().size() == 16);
    }
    CHECK(levels == std::set<std::string>{"error", "warning", "note"});

    // The M52 after the emoji: code-point column 39, UTF-16 column 40 (1-based).
    const json* m52 = nullptr;
    for (const auto& r : res)
        if (r["ruleId"] == "OSP104" && !r.contains("suppressions")) m52 = &r;
    REQUIRE(m52);
    const json& region = (*m52)["locations"][0]["physicalLocation"]["region"];
    CHECK(region["startLine"] == 3);
    CHECK(region["startColumn"] == 40);
    CHECK(region["endColumn"] == 43);
    // Its fix, as an artifact change.
    REQUIRE((*m52)["fixes"].size() == 1);
    const json& rep = (*m52)["fixes"][0]["artifactChanges"][0]["replacements"][0];
    CHECK(rep["deletedRegion"]["startColumn"] == 40);
    CHECK(rep["insertedContent"]["text"] == "PM=52");
    CHECK((*m52)["fixes"][0]["artifactChanges"][0]["artifactLocation"]["uri"] == "parts/P.MIN");

    // The duplicate sequence name points at the first definition.
    bool related = false;
    for (const auto& r : res)
        if (r["ruleId"] == "OSP003") {
            REQUIRE(r.contains("relatedLocations"));
            CHECK(r["relatedLocations"][0]["physicalLocation"]["region"]["startLine"] == 2);
            CHECK(r["relatedLocations"][0]["id"] == 1);
            related = true;
        }
    CHECK(related);

    // The suppressed finding: listed with its in-source justification.
    bool suppressed = false;
    for (const auto& r : res)
        if (r.contains("suppressions")) {
            suppressed = true;
            CHECK(r["ruleId"] == "OSP104");
            CHECK(r["suppressions"][0]["kind"] == "inSource");
            CHECK(r["suppressions"][0]["justification"] == "reviewed with the setter");
            CHECK(r["locations"][0]["physicalLocation"]["region"]["startLine"] == 6);
        }
    CHECK(suppressed);
}

TEST_CASE("SARIF: partial fingerprints stay when a line is inserted above") {
    auto a = fingerprints_by_rule_and_text(sarif_of(check("/proj/P.MIN", kProgram)));
    auto b = fingerprints_by_rule_and_text(sarif_of(check("/proj/P.MIN", "(REVISION C)\n" + kProgram)));
    REQUIRE(a.size() >= 4);
    CHECK(a == b);
}

TEST_CASE("SARIF: artifact URIs are percent-encoded, relative under the root, absolute file: URIs outside") {
    bool rel = false;
    CHECK(sarif_artifact_uri("/proj/dir with blank/\xC3\x84#1.MIN", "/proj", rel) == "dir%20with%20blank/%C3%84%231.MIN");
    CHECK(rel);
    CHECK(sarif_artifact_uri("/other/P.MIN", "/proj", rel) == "file:///other/P.MIN");
    CHECK_FALSE(rel);
    CHECK(sarif_artifact_uri("<stdin>", std::filesystem::current_path(), rel) == "%3Cstdin%3E");
    CHECK(rel);
}

TEST_CASE("SARIF: baseline matches are listed as externally suppressed") {
    auto results = check("/proj/P.MIN", kProgram);
    FileResult& r = results[0];
    SuppressedDiagnostic s;
    s.kind = SuppressedDiagnostic::Kind::Baseline;
    s.reason = "recorded in the baseline b.json";
    s.diagnostic = r.diagnostics.front();
    r.diagnostics.erase(r.diagnostics.begin());
    r.suppressed.push_back(s);
    json log = sarif_of(results);
    int external = 0;
    for (const auto& x : log["runs"][0]["results"])
        if (x.contains("suppressions") && x["suppressions"][0]["kind"] == "external") {
            ++external;
            CHECK(x["suppressions"][0]["justification"] == "recorded in the baseline b.json");
        }
    CHECK(external == 1);
}

TEST_CASE("JSON report: the version 1 contract, with suppressed findings and their reason") {
    auto results = check("P.MIN", kProgram);
    json full = json::parse(render_report(results, Format::Json));
    REQUIRE(full["files"].size() == 1);
    REQUIRE(full["files"][0].contains("suppressed"));
    json sup = full["files"][0]["suppressed"];
    REQUIRE(sup.size() == 1);
    CHECK(sup[0]["rule"] == "OSP104");
    CHECK(sup[0]["range"]["start"]["line"] == 6);
    CHECK(sup[0]["suppression"]["kind"] == "inSource");
    CHECK(sup[0]["suppression"]["reason"] == "reviewed with the setter");
    CHECK(sup[0]["suppression"]["scope"] == "block");
    CHECK(sup[0]["suppression"]["directive"]["start"]["line"] == 6);
    for (const char* k : {"rule", "name", "severity", "message", "range", "notes", "fixes", "fingerprint"})
        CHECK(sup[0].contains(k));
    CHECK(full["summary"]["suppressed"] == 1);
    CHECK(full["version"] == 1);
    CHECK(full["tool"]["name"] == "osplint");
    const json& diags = full["files"][0]["diagnostics"];
    REQUIRE(diags.size() == results[0].diagnostics.size());
    for (size_t i = 0; i < diags.size(); ++i) {
        CHECK(diags[i]["rule"] == results[0].diagnostics[i].rule);
        CHECK(diags[i]["fingerprint"] == results[0].diagnostics[i].fingerprint);
    }
    CHECK(full["summary"]["error"].get<size_t>() + full["summary"]["warning"].get<size_t>() +
              full["summary"]["info"].get<size_t>() ==
          diags.size());
}

namespace {

Diagnostic finding(std::string rule, std::string message, uint32_t line, Severity severity = Severity::Error) {
    Diagnostic d;
    d.rule = std::move(rule);
    d.name = "n";
    d.severity = severity;
    d.message = std::move(message);
    d.range.start = {line, 0, 0, 0};
    d.range.end = {line, 1, 1, 1};
    d.line_text = "X1";
    d.kind = message_kind(d.rule, d.message);
    return d;
}

// Records what reaches it, one line per call.
struct Recorder final : DiagnosticSink {
    void begin_file(const std::string& p) override { calls.push_back("begin " + p); }
    void diagnostic(Diagnostic&& d) override {
        calls.push_back("diag " + d.rule + "@" + std::to_string(d.range.start.line) +
                        (d.folded ? " +" + std::to_string(d.folded) : ""));
    }
    void suppressed(SuppressedDiagnostic&& s) override {
        calls.push_back("supp " + s.diagnostic.rule + "@" + std::to_string(s.diagnostic.range.start.line));
    }
    void end_file(const std::string& p, const std::string& e) override { calls.push_back("end " + p + " " + e); }
    std::vector<std::string> calls;
};

}  // namespace

TEST_CASE("folding: beyond `keep` findings of a kind, the others become one with their count") {
    Recorder rec;
    Counts counts;
    FoldingSink fold(rec, 2, counts);
    fold.begin_file("A.MIN");
    // Two kinds interleaved: numbers do not make a kind, words do.
    for (uint32_t i = 1; i <= 6; ++i) {
        fold.diagnostic(finding("OSP301", "Z-" + std::to_string(300 + i) + ".5 is below -300", i));
        fold.diagnostic(finding("OSP301", "X" + std::to_string(i) + " is above 100", 100 + i));
    }
    fold.diagnostic(finding("OSP104", "M52 on the CALL line", 50));
    fold.end_file("A.MIN", "");
    const std::vector<std::string> expected = {
        "begin A.MIN", "diag OSP301@1", "diag OSP301@101", "diag OSP301@2", "diag OSP301@102",
        "diag OSP104@50", "diag OSP301@3 +3", "diag OSP301@103 +3", "end A.MIN "};
    CHECK(rec.calls == expected);
    CHECK(counts.folded == 6);
    CHECK(message_kind("R", "Z-301.5 below") == message_kind("R", "Z7 below"));
    CHECK(message_kind("R", "Z-301.5 below") != message_kind("R", "X-301.5 below"));
    CHECK(message_kind("R", "a") != message_kind("S", "a"));
    CHECK(keyed_kind("R", "a") != message_kind("R", "a"));
}

TEST_CASE("folding off, and the limit per file") {
    Recorder rec;
    Counts counts;
    LimitSink limit(rec, 3, counts);
    FoldingSink fold(limit, 0, counts);
    for (const char* file : {"A.MIN", "B.MIN"}) {
        fold.begin_file(file);
        for (uint32_t i = 1; i <= 5; ++i) fold.diagnostic(finding("OSP104", "m", i));
        fold.end_file(file, "");
    }
    const std::vector<std::string> expected = {"begin A.MIN", "diag OSP104@1", "diag OSP104@2", "diag OSP104@3",
                                               "diag OSP104@4 +1",  "end A.MIN ",   "begin B.MIN",   "diag OSP104@1",
                                               "diag OSP104@2",     "diag OSP104@3", "diag OSP104@4 +1", "end B.MIN "};
    CHECK(rec.calls == expected);
    CHECK(counts.folded == 2);
}

TEST_CASE("ordered output: files finishing out of order are handed on in order, spooled through a file") {
    Recorder rec;
    OrderedOutput out(rec, 3);
    DiagnosticSink& a = out.channel(0);
    DiagnosticSink& b = out.channel(1);
    DiagnosticSink& c = out.channel(2);
    // C and B run ahead of A; B spills past the memory of its spool.
    c.begin_file("C");
    c.diagnostic(finding("OSP3", std::string(100, 'c'), 1));
    c.end_file("C", "gone");
    b.begin_file("B");
    for (uint32_t i = 1; i <= 60000; ++i) b.diagnostic(finding("OSP2", std::string(100, 'b'), i));
    a.begin_file("A");
    a.diagnostic(finding("OSP1", "a", 1));
    CHECK(rec.calls == std::vector<std::string>{"begin A", "diag OSP1@1"});  // A goes straight through
    a.end_file("A", "");
    // B is now replayed and goes on straight through.
    REQUIRE(rec.calls.size() == 3 + 1 + 60000);
    CHECK(rec.calls[3] == "begin B");
    CHECK(rec.calls.back() == "diag OSP2@60000");
    SuppressedDiagnostic s;
    s.diagnostic = finding("OSP2", "s", 60001);
    s.reason = "r";
    b.suppressed(std::move(s));
    b.end_file("B", "");
    CHECK(rec.calls[rec.calls.size() - 5] == "supp OSP2@60001");
    CHECK(rec.calls[rec.calls.size() - 4] == "end B ");
    CHECK(rec.calls[rec.calls.size() - 3] == "begin C");
    CHECK(rec.calls[rec.calls.size() - 1] == "end C gone");
    CHECK(out.errors().empty());
}

TEST_CASE("ordered output: a diagnostic survives its binary form, every field") {
    Diagnostic d = finding("OSP104", "M52 \xE2\x80\x94 PM=52", 3, Severity::Warning);
    d.notes.push_back({"n1", std::nullopt});
    d.notes.push_back({"n2", d.range});
    d.fixes.push_back({"t", {{d.range, "PM=52"}, {d.range, ""}}});
    d.fingerprint = "0123456789abcdef";
    d.folded = 7;
    d.folded_last = d.range;
    std::string bytes;
    encode_diagnostic(bytes, d);
    std::string_view in(bytes);
    Diagnostic back;
    REQUIRE(decode_diagnostic(in, back));
    CHECK(in.empty());
    CHECK(back.rule == d.rule);
    CHECK(back.message == d.message);
    CHECK(back.severity == d.severity);
    CHECK(back.notes.size() == 2);
    CHECK_FALSE(back.notes[0].range.has_value());
    CHECK(back.notes[1].range->start.line == 3);
    CHECK(back.fixes[0].edits[0].replacement == "PM=52");
    CHECK(back.fingerprint == d.fingerprint);
    CHECK(back.folded == 7);
    CHECK(back.folded_last.has_value());
    std::string_view cut(bytes.data(), bytes.size() - 3);
    Diagnostic broken;
    CHECK_FALSE(decode_diagnostic(cut, broken));
}

namespace {

size_t occurrences(const std::string& s, const std::string& what) {
    size_t n = 0;
    for (size_t i = s.find(what); i != std::string::npos; i = s.find(what, i + what.size())) ++n;
    return n;
}

// The page `osplint check --format html` writes for one file: the writer after
// the counting stage, the file's walk observed by the side-view tap.
std::string html_page(const std::string& path, const Config& config) {
    SideViews views;
    WriterOptions wo;
    wo.side_views = &views;
    std::ostringstream out;
    auto writer = make_writer(Format::Html, out, wo);
    Counts counts;
    CountingSink count(*writer, counts);
    SideViewTap tap(count, config, views);
    AnalysisOptions options;
    options.observer = &tap;
    check_path(path, config, options, tap);
    writer->finish(counts);
    return out.str();
}

}  // namespace

TEST_CASE("HTML escaping: markup, quotes, control characters and invalid UTF-8") {
    CHECK(html_escape("<script>alert('x & \"y\"')</script>") ==
          "&lt;script&gt;alert(&#39;x &amp; &quot;y&quot;&#39;)&lt;/script&gt;");
    CHECK(html_escape("a\tb\nc") == "a\tb\nc");
    CHECK(html_escape("a\x01z\x7f") == "a\xEF\xBF\xBDz\xEF\xBF\xBD");
    CHECK(html_escape("\xC3\xA9 \xF0\x9F\x93\x90") == "\xC3\xA9 \xF0\x9F\x93\x90");  // valid UTF-8 stays
    CHECK(html_escape("\xC3(\xFF\xED\xA0\x80") == "\xEF\xBF\xBD(\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");
}

TEST_CASE("html format: summary, findings beside their lines, escaped program text, side views") {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / fs::path("osplint-html-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path file = dir / "P<1>.MIN";
    {
        std::ofstream f(file, std::ios::binary);
        f << "O1000\n"
             "(<script>alert('owned')</script> & \"Q\")\n"
             "G0 X50 Y30\n"
             "G56 Z50. H1\n"
             "CALL OZAGR PR=5 PZ=-298. PI=5. M52 (<b>bold</b>)\n"
             "G0 X0 Y0\n"
             "CALL OZAGR PR=5 PZ=-20 PI=12 PM=52 M8\n"
             "M30\n";
    }
    Config config;
    config.travel['Z'] = TravelLimit{-300, 150};
    const std::string page = html_page(file.string(), config);
    // The same findings as the text report.
    const FileResult r = check_file(file.string(), config);
    REQUIRE(!r.diagnostics.empty());
    uint64_t errors = 0, warnings = 0;
    std::map<std::string, int> per_rule;
    for (const auto& d : r.diagnostics) {
        CAPTURE(d.rule);
        CHECK(page.find("<p class=\"msg\">" + html_escape(d.message) + "</p>") != std::string::npos);
        errors += d.severity == Severity::Error;
        warnings += d.severity == Severity::Warning;
        ++per_rule[d.rule];
    }
    CHECK(occurrences(page, "<article class=\"finding ") == r.diagnostics.size());
    CHECK(per_rule.count("OSP104") == 1);
    CHECK(per_rule.count("OSP301") == 1);
    // The summary: counts per severity and per rule, linked to the first finding.
    CHECK(page.find(fmt::format("<span class=\"n\">{}</span>error", errors)) != std::string::npos);
    CHECK(page.find(fmt::format("<span class=\"n\">{}</span>warning", warnings)) != std::string::npos);
    CHECK(page.find("<span class=\"n\">1</span>file checked") != std::string::npos);
    for (const auto& [rule, n] : per_rule) {
        CAPTURE(rule);
        const size_t row = page.find(">" + rule + "</a></td>");
        REQUIRE(row != std::string::npos);
        CHECK(page.find(fmt::format("<td class=\"num\">{}</td></tr>", n), row) < page.find("</tr>", row) + 6);
        CHECK(page.find("<a href=\"#file-1-", row) < page.find("</tr>", row));
    }
    CHECK(page.find("examples") == std::string::npos);
    // Program text is escaped everywhere: the context line, the path, the fix.
    CHECK(page.find("<script>") == std::string::npos);
    CHECK(page.find("<b>bold") == std::string::npos);
    CHECK(page.find("(&lt;script&gt;alert(&#39;owned&#39;)") != std::string::npos);
    CHECK(page.find("&lt;/script&gt; &amp; &quot;Q&quot;)") != std::string::npos);
    CHECK(page.find("&lt;b&gt;bold&lt;/b&gt;") != std::string::npos);
    CHECK(page.find("P&lt;1&gt;.MIN") != std::string::npos);
    // The lines around a finding, numbered, its columns marked.
    CHECK(page.find("<td class=\"ln\">3</td>") != std::string::npos);
    CHECK(page.find("<tr class=\"hit\"><td class=\"ln\">5</td>") != std::string::npos);
    CHECK(page.find("<mark>M52</mark>") != std::string::npos);
    CHECK(page.find("<code>PM=52</code>") != std::string::npos);
    // The side view: an inline picture (no XML prologue) beside the calls, the one past the travel in red.
    CHECK(occurrences(page, "<svg ") == 1);
    CHECK(page.find("<?xml") == std::string::npos);
    CHECK(page.find("class=\"violation\"") != std::string::npos);
    CHECK(page.find("<tr class=\"travel\"><td class=\"num\">5</td>") != std::string::npos);
    CHECK(page.find("<tr><td class=\"num\">7</td><td>OZAGR (CALL)</td><td class=\"code\">Z -37 .. 150</td>") !=
          std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("html format: a file's findings beyond the cap are counted; without the file, only the line of each") {
    std::vector<FileResult> results(1);
    results[0].path = "/nonexistent/osplint/G.MIN";
    for (uint32_t i = 1; i <= kHtmlMaxFindings + 5; ++i) {
        Diagnostic d;
        d.rule = "OSP104";
        d.name = "m52-on-call-line";
        d.message = "m";
        d.range.start.line = d.range.end.line = i;
        d.range.start.byte_col = 0;
        d.range.end.byte_col = 3;
        d.line_text = "M52 <" + std::to_string(i) + ">";
        results[0].diagnostics.push_back(std::move(d));
    }
    const std::string page = render_report(results, Format::Html);
    CHECK(occurrences(page, "<article class=\"finding ") == kHtmlMaxFindings);
    CHECK(page.find("and 5 more findings not shown here") != std::string::npos);
    CHECK(page.find(fmt::format("<td class=\"num\">{}</td></tr>", kHtmlMaxFindings + 5)) != std::string::npos);
    CHECK(page.find("<td class=\"code\"><mark>M52</mark> &lt;1&gt;</td>") != std::string::npos);
    CHECK(occurrences(page, "<td class=\"ln\">") == kHtmlMaxFindings);  // no context lines: the file is not there
    CHECK(page.rfind("</html>\n") == page.size() - 8);
}

TEST_CASE("html format: the lines around a finding come from the file; a range ending at a line's start stops before it") {
    namespace fs = std::filesystem;
    const fs::path file = fs::temp_directory_path() / fs::path("osplint-html-lines-" + std::to_string(::getpid()) + ".MIN");
    {
        std::ofstream f(file, std::ios::binary);
        for (int i = 1; i <= 9; ++i) f << "G0 X" << i << (i == 4 ? "\r\n" : "\n");
    }
    std::vector<FileResult> results(1);
    results[0].path = file.string();
    Diagnostic d;
    d.rule = "OSP999";
    d.name = "test";
    d.message = "lines 5 and 6";
    d.range.start.line = 5;
    d.range.start.byte_col = 3;
    d.range.end.line = 7;
    d.range.end.byte_col = 0;
    d.line_text = "G0 X5";
    results[0].diagnostics.push_back(d);
    const std::string page = render_report(results, Format::Html);
    fs::remove(file);
    CHECK(page.find("<tr><td class=\"ln\">2</td>") == std::string::npos);
    CHECK(page.find("<tr><td class=\"ln\">3</td><td class=\"code\">G0 X3</td></tr>") != std::string::npos);
    CHECK(page.find("<tr><td class=\"ln\">4</td><td class=\"code\">G0 X4</td></tr>") != std::string::npos);
    CHECK(page.find("<tr class=\"hit\"><td class=\"ln\">5</td><td class=\"code\">G0 <mark>X5</mark></td></tr>") !=
          std::string::npos);
    CHECK(page.find("<tr class=\"hit\"><td class=\"ln\">6</td><td class=\"code\"><mark>G0 X6</mark></td></tr>") !=
          std::string::npos);
    CHECK(page.find("<tr><td class=\"ln\">7</td><td class=\"code\">G0 X7</td></tr>") != std::string::npos);
    CHECK(page.find("<tr><td class=\"ln\">8</td>") != std::string::npos);
    CHECK(page.find("<tr><td class=\"ln\">9</td>") == std::string::npos);
}
