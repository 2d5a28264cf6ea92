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

#include "engine/analyzer.h"
#include "semantics/config.h"
#include "support/diagnostic.h"
#include "engine/suppress.h"

namespace osplint {

struct FileResult {
    std::string path;
    std::vector<Diagnostic> diagnostics;
    // Findings silenced by an `(osplint: disable=...)` directive of the file
    // (or, in the CLI, by a baseline), with the reason given. Not counted in
    // summaries or exit codes; listed by the JSON and SARIF reports.
    std::vector<SuppressedDiagnostic> suppressed;
    // Set when the file could not be read (the path is missing, a directory, ...).
    std::string io_error;
};

// Parses, analyzes and applies the file's suppression directives.
FileResult check_text(std::string path, std::string text, const Config& config,
                      const AnalysisOptions& options = {});
FileResult check_file(const std::string& path, const Config& config, const AnalysisOptions& options = {});

std::string_view version();

}  // namespace osplint
