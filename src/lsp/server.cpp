#include "lsp/server.h"

#include <algorithm>
#include <iterator>

#include "api/config.h"
#include "osplint/osplint.h"
#include "lsp/features.h"
#include "lsp/requests.h"
#include "lsp/structure.h"
#include "support/text.h"

namespace fs = std::filesystem;

namespace osplint::lsp {

namespace {

using Clock = std::chrono::steady_clock;

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
    if (is_document_request(method)) {
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

}  // namespace osplint::lsp
