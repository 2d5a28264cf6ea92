// Language server, layers 3-4: the LSP session (server.cpp) and its analysis
// workers (worker.cpp).
//
//   transport (lsp/transport.h) -> JSON-RPC (lsp/jsonrpc.h) -> this file:
//   lifecycle, documents, scheduling -> features (lsp/features.h) -> the
//   analysis engine (engine/engine.h, the same as `osplint check`).
//
// The message loop (run()) only reads, classifies and records: document text
// is kept here, every request about a document and every analysis is handed
// to the workers (a few threads), so `shutdown` and every message are read
// and answered while analyses run. A worker takes a document no other worker
// has: while it analyses it, it alone touches the model of that document
// (its text, line index and outline: lsp/document.h); it runs the engine over
// the text, publishes the diagnostics unless the document changed meanwhile,
// and then answers the requests that waited for that version. So a long
// analysis of one document holds back neither the other documents nor the
// session.
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
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "engine/summaries.h"
#include "engine/workspace.h"
#include "lsp/document.h"
#include "lsp/features.h"
#include "lsp/jsonrpc.h"
#include "lsp/navigation.h"
#include "lsp/text.h"
#include "rules/registry.h"
#include "semantics/config.h"

namespace osplint::lsp {

struct ServerOptions {
    // Quiet time after an edit before the analysis starts (an analysis of an
    // outdated text stops as soon as the next edit arrives, so it can be short).
    std::chrono::milliseconds debounce{2};
    // Diagnostics about the server itself (stderr for `osplint lsp`); called
    // from the message loop and from every worker.
    std::function<void(const std::string&)> log;
    // Also log when each analysis starts and the time it took.
    bool log_timing = false;
    // Documents analysed at the same time (0: 2 to 4, from the hardware).
    unsigned workers = 0;
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
    // The configuration of `file` in it: with the [[per-path]] tables that
    // match the file applied (the same object for files that match the same).
    std::shared_ptr<const Config> for_file(const std::shared_ptr<const Config>& config,
                                           const std::optional<std::filesystem::path>& file);
    void invalidate();

private:
    struct Entry {
        // Modification time and size of the file and of those it extends.
        std::vector<std::pair<std::filesystem::file_time_type, std::uintmax_t>> stamps;
        std::shared_ptr<const Config> config;
    };
    struct Derived {
        std::shared_ptr<const Config> base;  // held: its address is part of the key
        std::shared_ptr<const Config> config;
    };
    std::map<std::pair<const Config*, std::vector<size_t>>, Derived> per_path_;
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
        DiagnosticTexts published;             // the texts of the findings published last (publish_text)
        std::optional<BlockRecord> hovered;  // the block of the last hover, for this version
        // The programs it defines, as last analysed: read by the other
        // documents' workers (under m_) for the names a CALL may reach.
        std::vector<std::string> program_names;
        bool on_disk = false;  // the document is a file (its folder holds subprograms)
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
    void run_job(Job& job, Model& m);
    void update_model(Model& m, Job& job);
    std::shared_ptr<const Config> config_for(const Job& job);
    void store_findings(Model& m, const std::optional<CheckpointPlace>& resumed_at, std::vector<Diagnostic>& produced,
                        std::vector<Diagnostic>& kept);
    const BlockRecord* block_of(Model& m, uint32_t line);
    // `outdated` is set when the text changes: a walk for the answer stops.
    json answer(const Pending& p, Model& m, bool current, const std::atomic<bool>* outdated);
    json workspace_symbol(const json& params);
    // The other open documents (their text now, outlined) and the subprogram
    // files beside `uri` (kept in `loaded`).
    std::vector<OtherDocument> other_documents(const std::string& uri, std::vector<DiskDocument>& loaded);
    std::optional<std::filesystem::path> config_dir(const std::optional<std::string>& path) const;
    void collect_known(Model& m, const std::optional<std::string>& path);
    SubprogramSummaries* summaries_for(const Model& m);

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

    // The models, by URI (the map under m_; a model is used by the worker
    // that holds its URI in busy_).
    std::map<std::string, std::unique_ptr<Model>> models_;
    std::set<std::string> busy_;
    SubprogramDirectories directories_;
    // What the user subprograms beside a document leave behind (engine/summaries.h).
    SubprogramSummaries summaries_{builtin_rules(), directories_};
    std::atomic<bool> names_stale_{false};

    ConfigCache configs_;
    std::vector<std::thread> workers_;
};

}  // namespace osplint::lsp
