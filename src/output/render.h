// A whole report of results held in memory (tests, small runs): the report
// writers of writer.h fed file by file.
#pragma once

#include <string>
#include <vector>

#include "osplint/diagnostic.h"
#include "output/writer.h"

namespace osplint {

// The report of `results` in `format`, as `osplint check` writes it (the
// counts are those of the findings given: nothing is folded here).
std::string render_report(const std::vector<FileResult>& results, Format format, const WriterOptions& options = {});

// Feeds results to a sink, file by file: findings, then suppressed findings.
void replay(const FileResult& result, DiagnosticSink& sink);

}  // namespace osplint
