#include "osplint/osplint.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "syntax/frontend.h"
#include "engine/suppress.h"

namespace osplint {

std::string_view version() { return OSPLINT_VERSION; }

FileResult check_text(std::string path, std::string text, const Config& config, const AnalysisOptions& options) {
    FileResult r;
    r.path = path;
    if (text.size() > 0xFFFFFFF0ull) {
        r.io_error = "file too large (osplint checks files up to 4 GiB)";
        return r;
    }
    ProgramFile file = parse_program_file(std::move(path), std::move(text));
    SuppressionResult s = apply_suppressions(file, analyze(file, config, options).diagnostics, config, options);
    r.diagnostics = std::move(s.diagnostics);
    r.suppressed = std::move(s.suppressed);
    return r;
}

FileResult check_file(const std::string& path, const Config& config, const AnalysisOptions& options) {
    FileResult r;
    r.path = path;
    std::error_code ec;
    auto st = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(st)) {
        r.io_error = std::filesystem::is_symlink(std::filesystem::symlink_status(path, ec))
                         ? "dangling symbolic link"
                         : "no such file";
        return r;
    }
    if (std::filesystem::is_directory(st)) {
        r.io_error = "is a directory";
        return r;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        r.io_error = std::string("cannot open: ") + std::strerror(errno);
        return r;
    }
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) {
        r.io_error = "read error";
        return r;
    }
    return check_text(path, ss.str(), config, options);
}

}  // namespace osplint
