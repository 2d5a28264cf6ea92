// Benchmark: the language server on large part programs, through the whole
// server (framing, JSON-RPC, the document model, the engine,
// publishDiagnostics) over an in-memory transport.
//
//   * open: time from a didOpen of a large document (50 MB by default) to its
//     first diagnostics, and the process's peak RSS after it (VmHWM) with its
//     growth per document byte;
//   * edits: one-character edits (didChange with an incremental range) on
//     1 MB and 10 MB documents, each timed to the publishDiagnostics of its
//     version: median, p90 and max.
//
// A time ends when the publishDiagnostics message has arrived whole; the
// client's own parse of it (nlohmann::json here, a few milliseconds for a
// hundred findings) is not the server's latency and is not counted.
//
//     lsp_edit [--shapes "plain loops"] [--edit-shapes "plain ... macros"] [--open-mb 50]
//              [--edit-mb "1 10"] [--edits 20] [--dir DIR] [--gen PATH] [--file PATH]
//
// The opens take `--shapes`; the edits take every shape of bench/gen_cam.py
// unless `--edit-shapes` (or `--shapes`) names others: the aim holds for
// every program a machinist edits, the slowest shape (`macros`, a macro call
// on every block) included.
//
// The documents are bench/gen_cam.py's programs of each shape, generated into
// DIR (named as bench/run.sh names them, so both share them; regenerated
// when gen_cam.py is newer), or the one --file. Each measurement runs in a
// process of its own (fork), so that a peak RSS is not an earlier test's.
// The client side keeps no copy of an opened document: didOpen is streamed
// from the file in chunks, so the peak RSS is the server's (and the
// in-memory transport's) own. The server takes messages of up to 64 MiB:
// a document of about 60 MB at most. Prints one line per figure, then the
// targets (50 MB document: first diagnostics within 5 s, at most 20 bytes of
// RSS per document byte; 1 MB document: median edit-to-diagnostics at most
// 30 ms); the exit status is 1 when one is missed:
//     lsp_edit: open plain 50 MB (50000096 bytes): first diagnostics in 3002.5 ms, 0 diagnostics; peak RSS ...
//     lsp_edit: edits plain 1 MB (1004208 bytes), 20 one-character edits: median 17.3 ms, p90 23.8 ms, max 26.7 ms
//     target met:    lsp: plain 1 MB document: median edit-to-diagnostics at most 30 ms (17.3 ms)
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "lsp/server.h"

using namespace osplint::lsp;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Targets (see bench/run.sh).
constexpr double kOpenTargetMs = 5000;
constexpr double kBytesPerByteTarget = 20;
constexpr double kEditMedianTargetMs = 30;
// The open targets are for a large document (the server's own start-up
// weighs on the bytes per byte of a small one), the edit target for 1 MB.
constexpr uint64_t kOpenTargetMinBytes = 40'000'000;
constexpr uint64_t kEditTargetMaxBytes = 1'100'000;

const std::string kUri = "untitled:BENCH.MIN";


// A field of /proc/self/status in kB (VmRSS, VmHWM), -1 when unreadable.
long status_kb(const char* field) {
    std::ifstream in("/proc/self/status");
    std::string line;
    const std::size_t n = std::strlen(field);
    while (std::getline(in, line))
        if (line.compare(0, n, field) == 0 && line.size() > n && line[n] == ':') return std::atol(line.c_str() + n + 1);
    return -1;
}

// Where a target line goes: the parent collects them and prints them last.
int g_targets_fd = -1;
bool g_missed = false;

void target(bool met, const std::string& what) {
    if (!met) g_missed = true;
    const std::string line = std::string(met ? "target met:    " : "target missed: ") + "lsp: " + what + "\n";
    if (g_targets_fd >= 0) {
        if (::write(g_targets_fd, line.data(), line.size()) < 0) std::fputs(line.c_str(), stdout);
    } else {
        std::fputs(line.c_str(), stdout);
    }
}

// One server over an in-memory transport, initialized; shut down cleanly
// when it goes.
class Session {
public:
    Session() : server_(in_, out_, options()) {
        loop_ = std::thread([this] { server_.run(); });
        send(make_request(
            1, "initialize", {{"capabilities", {{"general", {{"positionEncodings", {"utf-8", "utf-16"}}}}}}}));
        for (;;) {
            json m = next(60000, "the initialize response");
            if (m.contains("id") && m["id"] == 1 && !m.contains("method")) break;
        }
        send(make_notification("initialized", json::object()));
    }
    ~Session() {
        send(make_request(2, "shutdown", nullptr));
        send(make_notification("exit", nullptr));
        in_.close();
        loop_.join();
    }
    void send(const json& m) { in_.push(frame(m.dump())); }
    void push(std::string_view bytes) { in_.push(bytes); }

    json next(int timeout_ms, const char* what, Clock::time_point* arrived = nullptr) {
        std::string body = out_.next(timeout_ms);
        if (arrived) *arrived = Clock::now();
        if (body.empty()) {
            std::fprintf(stderr, "lsp_edit: timed out (%d ms) waiting for %s\n", timeout_ms, what);
            std::fflush(stderr);
            std::_Exit(3);
        }
        return json::parse(body);
    }
    // The publishDiagnostics of `version`: the number of diagnostics in it,
    // and when its message arrived, whole (`arrived`): the client's parse of
    // it is the client's work, not the server's.
    std::size_t wait_for(int64_t version, int timeout_ms, Clock::time_point* arrived = nullptr) {
        for (;;) {
            Clock::time_point t;
            json m = next(timeout_ms, "publishDiagnostics", &t);
            if (m.value("method", "") == "textDocument/publishDiagnostics" &&
                m["params"].value("version", int64_t(-1)) == version) {
                if (arrived) *arrived = t;
                return m["params"]["diagnostics"].size();
            }
        }
    }

private:
    static ServerOptions options() {
        ServerOptions o;  // the defaults `osplint lsp` uses (debounce included)
        if (std::getenv("OSPLINT_LSP_TIMING")) {
            o.log_timing = true;
            o.log = [](const std::string& m) { std::fprintf(stderr, "%s\n", m.c_str()); };
        }
        return o;
    }
    PipeInput in_;
    MemoryOutput out_;
    Server server_;
    std::thread loop_;
};

// JSON string escaping of one chunk of program text (ASCII, or UTF-8 in comments).
void escape(std::string_view s, std::string& out) {
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\r': out += "\\r"; break;
            case '\t': out += "\\t"; break;
            default:
                if (c < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", c);
                    out += buf;
                } else {
                    out += ch;
                }
        }
    }
}

// Sends didOpen (version 1) of the file at `path` without holding its text:
// one pass for the length of the body, one to send it in 1 MiB pieces.
uint64_t stream_open(Session& s, const std::string& path) {
    const std::string head = R"({"jsonrpc":"2.0","method":"textDocument/didOpen","params":{"textDocument":{"uri":")" +
                             kUri + R"(","languageId":"osp","version":1,"text":")";
    const std::string tail = R"("}}})";
    std::vector<char> buf(std::size_t(1) << 20);
    std::string piece;
    auto each_piece = [&](auto&& f) {
        std::ifstream in(path, std::ios::binary);
        if (!in) {
            std::fprintf(stderr, "lsp_edit: cannot read %s\n", path.c_str());
            std::_Exit(3);
        }
        uint64_t bytes = 0;
        while (in.read(buf.data(), static_cast<std::streamsize>(buf.size())) || in.gcount() > 0) {
            piece.clear();
            escape(std::string_view(buf.data(), static_cast<std::size_t>(in.gcount())), piece);
            bytes += static_cast<uint64_t>(in.gcount());
            f(piece);
        }
        return bytes;
    };
    uint64_t length = head.size() + tail.size();
    each_piece([&](const std::string& p) { length += p.size(); });
    s.push("Content-Length: " + std::to_string(length) + "\r\n\r\n" + head);
    const uint64_t bytes = each_piece([&](const std::string& p) { s.push(p); });
    s.push(tail);
    return bytes;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Child: didOpen of a large document, the first diagnostics, the peak RSS.
void test_open(const std::string& label, const std::string& path) {
    Session s;
    {  // the peak from here on (a fresh process has only the server's start behind it)
        std::ofstream clear("/proc/self/clear_refs");
        clear << "5";
    }
    const long before_kb = status_kb("VmRSS");
    const auto t0 = Clock::now();
    const uint64_t bytes = stream_open(s, path);
    Clock::time_point arrived;
    const std::size_t n = s.wait_for(1, 600000, &arrived);
    const double ms = std::chrono::duration<double, std::milli>(arrived - t0).count();
    const long hwm_kb = status_kb("VmHWM");
    const double per_byte = bytes ? (hwm_kb - before_kb) * 1024.0 / static_cast<double>(bytes) : 0;
    std::printf(
        "lsp_edit: open %s (%llu bytes): first diagnostics in %.1f ms, %zu diagnostics; peak RSS %.1f MB "
        "(%.1f MB before the document): %.1f bytes per document byte\n",
        label.c_str(), static_cast<unsigned long long>(bytes), ms, n, hwm_kb / 1024.0, before_kb / 1024.0,
        per_byte);
    std::fflush(stdout);
    if (bytes < kOpenTargetMinBytes) return;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s document: first diagnostics within %.0f s (%.2f s)", label.c_str(),
                  kOpenTargetMs / 1000, ms / 1000);
    target(ms <= kOpenTargetMs, buf);
    std::snprintf(buf, sizeof buf, "%s document: at most %.0f bytes of RSS per document byte (%.1f)", label.c_str(),
                  kBytesPerByteTarget, per_byte);
    target(per_byte <= kBytesPerByteTarget, buf);
}

// Child: `edits` one-character edits, each timed to its diagnostics.
void test_edits(const std::string& label, const std::string& path, int edits) {
    const osplint::SourceText src(read_file(path));
    Session s;
    stream_open(s, path);
    s.wait_for(1, 600000);

    // A digit appended to a plain move (X.. Y.. Z..) in the middle of the
    // file: the commonest edit, and one that gives no new finding.
    std::vector<double> ms;
    std::mt19937 rng(1);
    std::map<uint32_t, uint32_t> appended;  // line (0-based) -> digits added to it
    const uint32_t lines = src.line_count();
    if (lines < 100) {
        std::fprintf(stderr, "lsp_edit: %s is too short for the edit test\n", path.c_str());
        std::_Exit(3);
    }
    // A plain move, perhaps after a sequence number ("N930 X-41.1 Y-40. Z-3.481").
    const auto is_move = [&](uint32_t l) {
        std::string_view t = src.line_text(l + 1);
        if (!t.empty() && t[0] == 'N') {
            const std::size_t blank = t.find(' ');
            if (blank == std::string_view::npos) return false;
            t.remove_prefix(blank + 1);
        }
        return !t.empty() && t[0] == 'X';
    };
    int misses = 0;
    for (int k = 0; k < edits; ++k) {
        uint32_t line = 20 + rng() % (lines - 40);
        while (line + 20 < lines && !is_move(line)) ++line;
        const std::string_view lt = src.line_text(line + 1);
        if (!is_move(line)) {
            if (++misses > 1000) {
                std::fprintf(stderr, "lsp_edit: %s has no plain move (X.. Y.. Z..) to edit\n", path.c_str());
                std::_Exit(3);
            }
            --k;
            continue;
        }
        const uint32_t c = static_cast<uint32_t>(lt.size()) + appended[line]++;
        json change = {
            {"range", {{"start", {{"line", line}, {"character", c}}}, {"end", {{"line", line}, {"character", c}}}}},
            {"text", "1"}};
        const auto t0 = Clock::now();
        s.send(make_notification("textDocument/didChange", {{"textDocument", {{"uri", kUri}, {"version", k + 2}}},
                                                            {"contentChanges", json::array({change})}}));
        Clock::time_point arrived;
        s.wait_for(k + 2, 120000, &arrived);
        ms.push_back(std::chrono::duration<double, std::milli>(arrived - t0).count());
        std::this_thread::sleep_for(std::chrono::milliseconds(20));  // past the debounce: one analysis per edit
    }
    std::sort(ms.begin(), ms.end());
    const double median = ms[ms.size() / 2];
    const double p90 = ms[std::min(ms.size() - 1, ms.size() * 9 / 10)];
    std::printf("lsp_edit: edits %s (%u bytes), %d one-character edits: median %.1f ms, p90 %.1f ms, max %.1f ms\n",
                label.c_str(), src.size(), edits, median, p90, ms.back());
    std::fflush(stdout);
    if (src.size() <= kEditTargetMaxBytes) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s document: median edit-to-diagnostics at most %.0f ms (%.1f ms)",
                      label.c_str(), kEditMedianTargetMs, median);
        target(median <= kEditMedianTargetMs, buf);
    }
}

// Runs `f` in a child process; its target lines are added to `targets`.
// Returns false when the child failed.
template <class F>
bool in_child(const std::string& what, std::string& targets, F f) {
    int fds[2];
    if (::pipe(fds) != 0) {
        std::perror("pipe");
        return false;
    }
    std::fflush(stdout);
    std::fflush(stderr);
    const pid_t pid = ::fork();
    if (pid < 0) {
        std::perror("fork");
        return false;
    }
    if (pid == 0) {
        ::close(fds[0]);
        g_targets_fd = fds[1];
        f();
        std::fflush(stdout);
        std::_Exit(g_missed ? 1 : 0);
    }
    ::close(fds[1]);
    char buf[4096];
    ssize_t n;
    while ((n = ::read(fds[0], buf, sizeof buf)) > 0) targets.append(buf, static_cast<std::size_t>(n));
    ::close(fds[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (WIFSIGNALED(status)) {
        std::printf("lsp_edit: %s: the test process died of signal %d\n", what.c_str(), WTERMSIG(status));
        targets += "target missed: lsp: " + what + " (crashed)\n";
        return false;
    }
    if (WEXITSTATUS(status) > 1) {
        targets += "target missed: lsp: " + what + " (failed)\n";
        return false;
    }
    return true;
}

std::vector<std::string> words(const std::string& s) {
    std::vector<std::string> out;
    std::string w;
    for (const char c : s + " ") {
        if (c == ' ' || c == ',') {
            if (!w.empty() && w != "0") out.push_back(w);
            w.clear();
        } else {
            w += c;
        }
    }
    return out;
}

// The program of `shape` and `mb` MB, as bench/run.sh names it in `dir`
// (PLAIN50.MIN), generated unless it is newer than the generator.
std::string document(const std::string& dir, const std::string& gen, const std::string& shape, const std::string& mb) {
    std::string name;
    for (const char c : shape) name += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    const fs::path path = fs::path(dir) / (name + mb + ".MIN");
    std::error_code ec;
    if (fs::exists(path, ec) && fs::last_write_time(path, ec) > fs::last_write_time(gen, ec)) return path.string();
    fs::create_directories(dir, ec);
    const std::string tmp = path.string() + ".tmp";
    const std::string cmd = "python3 '" + gen + "' --size-mb " + mb + " --seed 1 --shape " + shape + " --output '" +
                            tmp + "' && mv '" + tmp + "' '" + path.string() + "'";
    if (std::system(cmd.c_str()) != 0) {
        std::fprintf(stderr, "lsp_edit: could not generate %s\n", path.c_str());
        std::exit(3);
    }
    return path.string();
}

}  // namespace

int main(int argc, char** argv) {
    std::string shapes = "plain loops", open_mb = "50", edit_mb = "1 10", file;
    std::string edit_shapes = "plain numbered loops travel bigloop macros";
    std::string dir = (fs::temp_directory_path() / "osplint-bench").string();
    std::string gen = (fs::path(__FILE__).parent_path() / "gen_cam.py").string();
    int edits = 20;
    for (int i = 1; i < argc; ++i) {
        auto arg = [&](const char* name) { return !std::strcmp(argv[i], name) && i + 1 < argc; };
        if (arg("--shapes")) shapes = edit_shapes = argv[++i];
        else if (arg("--edit-shapes")) edit_shapes = argv[++i];
        else if (arg("--open-mb")) open_mb = argv[++i];
        else if (arg("--edit-mb")) edit_mb = argv[++i];
        else if (arg("--edits")) edits = std::max(1, std::atoi(argv[++i]));
        else if (arg("--dir")) dir = argv[++i];
        else if (arg("--gen")) gen = argv[++i];
        else if (arg("--file")) file = argv[++i];
        else {
            std::fprintf(stderr,
                         "usage: lsp_edit [--shapes \"plain loops\"] [--edit-shapes \"plain ... macros\"] [--open-mb 50]\n"
                         "                [--edit-mb \"1 10\"] [--edits 20] [--dir DIR] [--gen PATH] [--file PATH]\n"
                         "  --open-mb 0 or --edit-mb \"\" skips a test; --file measures both on that file\n");
            return 2;
        }
    }

    std::string targets;
    bool ok = true;
    if (!file.empty()) {
        const std::string label = fs::path(file).filename().string();
        ok &= in_child("open " + label, targets, [&] { test_open(label, file); });
        ok &= in_child("edits " + label, targets, [&] { test_edits(label, file, edits); });
    } else {
        // The opens first, then the edits; a document is generated when it is first needed.
        for (const std::string& shape : words(shapes))
            for (const std::string& mb : words(open_mb)) {
                const std::string path = document(dir, gen, shape, mb), label = shape + " " + mb + " MB";
                ok &= in_child("open " + label, targets, [&] { test_open(label, path); });
            }
        for (const std::string& shape : words(edit_shapes))
            for (const std::string& mb : words(edit_mb)) {
                const std::string path = document(dir, gen, shape, mb), label = shape + " " + mb + " MB";
                ok &= in_child("edits " + label, targets, [&] { test_edits(label, path, edits); });
            }
    }
    std::fputs(targets.c_str(), stdout);
    if (!ok) return 1;
    return targets.find("target missed") != std::string::npos ? 1 : 0;
}
