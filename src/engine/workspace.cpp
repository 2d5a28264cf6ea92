#include "engine/workspace.h"

#include <fcntl.h>
#include <unistd.h>

#include "support/text.h"
#include "syntax/outline.h"

namespace osplint {

bool add_program_names(ByteSource& src, ProgramNames& out) {
    OutlineOptions options;
    options.names_only = true;
    const FileOutline o = outline_file(src, options);
    if (!o.ok()) return false;
    for (const auto& p : o.programs)
        if (!p.name.empty()) out.insert(p.name);
    return true;
}

bool add_program_names(const std::filesystem::path& file, ProgramNames& out) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    FdSource src(fd, std::nullopt);
    const bool ok = add_program_names(src, out);
    ::close(fd);
    return ok;
}

void SubprogramDirectories::add_names(const std::filesystem::path& dir_in, ProgramNames& out) {
    const std::filesystem::path dir = dir_in.empty() ? std::filesystem::path(".") : dir_in;
    std::error_code ec;
    const auto dir_mtime = std::filesystem::last_write_time(dir, ec);
    if (ec) return;
    std::lock_guard lock(m_);
    DirEntry& d = dirs_[dir.string()];
    if (d.valid && d.mtime == dir_mtime) {
        out.insert(d.names.begin(), d.names.end());
        return;
    }
    d.names.clear();
    for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        if (!is_subprogram_file(it->path().string())) continue;
        std::error_code e2;
        if (!it->is_regular_file(e2)) continue;
        const auto size = it->file_size(e2);
        const auto mtime = it->last_write_time(e2);
        if (e2 || size > max_file_size) continue;
        FileEntry& f = files_[it->path().string()];
        if (f.mtime != mtime || f.size != size || f.names.empty()) {
            f.names.clear();
            add_program_names(it->path(), f.names);
            ++files_read_;
            f.mtime = mtime;
            f.size = size;
        }
        d.names.insert(f.names.begin(), f.names.end());
    }
    d.mtime = dir_mtime;
    d.valid = true;
    out.insert(d.names.begin(), d.names.end());
}

std::optional<std::filesystem::path> SubprogramDirectories::file_defining(const std::filesystem::path& dir_in,
                                                                          std::string_view name) {
    const std::filesystem::path dir = dir_in.empty() ? std::filesystem::path(".") : dir_in;
    ProgramNames all;
    add_names(dir, all);
    if (all.find(name) == all.end()) return std::nullopt;
    std::lock_guard lock(m_);
    for (const auto& [file, f] : files_)
        if (std::filesystem::path(file).parent_path() == dir && f.names.find(name) != f.names.end()) return file;
    return std::nullopt;
}

void SubprogramDirectories::invalidate() {
    std::lock_guard lock(m_);
    for (auto& [k, d] : dirs_) d.valid = false;
    for (auto& [k, f] : files_) f.names.clear();
}

}  // namespace osplint
