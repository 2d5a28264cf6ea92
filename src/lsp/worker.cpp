// Language server: the analysis workers (see server.h). A worker takes a
// document no other worker holds, brings its model up to date with the text
// (an edit is analysed from the engine's last checkpoint before it), publishes
// the diagnostics and answers the requests that waited for that version.
#include "lsp/server.h"

#include <algorithm>
#include <iterator>
#include <tuple>

#include "api/check.h"
#include "osplint/osplint.h"
#include "lsp/features.h"
#include "lsp/hints.h"
#include "lsp/navigation.h"
#include "lsp/requests.h"
#include "lsp/structure.h"

namespace fs = std::filesystem;

namespace osplint::lsp {

namespace {

using Clock = std::chrono::steady_clock;

// An analysis stopped because its text is outdated.
struct Outdated {};
// A request's walk stopped because the text changed.
struct ContentModified {};

}  // namespace

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
