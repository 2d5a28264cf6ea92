#include "api/check.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "rules/registry.h"

namespace osplint {

std::string check_source(const std::string& path, ByteSource& src, const Config& config,
                         const AnalysisOptions& options, DiagnosticSink& sink) {
    EngineOptions eo = options;
    if (!eo.rules) eo.rules = &builtin_rules();
    return run_engine(path, src, config, eo, sink, options.stats);
}

namespace {

// A file that cannot be checked at all: begin_file, end_file with the reason.
std::string unreadable(const std::string& path, std::string reason, DiagnosticSink& sink) {
    sink.begin_file(path);
    sink.end_file(path, reason);
    return reason;
}

}  // namespace

std::string check_fd(int fd, const std::string& path, const Config& config, const AnalysisOptions& options,
                     DiagnosticSink& sink) {
    struct stat st;
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
        if (static_cast<uint64_t>(st.st_size) > kMaxInputSize) return unreadable(path, kTooLargeMessage, sink);
        const std::optional<FileStamp> opened = file_stamp(fd);
        if (!opened) return unreadable(path, std::string("cannot read: ") + std::strerror(errno), sink);
        // A file that changes while it is read is an I/O error (kChangedMessage).
        FdSource src(fd, *opened);
        return check_source(path, src, config, options, sink);
    }
    SpoolSource src(fd);
    if (!src.ok()) return unreadable(path, src.error(), sink);
    return check_source(path, src, config, options, sink);
}

std::string check_path(const std::string& path, const Config& config, const AnalysisOptions& options,
                       DiagnosticSink& sink) {
    std::error_code ec;
    const auto st = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(st)) {
        const bool dangling = std::filesystem::is_symlink(std::filesystem::symlink_status(path, ec));
        return unreadable(path, dangling ? "dangling symbolic link" : "no such file", sink);
    }
    if (std::filesystem::is_directory(st)) return unreadable(path, "is a directory", sink);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return unreadable(path, std::string("cannot open: ") + std::strerror(errno), sink);
    std::string error = check_fd(fd, path, config, options, sink);
    ::close(fd);
    return error;
}

void ResultCollector::begin_file(const std::string& path) {
    result_ = FileResult{};
    result_.path = path;
}

void ResultCollector::end_file(const std::string&, const std::string& io_error) {
    result_.io_error = io_error;
    std::stable_sort(result_.diagnostics.begin(), result_.diagnostics.end(), diagnostic_less);
    std::stable_sort(result_.suppressed.begin(), result_.suppressed.end(),
                     [](const SuppressedDiagnostic& a, const SuppressedDiagnostic& b) {
                         return diagnostic_less(a.diagnostic, b.diagnostic);
                     });
}

FileResult check_text(const std::string& path, std::string_view text, const Config& config,
                      const AnalysisOptions& options) {
    ResultCollector collect;
    if (text.size() > kMaxInputSize) {
        unreadable(path, kTooLargeMessage, collect);
        return collect.take();
    }
    MemorySource src(text);
    check_source(path, src, config, options, collect);
    return collect.take();
}

FileResult check_file(const std::string& path, const Config& config, const AnalysisOptions& options) {
    ResultCollector collect;
    check_path(path, config, options, collect);
    return collect.take();
}

}  // namespace osplint
