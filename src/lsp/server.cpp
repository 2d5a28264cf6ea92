#include "lsp/server.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <tuple>
#include <set>

#include "api/check.h"
#include "api/config.h"
#include "osplint/osplint.h"
#include "lsp/features.h"
#include "lsp/hints.h"
#include "lsp/navigation.h"
#include "lsp/structure.h"
#include "support/errors.h"
#include "support/text.h"

namespace fs = std::filesystem;

namespace osplint::lsp {

namespace {

using Clock = std::chrono::steady_clock;

// An analysis stopped because its text is outdated.
struct Outdated {};
// A request's walk stopped because the text changed.
struct ContentModified {};

const json& field(const json& obj, const char* key) {
    if (!obj.is_object()) throw std::invalid_argument("params must be an object");
    auto it = obj.find(key);
    if (it == obj.end()) throw std::invalid_argument(std::string("missing '") + key + "'");
    return *it;
}

std::string uri_of(const json& params) {
    const json& td = field(params, "textDocument");
    const json& uri = field(td, "uri");
    if (!uri.is_string()) throw std::invalid_argument("textDocument.uri must be a string");
    return uri.get<std::string>();
}

// The requests answered from a document's model, and what they answer for a
// document that is not open (or closed while the request waited).
struct DocumentRequest {
    std::string_view method;
    bool null_when_empty;  // null, else an empty array
};
constexpr DocumentRequest kDocumentRequests[] = {
    {"textDocument/hover", true},          {"textDocument/completion", false},
    {"textDocument/codeAction", false},    {"textDocument/documentSymbol", false},
    {"textDocument/definition", true},     {"textDocument/references", false},
    {"textDocument/documentHighlight", false}, {"textDocument/prepareRename", true},
    {"textDocument/rename", true},         {"textDocument/foldingRange", false},
    {"textDocument/semanticTokens/full", true}, {"textDocument/semanticTokens/range", true},
    {"textDocument/inlayHint", false},     {"textDocument/signatureHelp", true},
};

const DocumentRequest* document_request(std::string_view method) {
    for (const auto& r : kDocumentRequests)
        if (r.method == method) return &r;
    return nullptr;
}

json empty_result(std::string_view method) {
    const DocumentRequest* r = document_request(method);
    return r && r->null_when_empty ? json(nullptr) : json::array();
}

bool ends_with_ci(std::string_view s, std::string_view suffix) {
    if (s.size() < suffix.size()) return false;
    for (std::size_t i = 0; i < suffix.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) !=
            std::tolower(static_cast<unsigned char>(suffix[i])))
            return false;
    return true;
}

}  // namespace

// --- configuration -----------------------------------------------------------

std::shared_ptr<const Config> ConfigCache::defaults() {
    if (!defaults_) defaults_ = std::make_shared<const Config>();
    return defaults_;
}

void ConfigCache::invalidate() {
    std::lock_guard lock(m_);
    entries_.clear();
    per_path_.clear();
}

std::shared_ptr<const Config> ConfigCache::for_file(const std::shared_ptr<const Config>& config,
                                                    const std::optional<fs::path>& file) {
    if (!config || !file || config->per_path.empty()) return config;
    std::vector<size_t> tables = config->per_path_matching(*file);
    if (tables.empty()) return config;
    std::lock_guard lock(m_);
    for (auto it = per_path_.begin(); it != per_path_.end();)  // those nothing uses any more
        it = it->second.base.use_count() == 1 && it->second.config.use_count() == 1 ? per_path_.erase(it)
                                                                                     : std::next(it);
    auto& slot = per_path_[{config.get(), tables}];
    if (!slot.config) {
        auto derived = std::make_shared<Config>(*config);
        derived->apply_per_path(tables);
        slot = {config, std::move(derived)};
    }
    return slot.config;
}

ConfigCache::Lookup ConfigCache::get(const std::optional<fs::path>& dir) {
    std::lock_guard lock(m_);
    Lookup out;
    std::optional<fs::path> file = dir ? find_config(*dir) : std::nullopt;
    if (!file) {
        out.config = defaults();
        return out;
    }
    // A change of the file or of a file it extends is a change of the configuration.
    auto stamps_of = [&](const std::shared_ptr<const Config>& config) {
        std::vector<std::pair<fs::file_time_type, std::uintmax_t>> stamps;
        std::vector<std::string> files{file->string()};
        if (config) files.insert(files.end(), config->extends.begin(), config->extends.end());
        for (const auto& f : files) {
            std::error_code ec;
            const auto mtime = fs::last_write_time(f, ec);
            const auto size = ec ? 0 : fs::file_size(f, ec);
            stamps.emplace_back(mtime, size);
        }
        return stamps;
    };
    const std::string key = file->string();
    auto it = entries_.find(key);
    if (it != entries_.end() && it->second.stamps == stamps_of(it->second.config)) {
        out.config = it->second.config;
        return out;
    }
    out.reloaded = it != entries_.end();
    Entry e;
    try {
        e.config = std::make_shared<const Config>(load_config(*file));
        e.stamps = stamps_of(e.config);
    } catch (const std::exception& ex) {
        e.config = defaults();
        e.stamps = stamps_of(nullptr);
        out.error = std::string("osplint: configuration error: ") + ex.what() + " (using the defaults)";
    }
    out.config = e.config;
    entries_[key] = std::move(e);
    return out;
}

// --- the session -------------------------------------------------------------

Server::Server(InputStream& in, OutputStream& out, ServerOptions options)
    : reader_(in), writer_(out), options_(std::move(options)) {
    unsigned n = options_.workers;
    if (n == 0) n = std::clamp(std::thread::hardware_concurrency(), 2u, 4u);
    for (unsigned i = 0; i < n; ++i) workers_.emplace_back([this] { worker_loop(); });
}

Server::~Server() {
    {
        std::lock_guard lock(m_);
        stop_ = true;
        for (auto& [uri, d] : docs_) d.outdate();  // a running analysis stops
    }
    cv_.notify_all();
    for (auto& w : workers_)
        if (w.joinable()) w.join();
}

void Server::send(const json& message) { writer_.send(message); }

void Server::log(const std::string& message) {
    if (options_.log) options_.log(message);
}

int Server::run() {
    for (;;) {
        ReadResult r = reader_.next();
        if (r.kind == ReadResult::Eof) break;
        if (r.kind == ReadResult::Error) {
            log("refused input: " + r.problem);
            send(make_error(nullptr, error::kParseError, r.problem));
            continue;
        }
        Incoming in = classify(r.body);
        if (in.kind == Incoming::Invalid) {
            send(make_error(in.id, in.error_code, in.problem));
            continue;
        }
        if (in.kind == Incoming::Response) continue;  // answers to our requests
        if (in.kind == Incoming::Notification && in.method == "exit") return state_ == State::ShutDown ? 0 : 1;
        try {
            if (in.kind == Incoming::Request)
                on_request(in.id, in.method, in.params);
            else
                on_notification(in.method, in.params);
        } catch (const std::invalid_argument& e) {
            if (in.kind == Incoming::Request)
                send(make_error(in.id, error::kInvalidParams, e.what()));
            else
                log(in.method + ": " + e.what());
        } catch (const json::exception& e) {
            if (in.kind == Incoming::Request)
                send(make_error(in.id, error::kInvalidParams, e.what()));
            else
                log(in.method + ": " + e.what());
        } catch (const std::exception& e) {
            if (in.kind == Incoming::Request)
                send(make_error(in.id, error::kInternalError, e.what()));
            else
                log(in.method + ": " + e.what());
        }
    }
    return state_ == State::ShutDown ? 0 : 1;
}

void Server::on_request(const json& id, const std::string& method, const json& params) {
    if (state_ == State::Uninitialized && method != "initialize") {
        send(make_error(id, error::kServerNotInitialized, "the server is not initialized"));
        return;
    }
    if (state_ == State::ShutDown) {
        send(make_error(id, error::kInvalidRequest, "the server is shut down"));
        return;
    }
    if (method == "initialize") {
        if (state_ != State::Uninitialized) {
            send(make_error(id, error::kInvalidRequest, "initialize may be sent only once"));
            return;
        }
        json result = initialize(params);
        state_ = State::Running;
        send(make_response(id, std::move(result)));
        return;
    }
    if (method == "shutdown") {
        state_ = State::ShutDown;
        send(make_response(id, nullptr));
        return;
    }
    if (method == "workspace/symbol") {
        std::lock_guard lock(m_);
        workspace_pending_.push_back({id, method, params});
        cv_.notify_all();
        return;
    }
    if (document_request(method)) {
        const std::string uri = uri_of(params);
        {
            std::lock_guard lock(m_);
            auto it = docs_.find(uri);
            if (it != docs_.end()) {
                it->second.pending.push_back({id, method, params});
                cv_.notify_all();
                return;
            }
        }
        // Not an open document.
        send(make_response(id, empty_result(method)));
        return;
    }
    send(make_error(id, error::kMethodNotFound, "method not supported: " + method));
}

void Server::on_notification(const std::string& method, const json& params) {
    if (state_ != State::Running) return;  // dropped before initialize and after shutdown
    if (method == "initialized") {
        if (watch_registration_) {
            json watchers = json::array(
                {{{"globPattern", "**/osplint.toml"}}, {{"globPattern", "**/*.{SSB,SUB,LIB,MSB,ssb,sub,lib,msb}"}}});
            send(make_request("osplint/watch", "client/registerCapability",
                              {{"registrations", json::array({{{"id", "osplint-watched-files"},
                                                               {"method", "workspace/didChangeWatchedFiles"},
                                                               {"registerOptions", {{"watchers", watchers}}}}})}}));
        }
    } else if (method == "textDocument/didOpen") {
        did_open(params);
    } else if (method == "textDocument/didChange") {
        did_change(params);
    } else if (method == "textDocument/didClose") {
        did_close(params);
    } else if (method == "textDocument/didSave") {
        const std::string uri = uri_of(params);
        std::lock_guard lock(m_);
        if (auto it = docs_.find(uri); it != docs_.end()) {
            it->second.dirty = true;
            it->second.changed = Clock::now() - options_.debounce;
            cv_.notify_all();
        }
    } else if (method == "workspace/didChangeWatchedFiles") {
        bool relevant = false;
        if (params.is_object() && params.contains("changes") && params["changes"].is_array())
            for (const auto& c : params["changes"]) {
                const std::string uri = c.is_object() ? c.value("uri", "") : "";
                if (ends_with_ci(uri, "osplint.toml")) {
                    configs_.invalidate();
                    relevant = true;
                } else if (is_subprogram_file(uri)) {
                    names_stale_ = true;
                    relevant = true;
                }
            }
        if (relevant) mark_all_dirty();
    } else if (method == "workspace/didChangeConfiguration") {
        mark_all_dirty();
    } else if (method == "$/cancelRequest") {
        if (params.is_object() && params.contains("id")) cancel(params["id"]);
    }
    // Other notifications ($/setTrace, ...) are ignored.
}

json Server::initialize(const json& params) {
    json caps = params.is_object() && params.contains("capabilities") ? params["capabilities"] : json::object();
    encoding_ = negotiate_encoding(caps);
    if (params.is_object()) {
        if (params.contains("rootUri") && params["rootUri"].is_string())
            root_ = uri_to_path(params["rootUri"].get<std::string>());
        else if (params.contains("rootPath") && params["rootPath"].is_string())
            root_ = params["rootPath"].get<std::string>();
        if (params.contains("workspaceFolders") && params["workspaceFolders"].is_array() &&
            !params["workspaceFolders"].empty() && params["workspaceFolders"][0].is_object() &&
            params["workspaceFolders"][0].contains("uri") && params["workspaceFolders"][0]["uri"].is_string())
            if (auto p = uri_to_path(params["workspaceFolders"][0]["uri"].get<std::string>())) root_ = p;
    }
    if (caps.is_object() && caps.contains("workspace") && caps["workspace"].is_object()) {
        const json& ws = caps["workspace"];
        if (ws.contains("didChangeWatchedFiles") && ws["didChangeWatchedFiles"].is_object())
            watch_registration_ = ws["didChangeWatchedFiles"].value("dynamicRegistration", false);
    }
    json capabilities = {
        {"positionEncoding", std::string(encoding_name(encoding_))},
        {"textDocumentSync", {{"openClose", true}, {"change", 2}, {"save", {{"includeText", false}}}}},
        {"hoverProvider", true},
        {"completionProvider", {{"triggerCharacters", json::array({" "})}, {"resolveProvider", false}}},
        {"codeActionProvider", {{"codeActionKinds", json::array({"quickfix"})}}},
        {"documentSymbolProvider", true},
        {"definitionProvider", true},
        {"referencesProvider", true},
        {"documentHighlightProvider", true},
        {"renameProvider", {{"prepareProvider", true}}},
        {"foldingRangeProvider", true},
        {"semanticTokensProvider", {{"legend", semantic_tokens_legend()}, {"full", true}, {"range", true}}},
        {"workspaceSymbolProvider", true},
        {"inlayHintProvider", true},
        {"signatureHelpProvider", {{"triggerCharacters", json::array({" ", "="})}}},
    };
    return json{{"capabilities", capabilities},
                {"serverInfo", {{"name", "osplint"}, {"version", std::string(version())}}}};
}

void Server::did_open(const json& params) {
    const json& td = field(params, "textDocument");
    const std::string uri = uri_of(params);
    const json& text = field(td, "text");
    if (!text.is_string()) throw std::invalid_argument("textDocument.text must be a string");
    Document d;
    d.uri = uri;
    d.path = uri_to_path(uri);
    d.text = text.get<std::string>();
    d.version = td.contains("version") && td["version"].is_number_integer() ? td["version"].get<int64_t>() : 0;
    d.changed = Clock::now() - options_.debounce;  // the first analysis starts at once
    std::lock_guard lock(m_);
    d.generation = next_generation_++;
    if (auto it = docs_.find(uri); it != docs_.end()) {
        for (const auto& p : it->second.pending)
            send(make_response(p.id, empty_result(p.method)));
        it->second.outdate();
    }
    docs_[uri] = std::move(d);
    cv_.notify_all();
}

void Server::did_change(const json& params) {
    const std::string uri = uri_of(params);
    const json& td = field(params, "textDocument");
    const json& changes = field(params, "contentChanges");
    if (!changes.is_array()) throw std::invalid_argument("contentChanges must be an array");
    std::unique_lock lock(m_);
    auto it = docs_.find(uri);
    if (it == docs_.end()) {
        lock.unlock();
        log("didChange for a document that is not open: " + uri);
        return;
    }
    Document& d = it->second;
    // Apply to a copy: a malformed event leaves the document as it was.
    std::string text = d.text;
    for (const auto& c : changes) apply_change(text, c, encoding_);
    d.text = std::move(text);
    d.outdate();
    if (td.contains("version") && td["version"].is_number_integer())
        d.version = td["version"].get<int64_t>();
    else
        ++d.version;
    d.dirty = true;
    d.changed = Clock::now();
    cv_.notify_all();
}

void Server::did_close(const json& params) {
    const std::string uri = uri_of(params);
    std::lock_guard lock(m_);
    auto it = docs_.find(uri);
    if (it == docs_.end()) return;
    for (const auto& p : it->second.pending)
        send(make_response(p.id, empty_result(p.method)));
    it->second.outdate();
    docs_.erase(it);
    send(make_notification("textDocument/publishDiagnostics", {{"uri", uri}, {"diagnostics", json::array()}}));
    cv_.notify_all();
}

void Server::mark_all_dirty() {
    std::lock_guard lock(m_);
    const auto now = Clock::now();
    for (auto& [uri, d] : docs_) {
        d.dirty = true;
        d.changed = now;
    }
    cv_.notify_all();
}

void Server::cancel(const json& id) {
    std::lock_guard lock(m_);
    for (auto& [uri, d] : docs_) {
        auto it = std::find_if(d.pending.begin(), d.pending.end(), [&](const Pending& p) { return p.id == id; });
        if (it != d.pending.end()) {
            send(make_error(id, error::kRequestCancelled, "cancelled"));
            d.pending.erase(it);
            return;
        }
    }
}

// --- the worker ----------------------------------------------------------------

void Server::worker_loop() {
    std::unique_lock lock(m_);
    for (;;) {
        if (stop_) return;
        // Forget the models of closed documents (not one a worker holds).
        for (auto it = models_.begin(); it != models_.end();) {
            auto d = docs_.find(it->first);
            if (!busy_.count(it->first) && (d == docs_.end() || d->second.generation != it->second->generation))
                it = models_.erase(it);
            else
                ++it;
        }
        if (!workspace_pending_.empty()) {
            std::vector<Pending> work = std::move(workspace_pending_);
            workspace_pending_.clear();
            lock.unlock();
            for (const auto& p : work) {
                try {
                    send(make_response(p.id, workspace_symbol(p.params)));
                } catch (const std::exception& e) {
                    send(make_error(p.id, error::kInternalError, e.what()));
                }
            }
            lock.lock();
            continue;
        }
        // A document no other worker holds: one with a request waiting first
        // (no debounce), else one whose quiet time after an edit is over.
        const auto now = Clock::now();
        Document* pick = nullptr;
        auto next_due = Clock::time_point::max();
        for (auto& [uri, d] : docs_) {
            if (busy_.count(uri)) continue;
            if (!d.pending.empty()) {
                pick = &d;
                break;
            }
            if (!d.dirty) continue;
            const auto due = d.changed + options_.debounce;
            if (due <= now && !pick) pick = &d;
            next_due = std::min(next_due, due);
        }
        if (!pick) {
            if (next_due == Clock::time_point::max())
                cv_.wait(lock);
            else
                cv_.wait_until(lock, next_due);
            continue;
        }
        Job job;
        job.uri = pick->uri;
        job.path = pick->path;
        job.generation = pick->generation;
        job.version = pick->version;
        std::unique_ptr<Model>& slot = models_[job.uri];
        if (!slot) slot = std::make_unique<Model>();
        Model& model = *slot;  // stays in place while busy_ holds its URI
        if (pick->dirty || model.generation != job.generation) {
            job.has_text = true;
            job.text = pick->text;
            pick->dirty = false;
        }
        job.pending = std::move(pick->pending);
        pick->pending.clear();
        job.outdated = pick->outdated;
        busy_.insert(job.uri);
        lock.unlock();
        try {
            run_job(job, model);
        } catch (const std::exception& e) {
            log(std::string("analysis failed: ") + e.what());
            for (const auto& p : job.pending) send(make_error(p.id, error::kInternalError, e.what()));
        }
        lock.lock();
        busy_.erase(job.uri);
        cv_.notify_all();  // its requests that came meanwhile, and the other workers
    }
}

std::optional<fs::path> Server::config_dir(const std::optional<std::string>& path) const {
    if (path) {
        fs::path dir = fs::path(*path).parent_path();
        return dir.empty() ? fs::path(".") : dir;
    }
    if (root_) return fs::path(*root_);
    return std::nullopt;
}

SubprogramSummaries* Server::summaries_for(const Model& m) {
    // A document with no file (untitled) has no folder to look in.
    return m.on_disk ? &summaries_ : nullptr;
}

void Server::collect_known(Model& m, const std::optional<std::string>& path) {
    m.on_disk = path.has_value();
    m.known.clear();
    if (names_stale_.exchange(false)) directories_.invalidate();
    // Subprogram files beside the document (.SSB/.SUB/.LIB/.MSB).
    if (path) directories_.add_names(fs::path(*path).parent_path(), m.known);
    // Programs of the other open documents, as last analysed.
    std::lock_guard lock(m_);
    for (const auto& [uri, other] : models_) {
        if (other.get() == &m) continue;
        for (const auto& name : other->program_names) m.known.insert(name);
    }
}

// The configuration of the job's document; a broken file is shown once, and
// a changed one has the other documents analysed again.
std::shared_ptr<const Config> Server::config_for(const Job& job) {
    auto lookup = configs_.get(config_dir(job.path));
    lookup.config = configs_.for_file(lookup.config, job.path);
    if (!lookup.error.empty()) {
        log(lookup.error);
        send(make_notification("window/showMessage", {{"type", 1}, {"message", lookup.error}}));
    }
    if (lookup.reloaded) {
        // Other documents were analysed with the old configuration.
        std::lock_guard lock(m_);
        for (auto& [uri, d] : docs_)
            if (uri != job.uri) {
                d.dirty = true;
                d.changed = Clock::now();
            }
        cv_.notify_all();
    }
    return lookup.config;
}

void Server::update_model(Model& m, Job& job) {
    const std::shared_ptr<const Config> config = config_for(job);
    if (m.generation != job.generation) {
        Model fresh;
        fresh.generation = job.generation;
        std::lock_guard lock(m_);  // its program names are read by the other workers
        m = std::move(fresh);
    }
    const auto t0 = Clock::now();
    if (options_.log_timing) log(job.uri + " v" + std::to_string(job.version) + ": analysis started");
    m.doc.path = job.path ? *job.path : job.uri;
    // An edit: the analysis starts at the last checkpoint before it, when the
    // configuration and the known programs are those of the last analysis.
    ProgramNames known_before = std::move(m.known);
    collect_known(m, job.path);
    TextChange edit;
    const bool resumable = m.config == config && known_before == m.known && !m.checkpoints.empty();
    if (resumable) edit = text_change(m.doc.text(), job.text);
    else m.checkpoints.clear();
    m.doc.set_text(std::move(job.text));
    m.version = job.version;
    m.config = config;
    m.hovered.reset();

    struct Produced final : DiagnosticSink {
        void diagnostic(Diagnostic&& d) override { out.push_back(std::move(d)); }
        std::vector<Diagnostic> out;
    } produced;
    AnalysisOptions opts;
    opts.known_programs = &m.known;
    opts.summaries = summaries_for(m);
    opts.outline = &m.doc.outline;
    opts.cancel = job.outdated.get();
    // A checkpoint every 1/32 of the document (at least every 64 KiB).
    opts.checkpoint_every = std::max<uint64_t>(uint64_t(64) << 10, m.doc.text().size() / 32);
    opts.checkpoints = &m.checkpoints;
    opts.edit = edit;
    std::optional<CheckpointPlace> resumed_at;
    opts.resumed_at = &resumed_at;
    std::optional<Convergence> converged;
    opts.converged = &converged;
    MemorySource src(m.doc.text());
    auto analyse = [&] {
        if (check_source(m.doc.path, src, *m.config, opts, produced) == kCancelled) {
            m.version = -1;  // half analysed: the analysis of the newer text follows
            m.checkpoints.clear();
            m.produced.clear();
            throw Outdated{};
        }
    };
    analyse();
    // Where the analysis ended early, the previous findings from there on
    // stand, moved by the edit.
    std::vector<Diagnostic> kept;
    if (converged) {
        const auto move = line_edit_move(edit);
        bool ok = move && converged->old_diagnostics <= m.produced.size();
        for (size_t i = ok ? converged->old_diagnostics : m.produced.size(); ok && i < m.produced.size(); ++i) {
            kept.push_back(std::move(m.produced[i]));
            ok = move_diagnostic(kept.back(), *move);
        }
        if (!ok) {  // not expected: the whole text again, from no checkpoint
            log(job.uri + ": the findings after an early end could not be moved; analysing the whole text");
            kept.clear();
            m.checkpoints.clear();
            m.produced.clear();
            produced.out.clear();
            opts.edit = TextChange{};
            analyse();
            resumed_at.reset();
            converged.reset();
        }
    }
    store_findings(m, resumed_at, produced.out, kept);
    if (options_.log_timing) {
        const auto t1 = Clock::now();
        auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
        log(job.uri + " v" + std::to_string(job.version) + ": analysed in " + std::to_string(ms(t0, t1)) + " ms" +
            (resumed_at ? " from line " + std::to_string(resumed_at->line) : std::string(" from the start")) +
            (converged ? " to line " + std::to_string(converged->at.line) : std::string()) + ", " +
            std::to_string(m.diagnostics.size()) + " finding(s)");
    }
}

// The model's findings after an analysis: those made before the checkpoint
// it started at, then the new ones, then those kept after where it ended
// early; and the program names the document defines.
void Server::store_findings(Model& m, const std::optional<CheckpointPlace>& resumed_at,
                            std::vector<Diagnostic>& produced, std::vector<Diagnostic>& kept) {
    if (resumed_at) m.produced.resize(std::min<size_t>(m.produced.size(), resumed_at->diagnostics));
    else m.produced.clear();
    for (auto& d : produced) m.produced.push_back(std::move(d));
    for (auto& d : kept) m.produced.push_back(std::move(d));
    m.diagnostics = m.produced;
    std::stable_sort(m.diagnostics.begin(), m.diagnostics.end(), diagnostic_less);
    std::vector<std::string> names;
    for (const auto& p : m.doc.outline.programs)
        if (!p.name.empty()) names.push_back(p.name);
    std::lock_guard lock(m_);
    m.program_names = std::move(names);
}

const BlockRecord* Server::block_of(Model& m, uint32_t line) {
    if (!m.hovered || m.hovered->block.line != line) m.hovered = block_at(m.doc, *m.config, &m.known, summaries_for(m), line);
    return m.hovered ? &*m.hovered : nullptr;
}

void Server::run_job(Job& job, Model& m) {
    if (job.has_text) {
        try {
            update_model(m, job);
        } catch (const Outdated&) {
            // A newer text arrived during the analysis: the requests that
            // waited wait for the analysis of that one.
            if (options_.log_timing) log(job.uri + " v" + std::to_string(job.version) + ": outdated, analysis stopped");
            std::lock_guard lock(m_);
            if (auto it = docs_.find(job.uri); it != docs_.end() && it->second.generation == job.generation) {
                auto& pending = it->second.pending;
                pending.insert(pending.begin(), std::make_move_iterator(job.pending.begin()),
                               std::make_move_iterator(job.pending.end()));
                it->second.dirty = true;
                cv_.notify_all();
            } else {
                for (const auto& p : job.pending)
                    send(make_response(p.id, empty_result(p.method)));
            }
            return;
        } catch (const std::exception& e) {
            // Never leave a document without a model: keep the text, report.
            log(std::string("analysis failed: ") + e.what());
            send(make_notification("window/showMessage",
                                   {{"type", 1}, {"message", std::string("osplint: analysis failed: ") + e.what()}}));
            m.diagnostics.clear();
            m.produced.clear();
            m.checkpoints.clear();
            m.hovered.reset();
            if (!m.config) m.config = configs_.get(std::nullopt).config;
        }
        std::lock_guard lock(m_);
        auto it = docs_.find(job.uri);
        if (it != docs_.end() && it->second.generation == job.generation && it->second.version == job.version)
            writer_.send_text(publish_text(job.uri, job.version, m.diagnostics, encoding_, m.published));
        // else: the document changed or closed meanwhile; these results are outdated.
    }
    const bool current = m.generation == job.generation && m.config;
    for (const auto& p : job.pending) {
        json result;
        try {
            result = answer(p, m, current, job.outdated.get());
        } catch (const ContentModified&) {
            send(make_error(p.id, error::kContentModified, "the document changed while the request was answered"));
            continue;
        } catch (const std::invalid_argument& e) {
            send(make_error(p.id, error::kInvalidParams, e.what()));
            continue;
        } catch (const json::exception& e) {
            send(make_error(p.id, error::kInvalidParams, e.what()));
            continue;
        }
        send(make_response(p.id, std::move(result)));
    }
}

std::vector<OtherDocument> Server::other_documents(const std::string& uri, std::vector<DiskDocument>& loaded) {
    std::set<std::string> open;
    std::vector<std::tuple<std::string, std::string, std::string>> texts;  // uri, path, text
    {
        std::lock_guard lock(m_);
        for (const auto& [u, d] : docs_) {
            if (d.path) open.insert(fs::path(*d.path).lexically_normal().string());
            if (u != uri) texts.emplace_back(u, d.path.value_or(u), d.text);
        }
    }
    for (auto& [u, path, text] : texts) loaded.push_back(outlined_document(u, path, std::move(text)));
    if (auto own = uri_to_path(uri)) {
        fs::path dir = fs::path(*own).parent_path();
        for (auto& d : sibling_documents(dir.empty() ? fs::path(".") : dir, open)) loaded.push_back(std::move(d));
    }
    std::vector<OtherDocument> out;
    for (const auto& d : loaded) out.push_back({d.uri, &d.doc});
    return out;
}

json Server::workspace_symbol(const json& params) {
    std::string query;
    if (params.is_object() && params.contains("query") && params["query"].is_string()) query = params["query"];
    // The open documents: their text in the editor.
    std::vector<std::tuple<std::string, std::string, std::string>> texts;  // uri, path, text
    std::vector<std::string> open;
    std::set<std::string> dirs;
    {
        std::lock_guard lock(m_);
        for (const auto& [uri, d] : docs_) {
            texts.emplace_back(uri, d.path.value_or(uri), d.text);
            if (d.path) {
                open.push_back(fs::path(*d.path).lexically_normal().string());
                dirs.insert(fs::path(*d.path).parent_path().string());
            }
        }
    }
    std::vector<SymbolSource> sources;
    for (auto& [uri, path, text] : texts) {
        auto doc = std::make_shared<DiskDocument>(outlined_document(uri, path, std::move(text)));
        sources.push_back({uri, std::shared_ptr<const DocumentModel>(doc, &doc->doc)});
    }
    // The workspace folder (and below); without one, the folders of the open documents.
    if (root_) {
        for (auto& d : folder_documents(fs::path(*root_), open)) sources.push_back(std::move(d));
    } else {
        for (const auto& dir : dirs)
            for (auto& d : folder_documents(fs::path(dir), open))
                if (fs::path(d.doc->path).parent_path() == fs::path(dir)) sources.push_back(std::move(d));
    }
    return workspace_symbols(sources, query, encoding_);
}

json Server::answer(const Pending& p, Model& m, bool current, const std::atomic<bool>* outdated) {
    const bool is_hover = p.method == "textDocument/hover";
    if (!current) return empty_result(p.method);
    const SourceText& source = m.doc.source();
    if (p.method == "textDocument/documentSymbol") return document_symbols(m.doc, encoding_);
    if (p.method == "textDocument/foldingRange") return folding_ranges(m.doc);
    if (p.method == "textDocument/semanticTokens/full") return semantic_tokens(m.doc, encoding_);
    if (p.method == "textDocument/inlayHint") {
        const ByteRange r = from_lsp_range(source, field(p.params, "range"), encoding_);
        json hints =
            inlay_hints(m.doc, *m.config, &m.known, summaries_for(m), source.line_of(r.begin), source.line_of(r.end), encoding_, outdated);
        if (outdated && outdated->load()) throw ContentModified{};  // the walk stopped: an edit came
        return hints;
    }
    if (p.method == "textDocument/semanticTokens/range") {
        const ByteRange r = from_lsp_range(source, field(p.params, "range"), encoding_);
        return semantic_tokens(m.doc, encoding_, source.line_of(r.begin), source.line_of(r.end));
    }
    if (p.method == "textDocument/codeAction") {
        field(p.params, "context");
        return code_actions(uri_of(p.params), p.params, source, m.version, encoding_);
    }
    const uint32_t offset = from_lsp_position(source, field(p.params, "position"), encoding_);
    if (p.method == "textDocument/definition" || p.method == "textDocument/references") {
        std::vector<DiskDocument> disk;
        std::vector<OtherDocument> others;
        if (name_at(m.doc, offset).kind == NameAt::Program) others = other_documents(uri_of(p.params), disk);
        if (p.method == "textDocument/definition") return definition(m.doc, uri_of(p.params), offset, others, encoding_);
        bool declaration = true;
        if (p.params.contains("context") && p.params["context"].is_object())
            declaration = p.params["context"].value("includeDeclaration", true);
        return references(m.doc, uri_of(p.params), offset, declaration, others, encoding_);
    }
    if (p.method == "textDocument/signatureHelp") return signature_help(m.doc, *m.config, offset);
    if (p.method == "textDocument/documentHighlight") return document_highlight(m.doc, offset, encoding_);
    if (p.method == "textDocument/prepareRename") return prepare_rename(m.doc, offset, encoding_);
    if (p.method == "textDocument/rename") {
        const json& name = field(p.params, "newName");
        if (!name.is_string()) throw std::invalid_argument("newName must be a string");
        return rename(m.doc, uri_of(p.params), offset, name.get<std::string>(), encoding_);
    }
    const uint32_t line = source.line_of(offset);
    if (is_hover) return hover(m.doc, block_of(m, line), *m.config, offset, encoding_);
    // Completion: the line up to the cursor, the programs known here.
    const uint32_t column = offset - source.line_start(line);
    ProgramNames programs = m.known;
    for (const auto& prog : m.doc.outline.programs)
        if (!prog.name.empty()) programs.insert(prog.name);
    return completion(source.line_text(line), column, *m.config, programs);
}

}  // namespace osplint::lsp
