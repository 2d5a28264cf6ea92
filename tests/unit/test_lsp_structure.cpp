// Language server structure, through a scripted client: folding ranges,
// semantic tokens (in UTF-8 and UTF-16 columns) and workspace symbols.
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <tuple>

#include "lsp/structure.h"
#include "lsp_session.h"

using namespace osplint;
using namespace osplint::lsp;
using namespace osplint::lsp::testing;
namespace fs = std::filesystem;

namespace {

const std::string kUri = "untitled:LOOPS.MIN";

const std::vector<std::string> kLines = {
    "(PART 1)",                                             // 0
    "(OP 10)",                                              // 1
    "(SECOND COMMENT)",                                     // 2
    "OMAIN",                                                // 3
    "VC1=0 (\xE8\xA3\x8F)",                                 // 4  (裏)
    "WHILE [VC1 LT 3] DO 1",                                // 5
    "  G0 X=VC1*10 Y0",                                     // 6
    "  VC1=VC1+1",                                          // 7
    "END 1",                                                // 8
    "MODIN OSUB PX=1",                                      // 9
    "(\xE8\xA3\x8F) G0 X10 Y10",                            // 10
    "MODOUT",                                               // 11
    "N100 CALL OSUB PX=VC2 (\xF0\x9F\x94\xA7)",             // 12 (🔧)
    "M30",                                                  // 13
    "OSUB",                                                 // 14
    "DO 2",                                                 // 15
    "IF [PX GT 3] N9",                                      // 16
    "END 2",                                                // 17
    "N9 RTS",                                               // 18
};

std::string joined(const std::vector<std::string>& lines) {
    std::string out;
    for (const auto& l : lines) out += l + "\n";
    return out;
}

using Fold = std::tuple<int, int, std::string>;

// Absolute (line, column, length, type name, modifiers) of encoded tokens.
struct Tok {
    int line, col, len;
    std::string type;
    int mods;
    friend bool operator==(const Tok&, const Tok&) = default;
};
std::vector<Tok> decode(const json& data, const json& legend) {
    std::vector<Tok> out;
    int line = 0, col = 0;
    for (size_t i = 0; i + 5 <= data.size(); i += 5) {
        const int dl = data[i], dc = data[i + 1];
        line += dl;
        col = dl ? dc : col + dc;
        out.push_back({line, col, data[i + 2].get<int>(), legend["tokenTypes"][data[i + 3].get<int>()], data[i + 4]});
    }
    return out;
}

bool has(const std::vector<Tok>& toks, const Tok& t) { return std::find(toks.begin(), toks.end(), t) != toks.end(); }

}  // namespace

TEST_CASE("lsp: folding ranges: programs, WHILE and DO loops, MODIN...MODOUT, comment runs") {
    Session s;
    json init = s.initialize();
    CHECK(init["capabilities"]["foldingRangeProvider"] == true);
    s.open(kUri, joined(kLines));
    s.diagnostics(kUri, 1);
    json folds = s.result("textDocument/foldingRange", {{"textDocument", td(kUri)}});
    std::set<Fold> got;
    for (const auto& f : folds) got.insert({f["startLine"], f["endLine"], f.value("kind", "")});
    const std::set<Fold> want = {
        {0, 13, ""},         // the first program (its header comments included)
        {0, 2, "comment"},   // the comment run
        {5, 8, ""},          // WHILE ... DO 1 ... END 1
        {9, 11, ""},         // MODIN ... MODOUT
        {14, 18, ""},        // OSUB
        {15, 17, ""},        // DO 2 ... END 2
    };
    CHECK(got == want);
    CHECK(folds.size() == want.size());
}

TEST_CASE("lsp: semantic tokens: calls, arguments, sequence names, variables, comments, G/M codes") {
    for (bool utf8 : {true, false}) {
        CAPTURE(utf8);
        Session s;
        json init = s.initialize(utf8);
        const json& provider = init["capabilities"]["semanticTokensProvider"];
        CHECK(provider["full"] == true);
        CHECK(provider["range"] == true);
        const json legend = provider["legend"];
        REQUIRE(legend["tokenTypes"].size() == std::size(kTokenTypes));
        CHECK(legend["tokenModifiers"][0] == "declaration");
        s.open(kUri, joined(kLines));
        s.diagnostics(kUri, 1);
        json full = s.result("textDocument/semanticTokens/full", {{"textDocument", td(kUri)}});
        REQUIRE(full["data"].size() % 5 == 0);
        const auto toks = decode(full["data"], legend);
        const int narrow = utf8 ? 3 : 1;  // 裏 in each encoding
        const int wide = utf8 ? 4 : 2;    // 🔧
        CHECK(has(toks, {3, 0, 5, "function", 1}));                         // OMAIN
        CHECK(has(toks, {4, 0, 3, "variable", 0}));                         // VC1
        CHECK(has(toks, {4, 6, 2 + narrow, "comment", 0}));                 // (裏)
        CHECK(has(toks, {5, 0, 5, "keyword", 0}));                          // WHILE
        CHECK(has(toks, {6, 2, 2, "macro", 0}));                            // G0
        CHECK(has(toks, {6, 7, 3, "variable", 0}));                         // VC1 in X=VC1*10
        CHECK(has(toks, {9, 0, 5, "keyword", 0}));                          // MODIN
        CHECK(has(toks, {9, 6, 4, "function", 0}));                         // OSUB
        CHECK(has(toks, {9, 11, 2, "parameter", 0}));                       // PX
        CHECK(has(toks, {10, 0, 2 + narrow, "comment", 0}));                // (裏)
        CHECK(has(toks, {10, 3 + narrow, 2, "macro", 0}));                  // G0 after the comment
        CHECK(has(toks, {12, 0, 4, "label", 1}));                           // N100
        CHECK(has(toks, {12, 10, 4, "function", 0}));                       // OSUB
        CHECK(has(toks, {12, 15, 2, "parameter", 0}));                      // PX
        CHECK(has(toks, {12, 18, 3, "variable", 0}));                       // VC2
        CHECK(has(toks, {12, 22, 2 + wide, "comment", 0}));                 // (🔧)
        CHECK(has(toks, {13, 0, 3, "macro", 0}));                           // M30
        CHECK(has(toks, {16, 13, 2, "label", 0}));                          // IF target N9
        CHECK(has(toks, {18, 0, 2, "label", 1}));                           // N9
        CHECK(has(toks, {18, 3, 3, "keyword", 0}));                         // RTS
        // In order, never overlapping.
        for (size_t i = 1; i < toks.size(); ++i) {
            const bool ordered = toks[i].line > toks[i - 1].line ||
                                 (toks[i].line == toks[i - 1].line && toks[i].col >= toks[i - 1].col + toks[i - 1].len);
            CHECK(ordered);
        }
        // A range: only the tokens of its lines, the first relative to line 0.
        json part = s.result("textDocument/semanticTokens/range", {{"textDocument", td(kUri)}, {"range", range(12, 0, 12, 5)}});
        const auto line12 = decode(part["data"], legend);
        REQUIRE(!line12.empty());
        for (const auto& t : line12) CHECK(t.line == 12);
        CHECK(line12.size() == 6);
    }
}

TEST_CASE("lsp: workspace symbols: the programs of the open documents and of the folder") {
    const fs::path dir = fs::temp_directory_path() / ("osplint-wsym-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "lib");
    fs::create_directories(dir / ".hidden");
    auto write = [&](const fs::path& p, const std::string& text) { std::ofstream(dir / p, std::ios::binary) << text; };
    write("A.MIN", "OMAIN\nCALL OSUB\nM30\nOSUB\nRTS\n");
    write("lib/TOOLS.lib", "OTLCHG\nRTS\nOSUB2\nRTS\n");
    write("B.MIN", "ODISK\nM30\n");
    write("README.TXT", "OFAKE\n");
    write(".hidden/X.MIN", "OHIDE\nM30\n");
    {
        Session s;
        json init = s.initialize(true, {{"rootUri", path_to_uri(dir.string())}});
        CHECK(init["capabilities"]["workspaceSymbolProvider"] == true);
        // The open document's text, not the file's, counts.
        const std::string b = path_to_uri((dir / "B.MIN").string());
        s.open(b, "OOPEN\nM30\n");
        s.diagnostics(b, 1);
        auto names = [&](const std::string& query) {
            std::set<std::string> out;
            for (const auto& sym : s.result("workspace/symbol", {{"query", query}})) out.insert(sym["name"]);
            return out;
        };
        CHECK(names("") == std::set<std::string>{"OMAIN", "OSUB", "OTLCHG", "OSUB2", "OOPEN"});
        CHECK(names("sub") == std::set<std::string>{"OSUB", "OSUB2"});
        json tl = s.result("workspace/symbol", {{"query", "TLCH"}});
        REQUIRE(tl.size() == 1);
        CHECK(tl[0]["kind"] == 12);
        CHECK(tl[0]["location"]["uri"] == path_to_uri((dir / "lib" / "TOOLS.lib").string()));
        CHECK(tl[0]["location"]["range"] == range(0, 0, 0, 6));
        CHECK(tl[0]["containerName"] == "TOOLS.lib");
    }
    fs::remove_all(dir);
}
