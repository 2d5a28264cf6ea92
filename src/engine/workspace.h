// The program names a CALL may reach beyond the file being checked: the other
// checked files, and the subprogram files (.SSB .SUB .LIB .MSB) beside it,
// which the control searches for the CALL targets of a main program.
//
// Names are read from a file's outline (syntax/outline.h), the same reading
// the analysis makes of its own programs, so `(LIB) O1234` names O1234 in
// both.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "support/io.h"

namespace osplint {

using ProgramNames = std::set<std::string, std::less<>>;

// Adds the names of the programs `src` defines. False when it cannot be read.
bool add_program_names(ByteSource& src, ProgramNames& out);
// The same for a file; false when it cannot be opened or read.
bool add_program_names(const std::filesystem::path& file, ProgramNames& out);

// The names defined by the subprogram files of directories, remembered per
// file (by size and modification time) and per directory (by its modification
// time), so that asking again costs one stat of the directory when nothing
// changed. Thread-safe.
class SubprogramDirectories {
public:
    // Adds the names of the subprogram files in `dir` (not recursive). Files
    // over `max_file_size` are skipped (not subprogram libraries).
    void add_names(const std::filesystem::path& dir, ProgramNames& out);
    // The subprogram file in `dir` that defines the program `name` (the first
    // by path when several do), or nullopt.
    std::optional<std::filesystem::path> file_defining(const std::filesystem::path& dir, std::string_view name);
    // Forget what was read (files changed on disk).
    void invalidate();
    // How many files were read for their names so far.
    uint64_t files_read() const { return files_read_; }

    static constexpr std::uintmax_t max_file_size = 64u << 20;

private:
    struct FileEntry {
        std::filesystem::file_time_type mtime{};
        std::uintmax_t size = 0;
        ProgramNames names;
    };
    struct DirEntry {
        std::filesystem::file_time_type mtime{};
        ProgramNames names;  // the union of its files' names
        bool valid = false;
    };
    std::mutex m_;
    std::atomic<uint64_t> files_read_{0};
    std::map<std::string, FileEntry> files_;
    std::map<std::string, DirEntry> dirs_;
};

}  // namespace osplint
