// Subprogram summaries made by walking the subprogram (see summaries.h).
#include "engine/summaries.h"

#include <fcntl.h>
#include <unistd.h>

#include <set>

#include "engine/engine.h"
#include "semantics/eval.h"
#include "support/io.h"

namespace osplint {

namespace {

// Keeps the state where the walk of one program ends, and what its reachable
// blocks do beyond the modal state: the common variables they assign, the
// macros they run that overwrite VC120-VC128, their RTS, and whether any of
// them starts or ends a fixed cycle or a modal call.
class EndOfProgram final : public BlockObserver {
public:
    explicit EndOfProgram(std::string_view name) : name_(name) {}
    void program(const Program& program, bool) override { in_ = !found_ && program.name == name_; }
    bool block(const BlockView& v, const LineRef&) override {
        if (!in_ || !v.reachable) return true;
        const Block& b = v.block;
        if (b.statement(StmtKind::Rts)) returns_ = true;
        for (const auto& a : b.assignments) {
            const auto key = variable_key(b, a.target, v.before);
            if (!key) {
                writes_any_ = true;  // a computed name: any variable
            } else if (auto n = common_variable_number(*key)) {
                writes_.insert(*n);
            }
        }
        if (const MacroCall* c = v.call) {
            if (c->kind == CallKind::Call && !c->spec) writes_any_ = true;  // a subprogram it calls in turn
            if (c->spec && c->spec->has(Hazard::OverwritesVc120To128) && clobbers_.empty()) clobbers_ = c->spec->name;
        }
        if (!(v.before.uncancelled == v.after.uncancelled)) cycle_touched_ = true;
        if (!(v.before.modin == v.after.modin)) modin_touched_ = true;
        return true;
    }
    void program_end(const Program& program, const ModalState* final_state) override {
        if (found_ || program.name != name_) return;
        found_ = true;
        in_ = false;
        line_ = program.first_block + 1;
        if (final_state) end_ = *final_state;
    }
    bool found() const { return found_; }
    uint32_t line() const { return line_; }
    const ModalState* end() const { return end_ ? &*end_ : nullptr; }

    // Adds what the blocks do to a summary made from the end states.
    void add_to(SubprogramSummary& s, const ModalState& end0, const ModalState& end1) const {
        s.returns = returns_;
        s.writes_any = writes_any_;
        s.clobbers_reserved = clobbers_;
        for (int n : writes_) {
            const std::string key = "VC" + std::to_string(n);
            auto a = end0.vars.find(key), b = end1.vars.find(key);
            std::optional<double> v;
            if (a != end0.vars.end() && b != end1.vars.end() && a->second == b->second) v = a->second;
            s.writes[n] = v;
        }
        // Left "as it came" in both walks, but some block changes it: it is
        // cancelled or opened on some paths only, which is not known.
        if (cycle_touched_ && s.uncancelled.kind == ModeEffect<std::optional<OpenCycle>>::Kind::Kept) {
            s.uncancelled.kind = ModeEffect<std::optional<OpenCycle>>::Kind::Unknown;
            s.cycle.kind = ModeEffect<std::optional<ActiveCycle>>::Kind::Unknown;
        }
        if (modin_touched_ && s.modin.kind == ModeEffect<std::optional<ActiveModin>>::Kind::Kept)
            s.modin.kind = ModeEffect<std::optional<ActiveModin>>::Kind::Unknown;
    }

private:
    std::string_view name_;
    bool in_ = false;
    bool found_ = false;
    uint32_t line_ = 0;
    std::optional<ModalState> end_;
    bool returns_ = false;
    bool writes_any_ = false;
    std::set<int> writes_;
    std::string clobbers_;
    bool cycle_touched_ = false;
    bool modin_touched_ = false;
};

}  // namespace

const SubprogramSummary* SubprogramSummaries::find(const Config& config, const std::string& checked_path,
                                                   std::string_view name) {
    const std::filesystem::path dir = std::filesystem::path(checked_path).parent_path();
    const std::optional<std::filesystem::path> file = dirs_.file_defining(dir, name);
    if (!file) return nullptr;
    std::error_code ec;
    const auto mtime = std::filesystem::last_write_time(*file, ec);
    const auto size = std::filesystem::file_size(*file, ec);
    if (ec) return nullptr;
    // Keyed by the file's stamp too: a summary handed out stays valid while
    // a walk uses it, even when the file changes meanwhile.
    const std::string key = std::to_string(reinterpret_cast<std::uintptr_t>(&config)) + '\n' + file->string() + '\n' + std::to_string(mtime.time_since_epoch().count()) + '\n' +
                            std::to_string(size) + '\n' + std::string(name);
    std::lock_guard lock(m_);
    auto [it, added] = cache_.try_emplace(key);
    if (added) it->second = make(config, *file, name);
    return it->second ? &*it->second : nullptr;
}

std::optional<SubprogramSummary> SubprogramSummaries::make(const Config& config, const std::filesystem::path& file,
                                                           std::string_view name) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return std::nullopt;
    FdSource src(fd, std::nullopt);
    std::optional<SubprogramSummary> s = walk(config, file.string(), src, name);
    ::close(fd);
    return s;
}

const SubprogramSummary* SubprogramSummaries::local(const Config& config, const std::string& path, ByteSource& src,
                                                   uint64_t begin, uint64_t end, uint32_t first_line,
                                                   std::string_view name) {
    // Keyed by the program's bytes (FNV-1a, read in pieces): an edit of it
    // makes a new summary, one elsewhere in the file does not.
    uint64_t hash = 1469598103934665603ull;
    std::string piece(std::min<uint64_t>(end - begin, 1u << 16), '\0');
    for (uint64_t at = begin; at < end;) {
        const int64_t got = src.read(at, piece.data(), std::min<uint64_t>(piece.size(), end - at));
        if (got <= 0) return nullptr;
        for (int64_t i = 0; i < got; ++i) hash = (hash ^ static_cast<unsigned char>(piece[i])) * 1099511628211ull;
        at += static_cast<uint64_t>(got);
    }
    const std::string key = std::to_string(reinterpret_cast<std::uintptr_t>(&config)) + '\n' + path + '\n' +
                            std::to_string(end - begin) + '\n' + std::to_string(hash) + '\n' +
                            std::to_string(first_line) + '\n' + std::string(name) + "\n(local)";
    std::lock_guard lock(m_);
    auto [it, added] = cache_.try_emplace(key);
    if (added) {
        WindowSource window(src, begin, end);
        it->second = walk(config, path, window, name);
        if (it->second) it->second->line += first_line - 1;  // the window's lines count from its first
    }
    return it->second ? &*it->second : nullptr;
}

std::optional<SubprogramSummary> SubprogramSummaries::walk(const Config& config, const std::string& path,
                                                           ByteSource& src, std::string_view name) {
    std::optional<ModalState> ends[2];
    uint32_t line = 0;
    std::optional<EndOfProgram> last;
    for (int which = 0; which < 2; ++which) {
        const ModalState entry = summary_probe(which);
        EndOfProgram& end = last.emplace(name);
        EngineOptions options;
        options.rules = &rules_;
        options.run_rules = false;
        options.observer = &end;
        options.subprogram_entry = &entry;  // no summaries: what it calls in turn keeps the modes
        DiscardFindings discard;
        const std::string error = run_engine(path, src, config, options, discard);
        ++walks_;
        if (!error.empty() || !end.found() || !end.end()) return std::nullopt;
        ends[which] = *end.end();
        line = end.line();
    }
    SubprogramSummary s = summarize(&*ends[0], &*ends[1]);
    last->add_to(s, *ends[0], *ends[1]);
    s.name = std::string(name);
    s.file = path;
    s.line = line;
    return s;
}

}  // namespace osplint
