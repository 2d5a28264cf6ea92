// A scripted language-server client for the tests: framed messages in,
// framed messages out, over an in-memory transport, with the server's message
// loop on its own thread.
#pragma once

#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <deque>
#include <string>
#include <thread>
#include <vector>

#include "lsp/server.h"
#include "support/text.h"

namespace osplint::lsp::testing {

inline constexpr int kTimeoutMs = 20000;

// A client: sends framed messages, collects what the server sends.
class Session {
public:
    explicit Session(ServerOptions options = quiet()) : server_(in_, out_, std::move(options)) {
        thread_ = std::thread([this] { exit_code_ = server_.run(); });
    }
    ~Session() {
        in_.close();
        if (thread_.joinable()) thread_.join();
    }
    static ServerOptions quiet() {
        ServerOptions o;
        o.debounce = std::chrono::milliseconds(5);
        return o;
    }

    void raw(std::string_view bytes) { in_.push(bytes); }
    void send(const json& msg) { raw(frame(msg.dump())); }
    void notify(const std::string& method, json params) { send(make_notification(method, std::move(params))); }
    int request_async(const std::string& method, json params) {
        const int id = next_id_++;
        send(make_request(id, method, std::move(params)));
        return id;
    }
    // The response to `id` (other messages are kept for later).
    json response(const json& id) {
        return wait([&](const json& m) { return m.contains("id") && m["id"] == id && !m.contains("method"); });
    }
    json request(const std::string& method, json params) { return response(request_async(method, std::move(params))); }
    json result(const std::string& method, json params) {
        json r = request(method, std::move(params));
        REQUIRE_MESSAGE(r.contains("result"), r.dump());
        return r["result"];
    }
    // The publishDiagnostics of `uri` for `version` (or any version when < 0).
    json diagnostics(const std::string& uri, int64_t version = -1) {
        return wait([&](const json& m) {
            return m.value("method", "") == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri &&
                   (version < 0 || m["params"].value("version", int64_t(-1)) == version);
        })["params"];
    }
    json notification(const std::string& method) {
        return wait([&](const json& m) { return m.value("method", "") == method; });
    }
    // Waits for the first message (received or backlogged) that matches.
    template <class P>
    json wait(P pred) {
        for (auto it = backlog_.begin(); it != backlog_.end(); ++it)
            if (pred(*it)) {
                json m = *it;
                backlog_.erase(it);
                return m;
            }
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(kTimeoutMs);
        while (std::chrono::steady_clock::now() < deadline) {
            std::string body = out_.next(100);
            if (body.empty()) continue;
            json m = json::parse(body);
            seen_.push_back(m);
            if (pred(m)) return m;
            backlog_.push_back(std::move(m));
        }
        FAIL("timed out waiting for a message");
        return nullptr;
    }
    std::size_t backlog_size() const { return backlog_.size(); }
    const std::vector<json>& seen() const { return seen_; }
    // Closes the input and returns the exit code of run().
    int finish() {
        in_.close();
        if (thread_.joinable()) thread_.join();
        return exit_code_;
    }
    bool finished_within(int ms) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
        while (exit_code_ < 0 && std::chrono::steady_clock::now() < deadline)
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        return exit_code_ >= 0;
    }
    int exit_code() const { return exit_code_; }

    json initialize(bool utf8 = true, json extra = json::object()) {
        json caps = {{"general", {{"positionEncodings", utf8 ? json{"utf-8", "utf-16"} : json{"utf-16"}}}}};
        json params = {{"processId", nullptr}, {"rootUri", nullptr}, {"capabilities", caps}};
        params.update(extra);
        json r = result("initialize", params);
        notify("initialized", json::object());
        return r;
    }
    void open(const std::string& uri, const std::string& text, int version = 1) {
        notify("textDocument/didOpen",
               {{"textDocument", {{"uri", uri}, {"languageId", "osp"}, {"version", version}, {"text", text}}}});
    }
    void change(const std::string& uri, int version, json changes) {
        notify("textDocument/didChange",
               {{"textDocument", {{"uri", uri}, {"version", version}}}, {"contentChanges", std::move(changes)}});
    }

private:
    PipeInput in_;
    MemoryOutput out_;
    Server server_;
    std::thread thread_;
    std::atomic<int> exit_code_{-1};
    int next_id_ = 1;
    std::deque<json> backlog_;
    std::vector<json> seen_;
};

inline json pos(uint32_t line, uint32_t character) { return {{"line", line}, {"character", character}}; }
inline json range(uint32_t l1, uint32_t c1, uint32_t l2, uint32_t c2) {
    return {{"start", pos(l1, c1)}, {"end", pos(l2, c2)}};
}
inline json td(const std::string& uri) { return {{"uri", uri}}; }

inline const json* find_code(const json& diags, std::string_view code) {
    for (const auto& d : diags)
        if (d.value("code", "") == code) return &d;
    return nullptr;
}

// Column of `needle` in `line`, in the units of the encoding.
inline uint32_t col(const std::string& line, const std::string& needle, bool utf8) {
    const std::size_t at = line.find(needle);
    REQUIRE(at != std::string::npos);
    if (utf8) return static_cast<uint32_t>(at);
    return count_columns(std::string_view(line).substr(0, at)).utf16;
}

}  // namespace osplint::lsp::testing
