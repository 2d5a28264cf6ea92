// Citations: the table of the manuals and their sections, the keys the
// sources cite, and the text users read. A finding, a note, an `explain`
// page, a macro card or a page of docs/ cites a manual by its title and a
// section by its heading; it never shows the catalog's internal names for
// the manuals' files, their line numbers or the numbers of the ambiguities.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>

#include "catalog/catalog.h"
#include "catalog/citations.h"
#include "engine/workspace.h"
#include "expectations.h"
#include "rules/registry.h"
#include "support/embedded.h"

namespace fs = std::filesystem;
using namespace osplint;
using namespace osplint::testing;

namespace {

fs::path source_dir() { return fs::path(OSPLINT_SOURCE_DIR); }

// What no user-facing text may contain, and why.
struct Forbidden {
    std::regex pattern;
    const char* what;
};

const std::vector<Forbidden>& forbidden() {
    static const std::vector<Forbidden> patterns = {
        {std::regex(R"(\bseeds?\b)", std::regex::icase), "the catalog's name for a manual's file (\"seed\")"},
        {std::regex("\\bL[0-9]+(-|\xE2\x80\x93)[0-9]+\\b"), "a line range (\"L26-30\")"},
        {std::regex(R"((^|[^0-9])[0-9]{3}:L[0-9]+)"), "a manual line (\"000:L153\")"},
        {std::regex(R"(\bA-[0-9]{2}\b)"), "an ambiguity number (\"A-17\")"},
    };
    return patterns;
}

// The first internal reference in `text`, or "".
std::string internal_reference(const std::string& text) {
    for (const auto& f : forbidden()) {
        std::smatch m;
        if (std::regex_search(text, m, f.pattern)) return std::string(f.what) + ": \"" + m.str() + "\"";
    }
    return {};
}

// A Markdown page without its code (fenced blocks and inline spans): the
// catalog schema shows `source = "000:L574"` as data, the trace page shows
// program line ranges as printed.
std::string prose_of(const std::string& md) {
    std::string out;
    bool fenced = false;
    std::istringstream in(md);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("```", 0) == 0) {
            fenced = !fenced;
            continue;
        }
        if (fenced) continue;
        bool code = false;
        for (char c : line) {
            if (c == '`') code = !code;
            else if (!code) out += c;
        }
        out += '\n';
    }
    return out;
}

Config config_for(const fs::path& dir) {
    if (fs::exists(dir / "osplint.toml")) return load_config(dir / "osplint.toml");
    return Config{};
}

std::vector<fs::path> programs_under(const fs::path& dir) {
    std::vector<fs::path> out;
    if (!fs::exists(dir)) return out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && e.path().extension() != ".toml" && e.path().extension() != ".md" &&
            e.path().extension() != ".snap" && e.path().extension() != ".fixed")  // a fixture's snapshots
            out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

// Every citation key written in a source file: cite("k"), cite({"k", ...}),
// cite_heading("k").
std::set<std::string> keys_cited_in(const std::string& text) {
    std::set<std::string> keys;
    static const std::regex call(R"(\bcite(?:_heading)?\(\s*(\{[^}]*\}|"[^"]*"))");
    static const std::regex literal(R"re("([^"]*)")re");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), call); it != std::sregex_iterator(); ++it) {
        std::string args = (*it)[1].str();
        for (auto l = std::sregex_iterator(args.begin(), args.end(), literal); l != std::sregex_iterator(); ++l)
            keys.insert((*l)[1].str());
    }
    return keys;
}

}  // namespace

TEST_CASE("citations: the table of the manuals is consistent") {
    REQUIRE(manuals().size() == 5);
    std::set<std::string_view> keys, numbers;
    for (const auto& m : manuals()) {
        CAPTURE(m.key);
        CHECK(keys.insert(m.key).second);
        CHECK(numbers.insert(m.number).second);
        CHECK(!m.title.empty());
        CHECK(!m.japanese.empty());
        CHECK(!m.covers.empty());
    }
    std::set<std::string_view> sections;
    for (const auto& s : manual_sections()) {
        CAPTURE(s.key);
        CHECK(sections.insert(s.key).second);
        CHECK(find_manual(s.key.substr(0, s.key.find('/'))) != nullptr);
        CHECK(!s.heading.empty());
        CHECK(s.first_line >= 1);
        CHECK(s.first_line <= s.last_line);
        CHECK(internal_reference(std::string(s.heading)).empty());
    }
}

TEST_CASE("citations: docs/manuals.md lists every manual and every section of the table") {
    std::string doc = read_file(source_dir() / "docs" / "manuals.md");
    for (const auto& m : manuals()) {
        CAPTURE(m.key);
        CHECK(doc.find("## " + std::string(m.title) + "\n") != std::string::npos);
        CHECK(doc.find(std::string(m.japanese)) != std::string::npos);
    }
    for (const auto& s : manual_sections()) {
        CAPTURE(s.key);
        CHECK(doc.find("| " + std::string(s.heading) + " |") != std::string::npos);
    }
}

TEST_CASE("citations: a key gives the manual's title and the section's heading") {
    CHECK(cite("fixed-cycles/g84") == "Fixed cycles manual, \"G84 Tap cycle\"");
    CHECK(cite("back-counterboring/common-3") == "Back counterboring macros manual, \"Common rules (3)\"");
    CHECK(cite("keyway") == "Keyway macros manual");
    CHECK(cite_heading("tap-cycle/cautions-8") == "\"Cautions (8)\"");
    // Sections of one manual in a row share its title; another manual starts anew.
    CHECK(cite({"fixed-cycles/basic", "fixed-cycles/alarms", "tap-cycle/args"}) ==
          "Fixed cycles manual, \"Basic motion\", \"Cautions: examples of resolving alarms\"; "
          "Tap cycle (2) manual, \"Argument list\"");
    CHECK_THROWS_AS(cite("fixed-cycles/g999"), std::out_of_range);
    CHECK_THROWS_AS(cite("no-such-manual"), std::out_of_range);
}

TEST_CASE("citations: a catalog source resolves to the innermost section holding it") {
    const ManualSection* s = section_at("004:L199");
    REQUIRE(s != nullptr);
    CHECK(s->key == "fixed-cycles/g84-normal");
    s = section_at("000:L552-648");  // a whole macro: its section, not the first subsection
    REQUIRE(s != nullptr);
    CHECK(s->key == "back-counterboring/ozagr");
    s = section_at("000:L26-30, L42");
    REQUIRE(s != nullptr);
    CHECK(s->key == "back-counterboring/common-3");
    CHECK(cite_source("003:L103") == "Tap cycle (2) manual, \"Cautions (8)\"");
    CHECK(section_at("003:L1-333") == nullptr);  // the whole manual: no one section
    CHECK(cite_source("003:L1-333") == "");
    CHECK(section_at("009:L1") == nullptr);
    CHECK(section_at("shop manual p. 12") == nullptr);
    CHECK(cite_source("") == "");
}

TEST_CASE("citations: every key the sources cite is in the table") {
    std::set<std::string> used;
    for (const char* dir : {"rules", "src", "cli"}) {
        for (const auto& e : fs::recursive_directory_iterator(source_dir() / dir)) {
            auto ext = e.path().extension();
            if (!e.is_regular_file() || (ext != ".cpp" && ext != ".h")) continue;
            if (e.path().filename() == "citations.h") continue;  // its examples
            for (const auto& k : keys_cited_in(read_file(e.path()))) used.insert(k);
        }
    }
    // The rules of the fixed cycles and of G114 cite by key: a scan that finds
    // none is broken.
    REQUIRE(used.size() >= 10);
    for (const auto& k : used) {
        CAPTURE(k);
        CHECK((find_section(k) != nullptr || find_manual(k) != nullptr));
        CHECK_NOTHROW(cite(k));
    }
}

TEST_CASE("citations: every source of the shipped catalog names a section") {
    Catalog cat = Catalog::builtin();
    std::size_t sources = 0;
    auto check = [&](const std::string& where, const std::string& source) {
        if (source.empty()) return;
        ++sources;
        CAPTURE(where);
        CAPTURE(source);
        // Each line it names lies in a section of the manual; a range over
        // several sections (a whole manual) cites the manual alone.
        static const std::regex lines(R"(^([0-9]{3}):L([0-9]+)(?:-([0-9]+))?)");
        std::smatch m;
        REQUIRE(std::regex_search(source, m, lines));
        CHECK(section_at(m[1].str() + ":L" + m[2].str()) != nullptr);
        if (m[3].matched) CHECK(section_at(m[1].str() + ":L" + m[3].str()) != nullptr);
    };
    auto check_spec = [&](const MacroSpec& m) {
        // Every entry names a manual of the table, except the G codes known
        // only by name (G73, G74, G76: no manual describes them).
        if (!m.manual.empty() || !m.args.empty())
            CHECK_MESSAGE(find_manual(m.manual) != nullptr, m.name << ": manual \"" << m.manual << "\"");
        check(m.name, m.source);
        for (const auto& f : m.formats) check(m.name + " format", f.source);
        if (m.gcode_form) check(m.name + " gcode", m.gcode_form->source);
        for (const auto& a : m.args) check(m.name + " " + a.name, a.source);
        for (const auto& r : m.at_least_one) check(m.name + " at least one", r.source);
        for (const auto& r : m.relations) check(m.name + " relation", r.source);
        for (const auto& st : m.action) check(m.name + " step " + st.step, st.source);
        for (const auto& n : m.notes) check(m.name + " note", n.source);
        if (const CommonRules* c = m.common.empty() ? nullptr : cat.common_rules(m.common)) {
            check(c->id, c->source);
            for (const auto& n : c->notes) check(c->id + " note", n.source);
        }
        if (const PlaneTable* p = m.plane_table.empty() ? nullptr : cat.plane_table(m.plane_table))
            check(p->id, p->source);
    };
    for (const auto& m : cat.macros()) check_spec(m);
    for (const auto& c : cat.cycles()) check_spec(c);
    CHECK(sources > 500);
}

TEST_CASE("no internal reference in findings, notes, explain pages, macro cards or docs") {
    std::size_t texts = 0;
    auto check = [&](const std::string& where, const std::string& text) {
        ++texts;
        std::string found = internal_reference(text);
        CHECK_MESSAGE(found.empty(), where << ": " << found << "\n  in: " << text.substr(0, 300));
    };

    // Every rule's fixtures and the examples, with every rule enabled.
    std::vector<fs::path> files = programs_under(source_dir() / "tests" / "rules");
    for (const auto& f : programs_under(source_dir() / "examples")) files.push_back(f);
    std::size_t findings = 0;
    for (const auto& f : files) {
        AnalysisOptions options;
        ProgramNames names;
        SubprogramDirectories().add_names(f.parent_path(), names);
        options.known_programs = &names;
        FileResult r = check_text(f.string(), read_file(f), config_for(f.parent_path()), options);
        for (const auto& d : r.diagnostics) {
            ++findings;
            check(f.string() + " " + d.rule, d.message);
            for (const auto& n : d.notes) check(f.string() + " " + d.rule + " note", n.message);
            for (const auto& x : d.fixes) check(f.string() + " " + d.rule + " fix", x.title);
        }
    }
    CHECK(findings > 100);

    // `osplint explain OSPnnn`: the rule's page.
    for (const auto& meta : all_rules()) {
        auto doc = embedded::find("docs/rules/" + std::string(meta.id) + ".md");
        REQUIRE(doc.has_value());
        check("explain " + std::string(meta.id), std::string(*doc));
        check(std::string(meta.id) + " summary", std::string(meta.summary));
    }

    // `osplint explain NAME` and the hover: every macro's and cycle's card.
    Catalog cat = Catalog::builtin();
    for (const auto& m : cat.macros()) {
        check("card " + m.name, cat.render_card(m, false));
        check("hover " + m.name, cat.render_card(m, true));
    }
    for (const auto& c : cat.cycles()) {
        check("card " + c.name, cat.render_card(c, false));
        check("hover " + c.name, cat.render_card(c, true));
    }

    // Every page of docs/ and the README, without their code.
    std::vector<fs::path> pages = {source_dir() / "README.md"};
    for (const auto& e : fs::recursive_directory_iterator(source_dir() / "docs"))
        if (e.is_regular_file() && e.path().extension() == ".md") pages.push_back(e.path());
    CHECK(pages.size() > 50);
    for (const auto& p : pages) check(p.string(), prose_of(read_file(p)));
    CHECK(texts > 500);
}

TEST_CASE("the internal-reference check finds what it is meant to find") {
    CHECK(!internal_reference("(seed 004 L18-20)").empty());
    CHECK(!internal_reference("Seed 003 does not mention G99").empty());
    CHECK(!internal_reference("PFA default (A-08)").empty());
    CHECK(!internal_reference("as printed (000:L173)").empty());
    CHECK(!internal_reference("(L307\u2013311)").empty());
    CHECK(internal_reference("(Fixed cycles manual, \"G84 Tap cycle\") VC120-VC128, G81-G89, OG87C").empty());
    CHECK(prose_of("a `000:L5` b\n```toml\nsource = \"000:L5\"\n```\nc\n").find("000:L5") == std::string::npos);
}
