// Language server responsiveness, through a scripted client: a huge document
// under analysis holds back neither `shutdown` nor the other documents, and
// its analysis stops when a newer edit arrives. The bounds are generous (the
// sanitizer build is several times slower); what is checked is the order of
// events: the answer comes while the long analysis is still running.
#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <string>

#include "lsp_session.h"

using namespace osplint;
using namespace osplint::lsp;
using namespace osplint::lsp::testing;

namespace {

using Clock = std::chrono::steady_clock;

const std::string kHuge = "untitled:HUGE.MIN";
const std::string kSmall = "untitled:SMALL.MIN";

// About 16 MB of macro calls: its analysis takes seconds (far longer than a
// round trip), its transfer well under one.
std::string huge_text() {
    std::string text = "O1\nVC1=0\nG0 G90 X0 Y0\n";
    const std::string lines = "CALL OZAGR PX=VC1 PY=0 PR=5. PZ=-20. PI=12. (PASS)\nVC1=VC1+1\n";
    text.reserve((16u << 20) + lines.size());
    while (text.size() < (16u << 20)) text += lines;
    return text + "M30\n";
}

// Counts what the server logs about the analyses of the huge document.
struct Events {
    std::atomic<int> started{0}, finished{0}, stopped{0};
    ServerOptions options() {
        ServerOptions o = Session::quiet();
        o.log_timing = true;
        o.log = [this](const std::string& m) {
            if (m.rfind(kHuge, 0) != 0) return;
            if (m.find("analysis started") != std::string::npos) ++started;
            if (m.find("analysed in") != std::string::npos) ++finished;
            if (m.find("analysis stopped") != std::string::npos) ++stopped;
        };
        return o;
    }
    bool wait_started() {
        const auto deadline = Clock::now() + std::chrono::milliseconds(kTimeoutMs);
        while (started == 0 && Clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        return started > 0;
    }
};

}  // namespace

TEST_CASE("lsp: shutdown is answered at once while a huge document is analysed") {
    Events ev;
    Session s(ev.options());
    s.initialize();
    s.open(kHuge, huge_text());
    REQUIRE(ev.wait_started());
    const auto t0 = Clock::now();
    json r = s.request("shutdown", nullptr);
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0).count();
    CHECK(r.contains("result"));
    CHECK(r["result"].is_null());
    CHECK(ev.finished == 0);  // answered before the analysis ended
    CHECK(ms < 5000);
    MESSAGE("shutdown answered in " << ms << " ms");
    s.notify("exit", nullptr);
    CHECK(s.finished_within(kTimeoutMs));
    CHECK(s.exit_code() == 0);
}

TEST_CASE("lsp: a document under a long analysis does not hold back another") {
    Events ev;
    Session s(ev.options());
    s.initialize();
    s.open(kHuge, huge_text());
    REQUIRE(ev.wait_started());
    s.open(kSmall, "O1\nCALL OZAGR PR=5 PZ=-20 PI=12 M52\nM30\n");
    json d = s.diagnostics(kSmall, 1);
    CHECK(find_code(d["diagnostics"], "OSP104"));
    json h = s.result("textDocument/hover", {{"textDocument", td(kSmall)}, {"position", pos(1, 7)}});
    REQUIRE(h.is_object());
    CHECK(h["contents"]["value"].get<std::string>().find("OZAGR") != std::string::npos);
    CHECK(ev.finished == 0);  // the other document was served during the long analysis
    CHECK(s.result("shutdown", nullptr).is_null());
}

TEST_CASE("lsp: an analysis of an outdated text stops when the newer edit arrives") {
    Events ev;
    Session s(ev.options());
    s.initialize();
    s.open(kHuge, huge_text());
    REQUIRE(ev.wait_started());
    s.change(kHuge, 2, json::array({{{"text", "O1\nCALL OZAGR PR=5 PZ=-20 PI=12 M52\nM30\n"}}}));
    json d = s.diagnostics(kHuge, 2);
    CHECK(find_code(d["diagnostics"], "OSP104"));
    CHECK(ev.stopped >= 1);
    for (const auto& m : s.seen())
        if (m.value("method", "") == "textDocument/publishDiagnostics") CHECK(m["params"]["version"] == 2);
    CHECK(s.result("shutdown", nullptr).is_null());
}
