// Language server transcripts: framed messages in, framed messages out, over
// an in-memory transport, with the server's message loop on its own thread.
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <thread>

#include "lsp/server.h"
#include "lsp_session.h"

using namespace osplint;
using namespace osplint::lsp;
namespace fs = std::filesystem;

using namespace osplint::lsp::testing;

namespace {

const std::string kUri = "untitled:M52CALL.MIN";

// The LSP severity of the OSP104 finding published for `uri` at `version`.
int osp104_severity(Session& s, const std::string& uri, int version) {
    json list = s.diagnostics(uri, version)["diagnostics"];
    const json* d = find_code(list, "OSP104");
    REQUIRE(d);
    return (*d)["severity"].get<int>();
}

const std::string kProgram =
    "O3106\n"                                                         // 0
    "N1 (T31 BIG BACK C'BORE BAR)\n"                                  // 1
    "G15 H1\n"                                                        // 2
    "T31 M6\n"                                                        // 3
    "G0 G90 X0 Y0\n"                                                  // 4
    "G56 Z50. H31\n"                                                  // 5
    "S600 M3\n"                                                       // 6
    "M8\n"                                                            // 7
    "CALL OZAGR PX=70. PY=0 PR=5. PZ=-29. PI=6. PF=50 PS=600\n"       // 8
    "CALL OZAGR PX=-70. PY=0 PR=5. PZ=-29. PI=6. PF=50 PS=600 M52\n"  // 9
    "M9\n"                                                            // 10
    "M5\n"                                                            // 11
    "G30 P1\n"                                                        // 12
    "M30\n";                                                          // 13

}  // namespace

TEST_CASE("lsp: lifecycle: -32002 before initialize, shutdown, exit code 0") {
    Session s;
    json early = s.request("textDocument/hover", {{"textDocument", td(kUri)}, {"position", pos(0, 0)}});
    CHECK(early["error"]["code"] == error::kServerNotInitialized);
    // A notification before initialize is dropped: no diagnostics come for it.
    s.open(kUri, kProgram);
    json init = s.initialize(true);
    CHECK(init["capabilities"]["positionEncoding"] == "utf-8");
    CHECK(init["capabilities"]["textDocumentSync"]["change"] == 2);
    CHECK(init["capabilities"]["hoverProvider"] == true);
    CHECK(init["serverInfo"]["name"] == "osplint");
    CHECK(s.request("initialize", {{"capabilities", json::object()}})["error"]["code"] == error::kInvalidRequest);
    // The document opened before initialize does not exist.
    CHECK(s.result("textDocument/documentSymbol", {{"textDocument", td(kUri)}}) == json::array());
    CHECK(s.result("shutdown", nullptr).is_null());
    CHECK(s.request("textDocument/hover", {{"textDocument", td(kUri)}, {"position", pos(0, 0)}})["error"]["code"] ==
          error::kInvalidRequest);
    s.notify("exit", nullptr);
    CHECK(s.finished_within(kTimeoutMs));
    CHECK(s.exit_code() == 0);
    for (const auto& m : s.seen()) CHECK(m.value("method", "") != "textDocument/publishDiagnostics");
}

TEST_CASE("lsp: lifecycle: exit without shutdown is 1, end of input without exit is 1") {
    {
        Session s;
        s.initialize();
        s.notify("exit", nullptr);
        CHECK(s.finished_within(kTimeoutMs));
        CHECK(s.exit_code() == 1);
    }
    {
        Session s;
        s.notify("exit", nullptr);  // exit is honoured even before initialize
        CHECK(s.finished_within(kTimeoutMs));
        CHECK(s.exit_code() == 1);
    }
    {
        Session s;
        s.initialize();
        CHECK(s.finish() == 1);
    }
}

TEST_CASE("lsp: encoding: utf-16 when the client does not offer utf-8") {
    Session s;
    CHECK(s.initialize(false)["capabilities"]["positionEncoding"] == "utf-16");
}

TEST_CASE("lsp: unknown methods: -32601 for requests, notifications ignored") {
    Session s;
    s.initialize();
    s.notify("osplint/unknownNotification", {{"x", 1}});
    s.notify("$/setTrace", {{"value", "off"}});
    json r = s.request("workspace/executeCommand", {{"command", "x"}});
    CHECK(r["error"]["code"] == error::kMethodNotFound);
    CHECK(s.backlog_size() == 0);  // nothing was sent for the notifications
}

TEST_CASE("lsp: malformed input is answered or skipped, never fatal") {
    Session s;
    s.initialize();
    s.raw("Content-Length: 5\r\n\r\n{bad}");
    json e1 = s.wait([](const json& m) { return m.contains("error"); });
    CHECK(e1["error"]["code"] == error::kParseError);
    CHECK(e1["id"].is_null());
    s.raw("Content-Length: twelve\r\n\r\n{\"jsonrpc\":\"2.0\"}");
    CHECK(s.wait([](const json& m) { return m.contains("error"); })["error"]["code"] == error::kParseError);
    // An absurd length is refused at once; the next request is answered.
    s.raw("Content-Length: 1000000000000\r\n\r\n");
    CHECK(s.wait([](const json& m) { return m.contains("error"); })["error"]["code"] == error::kParseError);
    s.raw("Content-Length: 70000000\r\n\r\n");
    CHECK(s.wait([](const json& m) { return m.contains("error"); })["error"]["code"] == error::kParseError);
    // What follows a refused header is skipped up to the next message, which is answered.
    CHECK(s.result("textDocument/documentSymbol", {{"textDocument", td(kUri)}}) == json::array());
    s.raw("this is not a header\r\n\r\n");
    CHECK(s.wait([](const json& m) { return m.contains("error"); })["error"]["code"] == error::kParseError);
    s.send({{"id", 99}, {"method", "shutdown"}});  // no "jsonrpc"
    json inv = s.wait([](const json& m) { return m.contains("error"); });
    CHECK(inv["error"]["code"] == error::kInvalidRequest);
    CHECK(inv["id"] == 99);
    // Bad params: -32602, the server goes on.
    CHECK(s.request("textDocument/hover", {{"textDocument", 3}})["error"]["code"] == error::kInvalidParams);
    s.notify("textDocument/didOpen", {{"textDocument", {{"uri", 5}}}});
    CHECK(s.result("shutdown", nullptr).is_null());
}

TEST_CASE("lsp: 1,000 random byte strings leave the server alive") {
    Session s;
    s.initialize();
    std::mt19937 rng(7);
    int framed_errors = 0;
    for (int i = 0; i < 1000; ++i) {
        std::string junk(1 + rng() % 200, '\0');
        for (auto& c : junk) c = static_cast<char>(rng() % 256);
        if (i % 2 == 0) {
            s.raw(frame(junk));  // framed: the body is junk
            ++framed_errors;
        } else {
            s.raw(junk);  // unframed: junk between messages
            s.raw("\r\n\r\n");
        }
    }
    // Every framed junk body was answered with an error (parse error or invalid request).
    int errors = 0;
    json r = s.wait([&](const json& m) {
        if (m.contains("error") && m["id"].is_null()) ++errors;
        return errors >= framed_errors;
    });
    CHECK(errors >= framed_errors);
    json after = s.request("shutdown", nullptr);
    CHECK(after.contains("result"));
    s.notify("exit", nullptr);
    CHECK(s.finished_within(kTimeoutMs));
    CHECK(s.exit_code() == 0);
}

TEST_CASE("lsp: diagnostics: code, link, severity, notes, fixes in data, version; didClose clears") {
    Session s;
    s.initialize();
    s.open(kUri, kProgram, 3);
    json p = s.diagnostics(kUri, 3);
    CHECK(p["version"] == 3);
    const json* d = find_code(p["diagnostics"], "OSP104");
    REQUIRE(d);
    CHECK((*d)["source"] == "osplint");
    CHECK((*d)["severity"] == 1);
    CHECK((*d)["codeDescription"]["href"] == "https://github.com/osplint/osplint/blob/main/docs/rules/OSP104.md");
    const std::string line9 = "CALL OZAGR PX=-70. PY=0 PR=5. PZ=-29. PI=6. PF=50 PS=600 M52";
    CHECK((*d)["range"] == range(9, col(line9, "M52", true), 9, col(line9, "M52", true) + 3));
    CHECK((*d)["message"].get<std::string>().find("PM=52") != std::string::npos);
    REQUIRE((*d)["data"]["fixes"].size() >= 1);
    CHECK((*d)["data"]["version"] == 3);
    CHECK((*d)["data"]["fixes"][0]["edits"][0]["newText"] == "PM=52");

    // Notes with a range become relatedInformation (OSP006: a jump to a duplicated name).
    const std::string uri2 = "untitled:DUP.MIN";
    s.open(uri2, "O1\nN10 G0 X0\nN10 G0 X1\nGOTO N10\nM30\n");
    json p2 = s.diagnostics(uri2);
    const json* dup = find_code(p2["diagnostics"], "OSP006");
    REQUIRE(dup);
    REQUIRE(dup->contains("relatedInformation"));
    CHECK((*dup)["relatedInformation"][0]["location"]["uri"] == uri2);
    CHECK((*dup)["relatedInformation"][0]["location"]["range"]["start"]["line"] == 1);
    CHECK((*dup)["relatedInformation"][1]["location"]["range"]["start"]["line"] == 2);
    CHECK(find_code(p2["diagnostics"], "OSP003") == nullptr);  // off by default

    s.notify("textDocument/didClose", {{"textDocument", td(kUri)}});
    json cleared = s.diagnostics(kUri);
    CHECK(cleared["diagnostics"].empty());
}

TEST_CASE("lsp: incremental edits with non-ASCII comments, in both encodings") {
    for (bool utf8 : {true, false}) {
        CAPTURE(utf8);
        Session s;
        s.initialize(utf8);
        const std::string comment =
            "(\xE8\xA3\x8F\xE3\x82\xB6\xE3\x82\xB0\xE3\x83\xAA \xF0\x9F\x94\xA7)";  // (裏ザグリ 🔧)
        const std::string line = "CALL OZAGR " + comment + " PX=0 PY=0 PR=5. PZ=-29. PI=6.";
        const std::string text = "O1\nG0 G90 X0 Y0 F300 S800\n" + line + "\nM30\n";
        s.open(kUri, text, 1);
        CHECK(s.diagnostics(kUri, 1)["diagnostics"].empty());

        // Append M52 at the end of the CALL line: a position after the emoji.
        const uint32_t end = col(line + "|", "|", utf8);
        s.change(kUri, 2, json::array({{{"range", range(2, end, 2, end)}, {"text", " M52"}}}));
        json p = s.diagnostics(kUri, 2);
        const json* d = find_code(p["diagnostics"], "OSP104");
        REQUIRE(d);
        const std::string line2 = line + " M52";
        CHECK((*d)["range"] == range(2, col(line2, "M52", utf8), 2, col(line2, "M52", utf8) + 3));

        // The fix from the diagnostic's data, applied as the client would: the
        // edit's range is in the negotiated encoding.
        json fix = (*d)["data"]["fixes"][0]["edits"][0];
        s.change(kUri, 3, json::array({{{"range", fix["range"]}, {"text", fix["newText"]}}}));
        CHECK(s.diagnostics(kUri, 3)["diagnostics"].empty());

        // Several changes in one event, applied in order: type inside the
        // comment (after the emoji), then replace PR=5. by PR=X (OSP103? no: a
        // variable), then a full replacement.
        const std::string line3 = line + " PM=52";
        const uint32_t after_emoji = col(line3, ")", utf8);
        s.change(kUri, 4,
                 json::array({
                     {{"range", range(2, after_emoji, 2, after_emoji)}, {"text", " \xC3\xA9"}},
                     {{"range", range(2, 0, 2, 0)}, {"text", "N5 "}},
                 }));
        json p4 = s.diagnostics(kUri, 4);
        CHECK(p4["diagnostics"].empty());
        json sym = s.result("textDocument/documentSymbol", {{"textDocument", td(kUri)}});
        REQUIRE(sym.size() == 1);
        REQUIRE(sym[0]["children"].size() == 1);
        CHECK(sym[0]["children"][0]["name"] == "N5");
        // Hover on PM (after the edits) still resolves the right word.
        const std::string line4 =
            "N5 CALL OZAGR (\xE8\xA3\x8F\xE3\x82\xB6\xE3\x82\xB0\xE3\x83\xAA \xF0\x9F\x94\xA7 \xC3\xA9)"
            " PX=0 PY=0 PR=5. PZ=-29. PI=6. PM=52";
        json h = s.result("textDocument/hover",
                          {{"textDocument", td(kUri)}, {"position", pos(2, col(line4, "PR=", utf8) + 1)}});
        REQUIRE(h.is_object());
        CHECK(h["contents"]["value"].get<std::string>().find("**PR**") != std::string::npos);
        CHECK(h["range"] == range(2, col(line4, "PR=", utf8), 2, col(line4, "PR=", utf8) + 5));

        s.change(kUri, 5, json::array({{{"text", "O1\nCALL OZAGR PR=5 PZ=-20 PI=12 M52\nM30\n"}}}));
        CHECK(find_code(s.diagnostics(kUri, 5)["diagnostics"], "OSP104"));
    }
}

TEST_CASE("lsp: results for outdated versions are dropped") {
    Session s;
    s.initialize();
    s.open(kUri, kProgram, 1);
    s.diagnostics(kUri, 1);
    for (int v = 2; v <= 30; ++v)
        s.change(kUri, v, json::array({{{"range", range(9, 0, 9, 0)}, {"text", v % 2 ? "" : " "}}}));
    json last = s.diagnostics(kUri, 30);
    CHECK(last["version"] == 30);
    int64_t prev = 0;
    for (const auto& m : s.seen()) {
        if (m.value("method", "") != "textDocument/publishDiagnostics") continue;
        const int64_t v = m["params"]["version"];
        CHECK(v >= prev);
        prev = v;
    }
}

TEST_CASE("lsp: hover: macro card, argument with plane axis, G/M codes with modal state, rule docs") {
    // The modal state of the hovered block comes from a walk of the document
    // up to it.
    ServerOptions options = Session::quiet();
    Session s(options);
    s.initialize();
    const std::string text =
        "O1\n"                                                                     // 0
        "G0 G90 X0 Y0\n"                                                           // 1
        "CALL OZAGR PR=5 PZ=-20 PI=12 (osplint: disable=OSP104 -- checked) M52\n"  // 2
        "G18\n"                                                                    // 3
        "CALL OZAGR PR=5 PZ=-20 PI=12\n"                                           // 4
        "G17 G99\n"                                                                // 5
        "G81 Z-3. R3. F100\n"                                                      // 6
        "G80\n"                                                                    // 7
        "G114 R3. Z-10. F100\n"                                                    // 8
        "G80\n"                                                                    // 9
        "M30\n";                                                                   // 10
    s.open(kUri, text);
    s.diagnostics(kUri, 1);
    auto hover = [&](uint32_t line, uint32_t character) {
        return s.result("textDocument/hover", {{"textDocument", td(kUri)}, {"position", pos(line, character)}});
    };
    auto value = [](const json& h) {
        return h.is_object() ? h["contents"]["value"].get<std::string>() : std::string();
    };

    json card = hover(2, 7);  // OZAGR
    CHECK(card["contents"]["kind"] == "markdown");
    CHECK(value(card).find("OZAGR") != std::string::npos);
    CHECK(value(card).find("Back counterboring with the BIG back-counterbore bar") != std::string::npos);
    CHECK(card["range"] == range(2, 5, 2, 10));

    std::string pr17 = value(hover(2, 12));  // PR=5 in G17
    CHECK(pr17.find("**PR**") != std::string::npos);
    CHECK(pr17.find("Axis: **Z** (plane G17") != std::string::npos);
    CHECK(pr17.find("If omitted: required") != std::string::npos);
    CHECK(pr17.find("Value here: `5`") != std::string::npos);
    // Where the manual prints it: the section, not a line of the manual.
    CHECK(pr17.find("Source: Back counterboring macros manual, \"OZAGR: Argument list\"") != std::string::npos);
    CHECK(pr17.find("000:L") == std::string::npos);
    std::string pr18 = value(hover(4, 12));  // PR=5 in G18
    CHECK(pr18.find("Axis: **Y** (plane G18") != std::string::npos);

    std::string rule = value(hover(2, 51));  // OSP104 inside the directive
    CHECK(rule.find("OSP104") != std::string::npos);
    CHECK(rule.find("m52-on-call-line") != std::string::npos);

    std::string g81 = value(hover(6, 1));
    CHECK(g81.find("**G81** — Fixed cycle: drill cycle") != std::string::npos);
    CHECK(g81.find("| plane | G17 | G17 |") != std::string::npos);
    CHECK(g81.find("| fixed cycle | none | G81 |") != std::string::npos);
    CHECK(g81.find("| cycle return | G99 | G99 |") != std::string::npos);
    std::string g18 = value(hover(3, 1));
    CHECK(g18.find("| plane | G17 | G18 |") != std::string::npos);
    std::string m52 = value(hover(2, 68));
    CHECK(m52.find("**M52**") != std::string::npos);
    CHECK(m52.find("upper limit") != std::string::npos);
    std::string m30 = value(hover(10, 1));
    CHECK(m30.find("Program end") != std::string::npos);

    std::string g114 = value(hover(8, 2));  // a registered G-code macro: its card
    CHECK(g114.find("OG84L") != std::string::npos);
    CHECK(g114.find("Modal state") != std::string::npos);

    CHECK(value(hover(1, 4)).find("Absolute programming") != std::string::npos);  // G90
    CHECK(hover(1, 8).is_null());                                                 // X0: an axis word, nothing to say
    CHECK(hover(0, 0).is_null());                                                 // the program name
}

TEST_CASE("lsp: completion: macro names after CALL/MODIN, then missing arguments, required first") {
    Session s;
    s.initialize();
    const std::string text = "O1\nCALL \nMODIN \nCALL OZAGR PR=5 \nCALL OZAGR PR=5 P\nM30\n";
    s.open(kUri, text);
    auto items = [&](uint32_t line, uint32_t character) {
        json r = s.result("textDocument/completion", {{"textDocument", td(kUri)}, {"position", pos(line, character)}});
        return r.is_object() ? r["items"] : r;
    };
    auto labels = [](const json& list) {
        std::vector<std::string> out;
        for (const auto& i : list) out.push_back(i["label"]);
        return out;
    };
    json call = items(1, 5);
    auto call_labels = labels(call);
    CHECK(std::find(call_labels.begin(), call_labels.end(), "OZAGR") != call_labels.end());
    CHECK(std::find(call_labels.begin(), call_labels.end(), "OG87C") == call_labels.end());  // MODIN only
    for (const auto& i : call)
        if (i["label"] == "OZAGR") CHECK(i["detail"] == "Back counterboring with the BIG back-counterbore bar");
    auto modin_labels = labels(items(2, 6));
    CHECK(std::find(modin_labels.begin(), modin_labels.end(), "OG87C") != modin_labels.end());
    CHECK(std::find(modin_labels.begin(), modin_labels.end(), "OZAGR") == modin_labels.end());

    json args = items(3, 16);
    auto arg_labels = labels(args);
    CHECK(std::find(arg_labels.begin(), arg_labels.end(), "PR") == arg_labels.end());  // given
    REQUIRE(!args.empty());
    std::sort(args.begin(), args.end(), [](const json& a, const json& b) { return a["sortText"] < b["sortText"]; });
    // Required ones first: PZ and PI, then the optional ones.
    CHECK(args[0]["label"] == "PZ");
    CHECK(args[1]["label"] == "PI");
    CHECK(args[0]["insertText"] == "PZ=");
    CHECK(args[0]["detail"].get<std::string>().find("required") != std::string::npos);
    // A partly typed argument is still offered.
    auto partial = labels(items(4, 17));
    CHECK(std::find(partial.begin(), partial.end(), "PZ") != partial.end());
    CHECK(items(0, 1).empty());  // not a CALL line
}

TEST_CASE("lsp: code actions: the fix from data, and a suppression comment") {
    Session s;
    s.initialize(false);
    s.open(kUri, kProgram, 7);
    json p = s.diagnostics(kUri, 7);
    const json* d = find_code(p["diagnostics"], "OSP104");
    REQUIRE(d);
    json actions = s.result(
        "textDocument/codeAction",
        {{"textDocument", td(kUri)}, {"range", (*d)["range"]}, {"context", {{"diagnostics", json::array({*d})}}}});
    REQUIRE(actions.size() == 2);
    CHECK(actions[0]["title"] == "Replace M52 by PM=52");
    CHECK(actions[0]["kind"] == "quickfix");
    CHECK(actions[0]["isPreferred"] == true);
    json edit = actions[0]["edit"]["changes"][kUri][0];
    CHECK(edit["newText"] == "PM=52");
    CHECK(edit["range"] == (*d)["range"]);
    CHECK(actions[1]["title"] == "Suppress OSP104 on this block");
    const std::string line9 = "CALL OZAGR PX=-70. PY=0 PR=5. PZ=-29. PI=6. PF=50 PS=600 M52";
    json sup = actions[1]["edit"]["changes"][kUri][0];
    CHECK(sup["range"] == range(9, line9.size(), 9, line9.size()));
    CHECK(sup["newText"] == " (osplint: disable=OSP104 -- reason)");

    // Applying the suppression silences the finding.
    s.change(kUri, 8, json::array({{{"range", sup["range"]}, {"text", sup["newText"]}}}));
    CHECK_FALSE(find_code(s.diagnostics(kUri, 8)["diagnostics"], "OSP104"));
    // Data from an older version offers no fix (the text moved on), only the suppression.
    json stale = s.result(
        "textDocument/codeAction",
        {{"textDocument", td(kUri)}, {"range", (*d)["range"]}, {"context", {{"diagnostics", json::array({*d})}}}});
    REQUIRE(stale.size() == 1);
    CHECK(stale[0]["title"] == "Suppress OSP104 on this block");
    // What the client sends is never echoed back beyond the numbers and strings used.
    json odd = *d;
    odd["data"]["version"] = 8;
    odd["data"]["fixes"][0]["edits"][0]["range"]["start"]["line"] = "nine";
    odd["code"] = "OSP104) (x";
    odd["relatedInformation"] = json::array({json::object({{"deep", json::array({json::array()})}})});
    json sanitized = s.result("textDocument/codeAction", {{"textDocument", td(kUri)},
                                                          {"range", (*d)["range"]},
                                                          {"context", {{"diagnostics", json::array({odd})}}}});
    CHECK(sanitized.empty());
    json only = s.result("textDocument/codeAction",
                         {{"textDocument", td(kUri)},
                          {"range", (*d)["range"]},
                          {"context", {{"diagnostics", json::array({*d})}, {"only", {"refactor"}}}}});
    CHECK(only.empty());
}

TEST_CASE("lsp: document symbols: programs and their sequence names") {
    Session s;
    s.initialize();
    s.open(kUri, "(HEADER)\nOMAIN\nN1 G0 X0\nNEND M30\nOSUB1\nNA1 G1 X1\nRTS\n");
    json sym = s.result("textDocument/documentSymbol", {{"textDocument", td(kUri)}});
    REQUIRE(sym.size() == 2);
    CHECK(sym[0]["name"] == "OMAIN");
    CHECK(sym[0]["kind"] == 12);
    REQUIRE(sym[0]["children"].size() == 2);
    CHECK(sym[0]["children"][0]["name"] == "N1");
    CHECK(sym[0]["children"][1]["name"] == "NEND");
    CHECK(sym[0]["children"][1]["selectionRange"] == range(3, 0, 3, 4));
    CHECK(sym[1]["name"] == "OSUB1");
    CHECK(sym[1]["children"][0]["name"] == "NA1");
    CHECK(sym[1]["selectionRange"] == range(4, 0, 4, 5));
}

TEST_CASE("lsp: configuration: nearest osplint.toml, reloaded when it changes, broken file shown") {
    const fs::path dir = fs::temp_directory_path() / ("osplint-lsp-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "sub");
    auto write = [&](const std::string& content) {
        std::ofstream(dir / "osplint.toml", std::ios::binary | std::ios::trunc) << content;
    };
    write("[rules]\nOSP104 = \"warning\"\n");
    const std::string uri = path_to_uri((dir / "sub" / "PART.MIN").string());
    {
        Session s;
        s.initialize();
        s.open(uri, kProgram, 1);
        CHECK(osp104_severity(s, uri, 1) == 2);

        // Changed on disk (size and contents): picked up before the next analysis.
        write("[rules]\nOSP104 = \"info\"   # changed\n");
        s.notify("workspace/didChangeWatchedFiles",
                 {{"changes", json::array({{{"uri", path_to_uri((dir / "osplint.toml").string())}, {"type", 2}}})}});
        CHECK(osp104_severity(s, uri, 1) == 3);

        // Broken: an error message, and the defaults.
        write("[rules\nOSP104 = \n");
        s.notify("textDocument/didSave", {{"textDocument", td(uri)}});
        json msg = s.notification("window/showMessage");
        CHECK(msg["params"]["type"] == 1);
        CHECK(msg["params"]["message"].get<std::string>().find("osplint.toml") != std::string::npos);
        CHECK(osp104_severity(s, uri, 1) == 1);

        // Fixed again: an edit is enough (the modification time is checked).
        write("[rules]\nOSP104 = \"off\"\n");
        s.change(uri, 2, json::array({{{"range", range(13, 3, 13, 3)}, {"text", " "}}}));
        CHECK_FALSE(find_code(s.diagnostics(uri, 2)["diagnostics"], "OSP104"));
    }
    fs::remove_all(dir);
}

TEST_CASE("lsp: configuration: [[per-path]] tables apply to the documents they match") {
    const fs::path dir = fs::temp_directory_path() / ("osplint-lsp-pp-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "probe");
    std::ofstream(dir / "osplint.toml", std::ios::binary)
        << "[rules]\nOSP104 = \"warning\"\n[[per-path]]\npaths = [\"probe/**\"]\nrules = { m52-on-call-line = \"info\" }\n";
    const std::string probe = path_to_uri((dir / "probe" / "PART.MIN").string());
    const std::string other = path_to_uri((dir / "PART.MIN").string());
    {
        Session s;
        s.initialize();
        s.open(probe, kProgram, 1);
        CHECK(osp104_severity(s, probe, 1) == 3);
        s.open(other, kProgram, 1);
        CHECK(osp104_severity(s, other, 1) == 2);
    }
    fs::remove_all(dir);
}

TEST_CASE("lsp: configuration: a change of the file it extends is picked up") {
    const fs::path dir = fs::temp_directory_path() / ("osplint-lsp-ext-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "shop");
    fs::create_directories(dir / "cell");
    auto shop = [&](const std::string& content) {
        std::ofstream(dir / "shop" / "osplint.toml", std::ios::binary | std::ios::trunc) << content;
    };
    shop("[rules]\nOSP104 = \"warning\"\n");
    std::ofstream(dir / "cell" / "osplint.toml", std::ios::binary) << "extend = \"../shop/osplint.toml\"\n";
    const std::string uri = path_to_uri((dir / "cell" / "PART.MIN").string());
    {
        Session s;
        s.initialize();
        s.open(uri, kProgram, 1);
        CHECK(osp104_severity(s, uri, 1) == 2);
        shop("[rules]\nOSP104 = \"info\"   # the shop changed it\n");
        s.change(uri, 2, json::array({{{"range", range(13, 3, 13, 3)}, {"text", " "}}}));
        CHECK(osp104_severity(s, uri, 2) == 3);
    }
    fs::remove_all(dir);
}

TEST_CASE("lsp: subprograms beside the document are known (no OSP005 for them)") {
    const fs::path dir = fs::temp_directory_path() / ("osplint-lsp-sub-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "SHOP.SSB") << "OSUBA\nG0 X0\nRTS\n";
    const std::string uri = path_to_uri((dir / "MAIN.MIN").string());
    Session s;
    s.initialize();
    s.open(uri, "O1\nCALL OSUBA\nCALL OSUBB\nM30\n");
    json diags = s.diagnostics(uri, 1)["diagnostics"];
    int unknown = 0;
    for (const auto& d : diags)
        if (d["code"] == "OSP005") {
            ++unknown;
            CHECK(d["message"].get<std::string>().find("OSUBB") != std::string::npos);
        }
    CHECK(unknown == 1);
    fs::remove_all(dir);
}

TEST_CASE("lsp: what a subprogram beside the document leaves behind applies at its CALL, as in `check`") {
    const fs::path dir = fs::temp_directory_path() / ("osplint-lsp-summary-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "SHOP.SSB") << "O100\nG91 G0 X10.\nRTS\n";
    const std::string uri = path_to_uri((dir / "MAIN.MIN").string());
    Session s;
    s.initialize();
    s.open(uri, "O1\nG90 G17 G21\nCALL O100\nCALL OKYLX PX=10 PY=0 PR=3 PZ=-5 PI=60 PD=21 PFA=100\nM30\n");
    json diags = s.diagnostics(uri, 1)["diagnostics"];
    int g91 = 0;
    for (const auto& d : diags)
        if (d["code"] == "OSP109") {
            ++g91;
            CHECK(d["range"]["start"]["line"] == 3);
            // A note with no place in this document is part of the message.
            CHECK(d["message"].get<std::string>().find("note: G91 comes from the subprogram O100 (SHOP.SSB, line 1)") !=
                  std::string::npos);
        }
    CHECK(g91 == 1);
    fs::remove_all(dir);
}

TEST_CASE("lsp: $/cancelRequest: a waiting request is answered or cancelled, never both, never lost") {
    Session s;
    s.initialize();
    s.open(kUri, kProgram);
    // Both frames in one write: the request may still be waiting when the cancel arrives.
    const json hover = make_request(500, "textDocument/hover", {{"textDocument", td(kUri)}, {"position", pos(8, 7)}});
    const json cancel = make_notification("$/cancelRequest", {{"id", 500}});
    s.raw(frame(hover.dump()) + frame(cancel.dump()));
    json r = s.response(500);
    if (r.contains("error"))
        CHECK(r["error"]["code"] == error::kRequestCancelled);
    else
        CHECK(r["result"]["contents"]["value"].get<std::string>().find("OZAGR") != std::string::npos);
    s.notify("$/cancelRequest", {{"id", 12345}});  // unknown: ignored
    CHECK(s.result("shutdown", nullptr).is_null());
    for (const auto& m : s.seen()) CHECK_FALSE((m.contains("id") && m["id"] == 12345));
}

TEST_CASE("lsp: an edit during a long analysis stops it; requests that waited are answered for the new text") {
    ServerOptions options = Session::quiet();
    std::atomic<int> cancelled{0};
    options.log_timing = true;
    options.log = [&](const std::string& m) {
        if (m.find("outdated") != std::string::npos) ++cancelled;
    };
    Session s(options);
    s.initialize();
    // A few megabytes: the walk takes long enough for the edit to arrive during it.
    std::string text = "O1\n";
    while (text.size() < (8u << 20)) text += "G1 X10. Y20. Z-1. F300\nX11. Y21.\n";
    text += "M30\n";
    s.open(kUri, text);
    const int hover = s.request_async("textDocument/hover", {{"textDocument", td(kUri)}, {"position", pos(0, 0)}});
    s.change(kUri, 2, json::array({{{"text", "O1\nCALL OZAGR PR=5 PZ=-20 PI=12 M52\nM30\n"}}}));
    const json diags = s.diagnostics(kUri, 2);
    CHECK(find_code(diags["diagnostics"], "OSP104"));
    const json h = s.response(hover);
    CHECK(h.contains("result"));
    // Version 1 was never published: its analysis was stopped or its result dropped.
    for (const auto& m : s.seen())
        if (m.value("method", "") == "textDocument/publishDiagnostics") CHECK(m["params"]["version"] == 2);
    MESSAGE("analyses stopped: " << cancelled.load());
}

TEST_CASE("lsp: one-character edits of a large document end early and publish what a fresh analysis does") {
    // About 400 KB: the checkpoints are 64 KiB apart, the edits are far
    // before the last ones; a finding on every 50th line (OZAGR without PI).
    std::string text = "O1\nG90 G17\nG0 X0 Y0 Z50.\n";
    for (int i = 0; i < 16000; ++i) {
        if (i % 50 == 7) text += "CALL OZAGR PX=" + std::to_string(i % 90) + ". PY=-20. PR=5. PZ=-29. PF=50 PS=600\n";
        else text += "G1 X" + std::to_string(i % 97) + ". Y" + std::to_string(i % 13) + ". F300\n";
    }
    text += "M30\n";
    std::vector<std::string> logs;
    std::mutex logs_m;
    ServerOptions options = Session::quiet();
    options.log_timing = true;
    options.log = [&](const std::string& m) {
        std::lock_guard lock(logs_m);
        logs.push_back(m);
    };
    Session s(options);
    s.initialize(true);
    s.open(kUri, text, 1);
    CHECK(s.diagnostics(kUri, 1)["diagnostics"].size() == 16000 / 50);
    std::mt19937 rng(77);
    for (int v = 2; v < 12; ++v) {
        // A digit typed, or one deleted, on a line in the first half; every
        // third edit breaks a call (PI given: its finding goes) or mends it.
        const uint32_t line = 3 + static_cast<uint32_t>(rng() % 8000);
        size_t start = 0;
        for (uint32_t l = 0; l < line; ++l) start = text.find('\n', start) + 1;
        const size_t end = text.find('\n', start);
        const std::string old_line = text.substr(start, end - start);
        std::string new_line = old_line;
        if (old_line.rfind("CALL", 0) == 0) new_line += " PI=6.";
        else if (v % 2) new_line.insert(new_line.find('X') + 1, "1");
        else new_line.erase(new_line.find('X') + 1, 1);
        text.replace(start, end - start, new_line);
        s.change(kUri, v, json::array({{{"range", range(line, 0, line, static_cast<uint32_t>(old_line.size()))},
                                        {"text", new_line}}}));
        // The document version the fixes are for aside.
        auto unversioned = [](json d) {
            for (auto& x : d)
                if (x.contains("data")) x["data"].erase("version");
            return d;
        };
        const json got = unversioned(s.diagnostics(kUri, v)["diagnostics"]);
        const std::string fresh_uri = "untitled:FRESH" + std::to_string(v) + ".MIN";
        s.open(fresh_uri, text, 1);
        const json expected = unversioned(s.diagnostics(fresh_uri, 1)["diagnostics"]);
        CHECK(got.size() == expected.size());
        CHECK(got == expected);
        s.notify("textDocument/didClose", {{"textDocument", {{"uri", fresh_uri}}}});
    }
    std::lock_guard lock(logs_m);
    const auto early = std::count_if(logs.begin(), logs.end(), [](const std::string& m) {
        return m.find(kUri) == 0 && m.find(" to line ") != std::string::npos;
    });
    CHECK(early >= 5);
}
