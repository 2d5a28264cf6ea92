// osplint as a library: check a buffer or a file, get diagnostics.
//
// This is the whole public surface a CAM post-processor needs:
//
//     osplint::Config config = osplint::load_config("osplint.toml");  // or Config{}
//     osplint::FileResult r = osplint::check_text("PART.MIN", text, config);
//     for (const auto& d : r.diagnostics) ... d.rule, d.severity, d.message, d.range.start.line
//
// The CLI (`osplint check`) and the language server are thin shells over it.
#pragma once

#include <string>
#include <vector>

#include "analyzer/analyzer.h"
#include "analyzer/config.h"
#include "analyzer/diagnostic.h"

namespace osplint {

struct FileResult {
    std::string path;
    std::vector<Diagnostic> diagnostics;
    // Set when the file could not be read (the path is missing, a directory, ...).
    std::string io_error;
};

FileResult check_text(std::string path, std::string text, const Config& config,
                      const AnalysisOptions& options = {});
FileResult check_file(const std::string& path, const Config& config, const AnalysisOptions& options = {});

std::string_view version();

}  // namespace osplint
