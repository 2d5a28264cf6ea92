// Checking one input: the engine with the built-in rules, for every entry
// point (the CLI, the language server, trace, the public library API, tests).
#pragma once

#include <atomic>
#include <string>
#include <string_view>
#include <vector>

#include "engine/engine.h"
#include "osplint/diagnostic.h"
#include "semantics/config.h"

namespace osplint {

// The engine's options (engine/engine.h); the rules are the built-in ones
// unless `rules` names others.
struct AnalysisOptions : EngineOptions {
    EngineStats* stats = nullptr;
};

// Runs the engine over `src` with the built-in rules; findings go to `sink`.
// Returns the I/O error ("" when the input was read to its end).
std::string check_source(const std::string& path, ByteSource& src, const Config& config,
                         const AnalysisOptions& options, DiagnosticSink& sink);
// The same for a file on disk (a regular file is read in place; a pipe or a
// device is copied to a temporary file as it is read), and for a descriptor.
std::string check_path(const std::string& path, const Config& config, const AnalysisOptions& options,
                       DiagnosticSink& sink);
std::string check_fd(int fd, const std::string& path, const Config& config, const AnalysisOptions& options,
                     DiagnosticSink& sink);

// A sink that collects a file's findings into a FileResult, sorted.
class ResultCollector final : public DiagnosticSink {
public:
    explicit ResultCollector(bool fingerprints = true) : fingerprints_(fingerprints) {}
    bool wants_fingerprints() const override { return fingerprints_; }
    void begin_file(const std::string& path) override;
    void diagnostic(Diagnostic&& d) override { result_.diagnostics.push_back(std::move(d)); }
    void suppressed(SuppressedDiagnostic&& s) override { result_.suppressed.push_back(std::move(s)); }
    void end_file(const std::string& path, const std::string& io_error) override;
    FileResult take() { return std::move(result_); }

private:
    bool fingerprints_;
    FileResult result_;
};

// Checks a text or a file and collects the findings (sorted; fingerprints set).
FileResult check_text(const std::string& path, std::string_view text, const Config& config,
                      const AnalysisOptions& options = {});
FileResult check_file(const std::string& path, const Config& config, const AnalysisOptions& options = {});

}  // namespace osplint
