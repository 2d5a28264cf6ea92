// Benchmark: time from a one-character edit in a 1 MB part program to the
// republished diagnostics, through the whole language server (framing,
// JSON-RPC, incremental re-parse, rules, publishDiagnostics), over an
// in-memory transport.
//
//     lsp_edit [--size BYTES] [--edits N] [--file PATH]
//
// Prints one line per measurement set and the figure:
//     lsp_edit: 1000028-byte program, 30 edits: median 41.2 ms, p90 47.0 ms, max 52.3 ms (target < 100 ms)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "lsp/server.h"

using namespace osplint::lsp;
using Clock = std::chrono::steady_clock;

namespace {

// A CAM-like program: positioning, drilling with cycles, contour moves, comments.
std::string make_program(std::size_t size) {
    std::mt19937 rng(42);
    auto coord = [&](int lo, int hi) {
        std::uniform_real_distribution<double> d(lo, hi);
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.3f", d(rng));
        return std::string(buf);
    };
    std::string s =
        "(BENCHMARK PROGRAM - SURFACE AND HOLES)\nO1000\nG15 H1\nT2 M6\nG0 G90 X0 Y0\nG56 Z50. H2\nS1500 M3\nM8\n";
    int n = 0;
    while (s.size() < size) {
        if (n % 500 == 0) s += "N" + std::to_string(n / 500 + 1) + " (SECTION " + std::to_string(n) + ")\n";
        if (n % 97 == 0) {
            s += "G0 Z10.\nG81 X" + coord(-100, 100) + " Y" + coord(-100, 100) + " Z-5. R3. F150\n";
            s += "X" + coord(-100, 100) + " Y" + coord(-100, 100) + "\nG80\n";
        } else {
            s += "G1 X" + coord(-100, 100) + " Y" + coord(-100, 100) + " Z" + coord(-10, 0) + " F" +
                 std::to_string(100 + rng() % 800) + "\n";
        }
        ++n;
    }
    s += "G0 Z100. M9\nM5\nG30 P1\nM30\n";
    return s;
}

json wait_for(MemoryOutput& out, int64_t version) {
    for (;;) {
        std::string body = out.next(60000);
        if (body.empty()) {
            std::fprintf(stderr, "lsp_edit: timed out waiting for version %lld\n", static_cast<long long>(version));
            std::exit(1);
        }
        json m = json::parse(body);
        if (m.value("method", "") == "textDocument/publishDiagnostics" &&
            m["params"].value("version", int64_t(-1)) == version)
            return m;
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t size = 1'000'000;
    int edits = 30;
    std::string file;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--size") && i + 1 < argc)
            size = std::stoul(argv[++i]);
        else if (!std::strcmp(argv[i], "--edits") && i + 1 < argc)
            edits = std::stoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--file") && i + 1 < argc)
            file = argv[++i];
        else {
            std::fprintf(stderr, "usage: lsp_edit [--size BYTES] [--edits N] [--file PATH]\n");
            return 2;
        }
    }
    std::string text;
    if (!file.empty()) {
        std::ifstream in(file, std::ios::binary);
        std::stringstream ss;
        ss << in.rdbuf();
        text = ss.str();
    } else {
        text = make_program(size);
    }

    PipeInput in;
    MemoryOutput out;
    ServerOptions options;  // the defaults `osplint lsp` uses (debounce included)
    if (std::getenv("OSPLINT_LSP_TIMING")) {
        options.log_timing = true;
        options.log = [](const std::string& m) { std::fprintf(stderr, "%s\n", m.c_str()); };
    }
    Server server(in, out, options);
    std::thread loop([&] { server.run(); });
    auto send = [&](const json& m) { in.push(frame(m.dump())); };

    send(
        make_request(1, "initialize", {{"capabilities", {{"general", {{"positionEncodings", {"utf-8", "utf-16"}}}}}}}));
    send(make_notification("initialized", json::object()));
    const std::string uri = "untitled:BENCH.MIN";
    const auto t_open = Clock::now();
    send(make_notification("textDocument/didOpen",
                           {{"textDocument", {{"uri", uri}, {"languageId", "osp"}, {"version", 1}, {"text", text}}}}));
    wait_for(out, 1);
    const double open_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_open).count();

    // Edits in the middle of the file: one more digit in a feed rate (F150 -> F1150).
    std::vector<double> ms;
    std::mt19937 rng(1);
    const osplint::SourceText src(text);
    for (int k = 0; k < edits; ++k) {
        const uint32_t line = 20 + rng() % (src.line_count() - 40);
        const std::string_view lt = src.line_text(line + 1);
        const std::size_t x = lt.find('F');
        if (x == std::string_view::npos || x + 1 >= lt.size()) {
            --k;
            continue;
        }
        const uint32_t c = static_cast<uint32_t>(x + 1);
        json change = {
            {"range", {{"start", {{"line", line}, {"character", c}}}, {"end", {{"line", line}, {"character", c}}}}},
            {"text", "1"}};
        const auto t0 = Clock::now();
        send(make_notification("textDocument/didChange", {{"textDocument", {{"uri", uri}, {"version", k + 2}}},
                                                          {"contentChanges", json::array({change})}}));
        wait_for(out, k + 2);
        ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    send(make_request(2, "shutdown", nullptr));
    send(make_notification("exit", nullptr));
    loop.join();

    std::sort(ms.begin(), ms.end());
    const double median = ms[ms.size() / 2];
    const double p90 = ms[std::min(ms.size() - 1, ms.size() * 9 / 10)];
    std::printf("lsp_edit: open (full parse + analysis) %.1f ms\n", open_ms);
    std::printf(
        "lsp_edit: %zu-byte program, %d one-character edits: median %.1f ms, p90 %.1f ms, max %.1f ms "
        "(target < 100 ms)\n",
        text.size(), edits, median, p90, ms.back());
    return 0;
}
