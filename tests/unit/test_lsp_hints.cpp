// Language server inlay hints (the cycle axis's reach from the motion
// evaluator, an expression argument's value) and signature help, through a
// scripted client, in UTF-8 and UTF-16.
#include <doctest/doctest.h>

#include <atomic>
#include <string>
#include <vector>

#include "lsp/hints.h"
#include "lsp_session.h"

using namespace osplint;
using namespace osplint::lsp;
using namespace osplint::lsp::testing;

namespace {

const std::string kUri = "untitled:HINTS.MIN";

const std::vector<std::string> kLines = {
    "O1",                                                                                       // 0
    "G17 G90 G0 X0 Y0",                                                                         // 1
    "(\xE8\xA3\x8F\xE3\x82\xB6\xE3\x82\xB0\xE3\x83\xAA) CALL OZAGR PX=0 PY=0 PR=5. PZ=-20. PI=12.",  // 2 (裏ザグリ)
    "VC1=-20",                                                                                  // 3
    "CALL OZAGR PX=0 PY=0 PR=5. PZ=VC1 PI=12. (\xF0\x9F\x94\xA7)",                              // 4 (🔧)
    "G81 X10. Z-3. R3. F100",                                                                   // 5
    "G80",                                                                                      // 6
    "M30",                                                                                      // 7
};

std::string joined(const std::vector<std::string>& lines) {
    std::string out;
    for (const auto& l : lines) out += l + "\n";
    return out;
}

uint32_t end_of(const std::string& line, bool utf8) { return col(line + "\x01", "\x01", utf8); }

}  // namespace

TEST_CASE("lsp: inlay hints: the cycle axis's reach after a call or a hole, an expression's value") {
    for (bool utf8 : {true, false}) {
        CAPTURE(utf8);
        Session s;
        json init = s.initialize(utf8);
        CHECK(init["capabilities"]["inlayHintProvider"] == true);
        s.open(kUri, joined(kLines));
        s.diagnostics(kUri, 1);
        json hints = s.result("textDocument/inlayHint", {{"textDocument", td(kUri)}, {"range", range(0, 0, 8, 0)}});
        REQUIRE(hints.is_array());
        auto find = [&](int line, const std::string& label) -> const json* {
            for (const auto& h : hints)
                if (h["position"]["line"] == line && h["label"] == label) return &h;
            return nullptr;
        };
        // CALL OZAGR PR=5 PZ=-20 PI=12: down to PZ-PI-PL = -37, up to PR = 5; at the end of the line.
        const json* call = find(2, "\xE2\xA4\x93 Z-37 \xE2\xA4\x92 Z5");
        REQUIRE(call);
        CHECK((*call)["position"] == pos(2, end_of(kLines[2], utf8)));
        CHECK((*call)["tooltip"]["value"].get<std::string>().find("PZ-PI-PL = -20-12-5 = -37") != std::string::npos);
        // PZ=VC1: its value after the word, and the same reach (at the end, after the emoji).
        const json* value = find(4, "= -20");
        REQUIRE(value);
        CHECK((*value)["position"] == pos(4, col(kLines[4], "PZ=VC1", utf8) + 6));
        const json* call2 = find(4, "\xE2\xA4\x93 Z-37 \xE2\xA4\x92 Z5");
        REQUIRE(call2);
        CHECK((*call2)["position"] == pos(4, end_of(kLines[4], utf8)));
        // A literal argument gets no value hint.
        CHECK_FALSE(find(2, "= -20"));
        // The G81 hole: the CALL before it leaves Z at its last step, PR = 5, so the
        // I point is known: from Z5 down to Z-3.
        CHECK(find(5, "\xE2\xA4\x93 Z-3 \xE2\xA4\x92 Z5"));
        CHECK(hints.size() == 4);

        // A range: only its lines.
        json part = s.result("textDocument/inlayHint", {{"textDocument", td(kUri)}, {"range", range(5, 0, 5, 3)}});
        REQUIRE(part.size() == 1);
        CHECK(part[0]["position"]["line"] == 5);
    }
}

TEST_CASE("lsp: signature help: the macro's arguments, the one under the cursor") {
    Session s;
    json init = s.initialize(false);
    CHECK(init["capabilities"]["signatureHelpProvider"]["triggerCharacters"] == json::array({" ", "="}));
    const std::string line = "CALL OZAGR (\xF0\x9F\x94\xA7) PR=5 PZ=-20 ";
    s.open(kUri, "O1\n" + line + "\nCALL OSUBX PR=1\nM30\n");
    s.diagnostics(kUri, 1);
    auto help = [&](uint32_t l, uint32_t c) {
        return s.result("textDocument/signatureHelp", {{"textDocument", td(kUri)}, {"position", pos(l, c)}});
    };
    auto active_label = [](const json& h) {
        const json& sig = h["signatures"][0];
        const json& p = sig["parameters"][h["activeParameter"].get<int>()];
        const std::string label = sig["label"];
        return label.substr(p["label"][0].get<size_t>(), p["label"][1].get<size_t>() - p["label"][0].get<size_t>());
    };
    // On PZ (columns in UTF-16, after the emoji).
    json h = help(1, col(line, "PZ=", false) + 1);
    REQUIRE(h.is_object());
    CHECK(h["signatures"][0]["label"].get<std::string>().rfind("CALL OZAGR ", 0) == 0);
    CHECK(active_label(h) == "PZ");
    const json& sig = h["signatures"][0];
    const json& pz = sig["parameters"][h["activeParameter"].get<int>()];
    CHECK(pz["documentation"]["value"].get<std::string>().find("**PZ**") != std::string::npos);
    CHECK(pz["documentation"]["value"].get<std::string>().find("If omitted: required") != std::string::npos);
    // After the last argument: the next required one not given (PI).
    CHECK(active_label(help(1, col(line + "|", "|", false))) == "PI");
    // On the macro name, inside the comment, after a CALL of a program the catalog does not know: nothing.
    CHECK(help(1, 7).is_null());
    CHECK(help(1, col(line, ")", false)).is_null());
    CHECK(help(2, 14).is_null());
}

TEST_CASE("lsp: inlay hints: the walk stops when the text is outdated") {
    // 3,000 calls, one hint each; with the flag set the walk stops within its
    // first 1,024 blocks (the engine looks at the flag every 1,024 blocks).
    std::string text = "O1\nG17 G90 G0 X0 Y0\n";
    for (int i = 0; i < 3000; ++i) text += "CALL OZAGR PX=0 PY=0 PR=5. PZ=-20. PI=12.\n";
    text += "M30\n";
    DocumentModel doc;
    doc.path = "HINTS.MIN";
    doc.set_text(text);
    const Config config;
    std::atomic<bool> outdated{false};
    const json all = inlay_hints(doc, config, nullptr, nullptr, 1, 4000, Encoding::Utf8, &outdated);
    CHECK(all.size() == 3000);
    outdated = true;
    const json stopped = inlay_hints(doc, config, nullptr, nullptr, 1, 4000, Encoding::Utf8, &outdated);
    CHECK(stopped.size() <= 1024);
}
