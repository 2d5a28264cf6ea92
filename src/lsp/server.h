// Language server, layers 3-4: the LSP session and its analysis worker.
//
//   transport (lsp/transport.h) -> JSON-RPC (lsp/jsonrpc.h) -> this file:
//   lifecycle, documents, scheduling -> features (lsp/features.h) -> the
//   analysis engine (engine/engine.h, the same as `osplint check`).
//
// The message loop (run()) only reads, classifies and records: document text
// is kept here, every request about a document and every analysis is handed
// to one worker thread. The worker owns the model of each document (its text,
// line index and outline: lsp/document.h), runs the engine over the text,
// publishes the diagnostics unless the document changed meanwhile, and then
// answers the requests that waited for that version.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "engine/workspace.h"
#include "lsp/document.h"
#include "lsp/jsonrpc.h"
#include "lsp/navigation.h"
#include "lsp/text.h"
#include "semantics/config.h"

namespace osplint::lsp {

struct ServerOptions {
    // Quiet time after an edit before the analysis starts (an analysis of an
    // outdated text stops as soon as the next edit arrives, so it can be short).
    std::chrono::milliseconds debounce{2};
    // Diagnostics about the server itself (stderr for `osplint lsp`).
    std::function<void(const std::string&)> log;
    // Also log the time each analysis took (parse, rules, publish).
    bool log_timing = false;
};

// Configuration per directory: the nearest osplint.toml, reloaded when its
// modification time or size changes; a broken file gives the defaults and
// an error message to show once.
class ConfigCache {
public:
    struct Lookup {
        std::shared_ptr<const Config> config;
        std::string error;      // set when a file was (re)loaded and is broken
        bool reloaded = false;  // a file changed since it was last read
    };
    Lookup get(const std::optional<std::filesystem::path>& dir);
    void invalidate();

private:
    struct Entry {
        std::filesystem::file_time_type mtime{};
        std::uintmax_t size = 0;
        std::shared_ptr<const Config> config;
    };
    std::shared_ptr<const Config> defaults();
    std::mutex m_;
    std::map<std::string, Entry> entries_;
    std::shared_ptr<const Config> defaults_;
};

class Server {
public:
    Server(InputStream& in, OutputStream& out, ServerOptions options = {});
    ~Server();
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    // Runs the message loop until `exit` or the end of the input. Returns the
    // process exit code: 0 after shutdown, 1 otherwise.
    int run();

private:
    enum class State { Uninitialized, Running, ShutDown };

    struct Pending {
        json id;
        std::string method;
        json params;
    };

    struct Document {
        std::string uri;
        std::optional<std::string> path;  // for file:// URIs
        std::string text;
        int64_t version = 0;
        uint64_t generation = 0;  // distinguishes a reopened document
        bool dirty = true;
        std::chrono::steady_clock::time_point changed{};
        std::vector<Pending> pending;
        // Set when the text this flag was handed out with is outdated: an
        // analysis of it stops (the engine checks the flag as it walks).
        std::shared_ptr<std::atomic<bool>> outdated = std::make_shared<std::atomic<bool>>(false);
        void outdate() {
            outdated->store(true);
            outdated = std::make_shared<std::atomic<bool>>(false);
        }
    };

    // The worker's model of one document.
    struct Model {
        uint64_t generation = 0;
        int64_t version = -1;
        DocumentModel doc;
        std::shared_ptr<const Config> config;
        ProgramNames known;
        std::vector<Diagnostic> diagnostics;   // sorted, as published
        std::vector<Diagnostic> produced;      // the same in the order the engine made them
        std::vector<Checkpoint> checkpoints;   // where the next analysis may start after an edit
        std::optional<BlockRecord> hovered;  // the block of the last hover, for this version
    };

    struct Job {
        std::string uri;
        std::optional<std::string> path;
        uint64_t generation = 0;
        int64_t version = 0;
        bool has_text = false;
        std::string text;
        std::vector<Pending> pending;
        std::shared_ptr<std::atomic<bool>> outdated;
    };

    void handle(std::string_view body);
    void on_request(const json& id, const std::string& method, const json& params);
    void on_notification(const std::string& method, const json& params);
    json initialize(const json& params);
    void did_open(const json& params);
    void did_change(const json& params);
    void did_close(const json& params);
    void mark_all_dirty();
    void cancel(const json& id);
    void send(const json& message);
    void log(const std::string& message);

    void worker_loop();
    void run_job(Job& job);
    void update_model(Model& m, Job& job);
    const BlockRecord* block_of(Model& m, uint32_t line);
    json answer(const Pending& p, Model& m, bool current);
    json workspace_symbol(const json& params);
    // The other open documents and the subprogram files beside `m`'s (kept in `disk`).
    std::vector<OtherDocument> other_documents(const Model& m, std::vector<DiskDocument>& disk);
    std::optional<std::filesystem::path> config_dir(const std::optional<std::string>& path) const;
    void collect_known(Model& m, const std::optional<std::string>& path);

    FrameReader reader_;
    MessageWriter writer_;
    ServerOptions options_;
    State state_ = State::Uninitialized;
    Encoding encoding_ = Encoding::Utf16;
    std::optional<std::string> root_;
    bool watch_registration_ = false;

    std::mutex m_;  // guards docs_, stop_ (and is held while publishing)
    std::condition_variable cv_;
    std::map<std::string, Document> docs_;
    bool stop_ = false;
    std::vector<Pending> workspace_pending_;  // workspace/symbol requests for the worker
    uint64_t next_generation_ = 1;

    // Worker thread only.
    std::map<std::string, Model> models_;
    SubprogramDirectories directories_;
    std::atomic<bool> names_stale_{false};

    ConfigCache configs_;
    std::thread worker_;
};

}  // namespace osplint::lsp
