// Subprogram summaries made by walking the subprogram (see summaries.h).
#include "engine/summaries.h"

#include <fcntl.h>
#include <unistd.h>

#include "engine/engine.h"
#include "support/io.h"

namespace osplint {

namespace {

// Keeps the state where the walk of one program ends.
class EndOfProgram final : public BlockObserver {
public:
    explicit EndOfProgram(std::string_view name) : name_(name) {}
    bool block(const BlockView&, const LineRef&) override { return true; }
    void program_end(const Program& program, const ModalState* final_state) override {
        if (found_ || program.name != name_) return;
        found_ = true;
        line_ = program.first_block + 1;
        if (final_state) end_ = *final_state;
    }
    bool found() const { return found_; }
    uint32_t line() const { return line_; }
    const ModalState* end() const { return end_ ? &*end_ : nullptr; }

private:
    std::string_view name_;
    bool found_ = false;
    uint32_t line_ = 0;
    std::optional<ModalState> end_;
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
    std::optional<ModalState> ends[2];
    uint32_t line = 0;
    for (int which = 0; which < 2; ++which) {
        const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) return std::nullopt;
        FdSource src(fd, std::nullopt);
        const ModalState entry = summary_probe(which);
        EndOfProgram end(name);
        EngineOptions options;
        options.rules = &rules_;
        options.run_rules = false;
        options.observer = &end;
        options.subprogram_entry = &entry;  // no summaries: what it calls in turn keeps the modes
        DiscardFindings discard;
        const std::string error = run_engine(file.string(), src, config, options, discard);
        ::close(fd);
        ++walks_;
        if (!error.empty() || !end.found() || !end.end()) return std::nullopt;
        ends[which] = *end.end();
        line = end.line();
    }
    SubprogramSummary s = summarize(&*ends[0], &*ends[1]);
    s.name = std::string(name);
    s.file = file.string();
    s.line = line;
    return s;
}

}  // namespace osplint
