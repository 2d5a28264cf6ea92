// Language server navigation, through a scripted client: definition,
// references, document highlight and rename of sequence names and programs,
// across open documents and subprogram files on disk, in UTF-8 and UTF-16.
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "lsp/navigation.h"
#include "lsp_session.h"

using namespace osplint;
using namespace osplint::lsp;
using namespace osplint::lsp::testing;
namespace fs = std::filesystem;

namespace {

// Lines of the main program; the comments with non-ASCII text move the later
// columns differently in the two encodings.
const std::vector<std::string> kMain = {
    "OMAIN (\xE8\xA3\x8F\xE3\x82\xB6\xE3\x82\xB0\xE3\x83\xAA \xF0\x9F\x94\xA7)",  // 0  (裏ザグリ 🔧)
    "N10 G0 G90 X0 Y0",                                                          // 1
    "(\xE8\xA3\x8F) IF [VC1 EQ 0] N20",                                          // 2
    "GOTO N10",                                                                  // 3
    "N20 CALL OSUBA",                                                            // 4
    "(\xF0\x9F\x94\xA7) CALL OSUBB",                                             // 5
    "MODIN OSUBC PX=1",                                                          // 6
    "MODOUT",                                                                    // 7
    "N20 M9",                                                                    // 8
    "M30",                                                                       // 9
    "OSUBA",                                                                     // 10
    "N10 G1 X1",                                                                 // 11
    "GOTO N10",                                                                  // 12
    "RTS",                                                                       // 13
};

std::string joined(const std::vector<std::string>& lines) {
    std::string out;
    for (const auto& l : lines) out += l + "\n";
    return out;
}

struct Folder {
    fs::path dir;
    explicit Folder(const std::string& tag) {
        dir = fs::temp_directory_path() / ("osplint-nav-" + tag + "-" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~Folder() { fs::remove_all(dir); }
    void write(const std::string& name, const std::string& text) const {
        std::ofstream(dir / name, std::ios::binary) << text;
    }
    std::string uri(const std::string& name) const { return path_to_uri((dir / name).string()); }
};

json at(const std::string& uri, uint32_t line, uint32_t character) {
    return {{"textDocument", td(uri)}, {"position", pos(line, character)}};
}

// The (line, start character) of each location or range, in order.
std::vector<std::pair<int, int>> starts(const json& list) {
    std::vector<std::pair<int, int>> out;
    for (const auto& l : list) {
        const json& r = l.contains("range") ? l["range"] : l;
        out.push_back({r["start"]["line"].get<int>(), r["start"]["character"].get<int>()});
    }
    return out;
}

}  // namespace

TEST_CASE("lsp: navigation: definition, references, highlight and rename, in both encodings") {
    for (bool utf8 : {true, false}) {
        CAPTURE(utf8);
        Folder f(utf8 ? "8" : "16");
        // A subprogram file on disk (lower-case extension), and a file that is not one.
        f.write("shop.ssb", "(LIB)\nOSUBC\nG0 X0\nRTS\n");
        f.write("NOTES.TXT", "OSUBC\n");
        const std::string main = f.uri("MAIN.MIN");
        const std::string other = f.uri("OTHER.SSB");
        Session s;
        json init = s.initialize(utf8);
        const json& caps = init["capabilities"];
        CHECK(caps["definitionProvider"] == true);
        CHECK(caps["referencesProvider"] == true);
        CHECK(caps["documentHighlightProvider"] == true);
        CHECK(caps["renameProvider"]["prepareProvider"] == true);
        s.open(other, "OSUBB\nCALL OSUBC\nRTS\n");
        s.diagnostics(other, 1);
        s.open(main, joined(kMain));
        s.diagnostics(main, 1);
        auto c = [&](int line, const std::string& needle) {
            return static_cast<int>(col(kMain[line], needle, utf8));
        };

        // GOTO N10 in the main program: its N10, not the subprogram's.
        json d = s.result("textDocument/definition", at(main, 3, 6));
        REQUIRE(d.size() == 1);
        CHECK(d[0]["uri"] == main);
        CHECK(d[0]["range"] == range(1, 0, 1, 3));
        // IF ... N20 (after a non-ASCII comment): both definitions of N20.
        d = s.result("textDocument/definition", at(main, 2, c(2, "N20") + 1));
        CHECK(starts(d) == std::vector<std::pair<int, int>>{{4, 0}, {8, 0}});
        // GOTO N10 in the subprogram: the subprogram's N10.
        d = s.result("textDocument/definition", at(main, 12, 7));  // cursor just after the name
        CHECK(starts(d) == std::vector<std::pair<int, int>>{{11, 0}});
        // CALL OSUBA: the program in this document.
        d = s.result("textDocument/definition", at(main, 4, c(4, "OSUBA") + 2));
        REQUIRE(d.size() == 1);
        CHECK(d[0]["uri"] == main);
        CHECK(d[0]["range"] == range(10, 0, 10, 5));
        // CALL OSUBB: another open document.
        d = s.result("textDocument/definition", at(main, 5, c(5, "OSUBB")));
        REQUIRE(d.size() == 1);
        CHECK(d[0]["uri"] == other);
        CHECK(d[0]["range"] == range(0, 0, 0, 5));
        // MODIN OSUBC: the subprogram file on disk.
        d = s.result("textDocument/definition", at(main, 6, 8));
        REQUIRE(d.size() == 1);
        CHECK(d[0]["uri"] == f.uri("shop.ssb"));
        CHECK(d[0]["range"] == range(1, 0, 1, 5));
        // Not a name: nothing.
        CHECK(s.result("textDocument/definition", at(main, 1, 8)) == json::array());

        // References of N20, with and without its definitions.
        json r = s.result("textDocument/references",
                          {{"textDocument", td(main)}, {"position", pos(4, 1)}, {"context", {{"includeDeclaration", true}}}});
        CHECK(starts(r) == std::vector<std::pair<int, int>>{{2, c(2, "N20")}, {4, 0}, {8, 0}});
        r = s.result("textDocument/references",
                     {{"textDocument", td(main)}, {"position", pos(4, 1)}, {"context", {{"includeDeclaration", false}}}});
        REQUIRE(r.size() == 1);
        CHECK(r[0]["range"] == range(2, c(2, "N20"), 2, c(2, "N20") + 3));
        // References of OSUBC: the MODIN here, the CALL in the other document, its definition on disk.
        r = s.result("textDocument/references", {{"textDocument", td(main)},
                                                 {"position", pos(6, 7)},
                                                 {"context", {{"includeDeclaration", true}}}});
        std::set<std::string> where;
        for (const auto& l : r)
            where.insert(l["uri"].get<std::string>() + ":" + std::to_string(l["range"]["start"]["line"].get<int>()));
        CHECK(where == std::set<std::string>{main + ":6", other + ":1", f.uri("shop.ssb") + ":1"});

        // Highlight: the definition is written (3), the jump read (2).
        json h = s.result("textDocument/documentHighlight", at(main, 1, 1));
        REQUIRE(h.size() == 2);
        CHECK(h[0]["range"] == range(1, 0, 1, 3));
        CHECK(h[0]["kind"] == 3);
        CHECK(h[1]["range"] == range(3, 5, 3, 8));
        CHECK(h[1]["kind"] == 2);

        // prepareRename: a sequence name only.
        json pr = s.result("textDocument/prepareRename", at(main, 2, c(2, "N20") + 2));
        CHECK(pr["range"] == range(2, c(2, "N20"), 2, c(2, "N20") + 3));
        CHECK(pr["placeholder"] == "N20");
        CHECK(s.result("textDocument/prepareRename", at(main, 0, 2)).is_null());
        CHECK(s.result("textDocument/prepareRename", at(main, 4, c(4, "OSUBA"))).is_null());

        // Rename N20: every definition and jump of the main program.
        json edit = s.result("textDocument/rename",
                             {{"textDocument", td(main)}, {"position", pos(8, 0)}, {"newName", "NEND"}});
        json edits = edit["changes"][main];
        CHECK(starts(edits) == std::vector<std::pair<int, int>>{{2, c(2, "N20")}, {4, 0}, {8, 0}});
        for (const auto& e : edits) CHECK(e["newText"] == "NEND");
        CHECK(edits[0]["range"] == range(2, c(2, "N20"), 2, c(2, "N20") + 3));
        // Rename N10 of the subprogram: its own two sites only.
        edit = s.result("textDocument/rename", {{"textDocument", td(main)}, {"position", pos(11, 2)}, {"newName", "n11"}});
        CHECK(starts(edit["changes"][main]) == std::vector<std::pair<int, int>>{{11, 0}, {12, 5}});
        // Invalid new names, a name the program already has, a position that is no sequence name.
        for (const char* bad : {"NCYL", "NOEX", "X20", "N", "N 2", "N-1", "", "N20)", "N1.5"}) {
            CAPTURE(bad);
            json e = s.request("textDocument/rename",
                               {{"textDocument", td(main)}, {"position", pos(8, 0)}, {"newName", bad}});
            CHECK(e["error"]["code"] == error::kInvalidParams);
        }
        CHECK(s.request("textDocument/rename", {{"textDocument", td(main)}, {"position", pos(8, 0)}, {"newName", "N10"}})
                  ["error"]["code"] == error::kInvalidParams);
        CHECK(s.request("textDocument/rename", {{"textDocument", td(main)}, {"position", pos(4, 6)}, {"newName", "N30"}})
                  ["error"]["code"] == error::kInvalidParams);

        // Applying the rename as the client would leaves no unknown jump target.
        json changes = json::array();
        for (auto it = edits.rbegin(); it != edits.rend(); ++it)
            changes.push_back({{"range", (*it)["range"]}, {"text", (*it)["newText"]}});
        s.change(main, 2, changes);
        json after = s.diagnostics(main, 2);
        CHECK_FALSE(find_code(after["diagnostics"], "OSP002"));
        d = s.result("textDocument/definition", at(main, 2, c(2, "N20") + 1));
        CHECK(starts(d) == std::vector<std::pair<int, int>>{{4, 0}, {8, 0}});
        CHECK(s.result("shutdown", nullptr).is_null());
    }
}

TEST_CASE("lsp: navigation: valid_sequence_name follows the front end") {
    CHECK(valid_sequence_name("N1"));
    CHECK(valid_sequence_name("NEND"));
    CHECK(valid_sequence_name("nskip"));
    CHECK(valid_sequence_name("N850020"));
    CHECK_FALSE(valid_sequence_name("NCYL"));
    CHECK_FALSE(valid_sequence_name("NOEX"));
    CHECK_FALSE(valid_sequence_name("N"));
    CHECK_FALSE(valid_sequence_name("O100"));
    CHECK_FALSE(valid_sequence_name("N1 2"));
    CHECK_FALSE(valid_sequence_name("N=1"));
}
