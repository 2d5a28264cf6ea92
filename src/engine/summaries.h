// Summaries of the user subprograms a CALL reaches, in the checked file itself
// or in the subprogram files beside it (.SSB .SUB .LIB .MSB, as the control
// searches them): what each leaves behind for its caller
// (semantics/summary.h). A summary is made by walking the subprogram with this
// engine, without rules, from the two entry states of summary_probe, and kept
// (a state may point at it) by its file's stamp, or for a program of the
// checked file by the program's bytes, which are read from the source being
// walked (an editor's text as well as a file). Thread-safe: the files of one
// check share it.
#pragma once

#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "engine/workspace.h"
#include "semantics/summary.h"

namespace osplint {

struct Config;
class RuleRegistry;

class SubprogramSummaries {
public:
    // `rules` must outlive the summaries; `dirs` may be shared with the
    // lookup of program names.
    SubprogramSummaries(const RuleRegistry& rules, SubprogramDirectories& dirs) : rules_(rules), dirs_(dirs) {}

    // The summary of the program `name` defined in a subprogram file in the
    // directory of `checked_path`, analysed with `config` (the checked file's:
    // its catalog says which CALLs inside are macros); nullptr when no such
    // file defines it, it cannot be read, or no path reaches its end.
    const SubprogramSummary* find(const Config& config, const std::string& checked_path, std::string_view name);

    // The summary of the program `name` of the file being walked, from its
    // bytes [begin, end) of `src` (its first line: `first_line`); nullptr
    // when no path reaches its end or the bytes cannot be read.
    const SubprogramSummary* local(const Config& config, const std::string& path, ByteSource& src, uint64_t begin,
                                   uint64_t end, uint32_t first_line, std::string_view name);

    // How many subprogram walks were made so far (each summary takes two).
    uint64_t walks() const { return walks_; }

private:
    std::optional<SubprogramSummary> make(const Config& config, const std::filesystem::path& file,
                                          std::string_view name);
    // The two walks of the program `name` of `src`.
    std::optional<SubprogramSummary> walk(const Config& config, const std::string& path, ByteSource& src,
                                          std::string_view name);

    const RuleRegistry& rules_;
    SubprogramDirectories& dirs_;
    std::mutex m_;
    // By configuration, file, the file's stamp and the name.
    std::map<std::string, std::optional<SubprogramSummary>> cache_;
    std::atomic<uint64_t> walks_{0};
};

}  // namespace osplint
