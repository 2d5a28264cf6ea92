// Renderers of the one diagnostic model.
#pragma once

#include <string>
#include <vector>

#include "osplint/diagnostic.h"
#include "osplint/osplint.h"

namespace osplint {

struct Summary {
    size_t files = 0;
    size_t error = 0, warning = 0, info = 0;
};
Summary summarize(const std::vector<FileResult>& results);

struct TextOptions {
    bool color = false;
};
// Human-readable report: `path:line:col: severity[ID]: message`, the source
// line with a caret under the range, notes and fixes, then a summary line.
std::string render_text(const std::vector<FileResult>& results, const TextOptions& options);
std::string render_text_diagnostic(const std::string& path, const Diagnostic& d, const TextOptions& options);
std::string render_summary(const Summary& s);

// The versioned JSON contract (version 1).
std::string render_json(const std::vector<FileResult>& results);

}  // namespace osplint
