#include "output/render.h"

#include <sstream>

#include "output/pipeline.h"

namespace osplint {

void replay(const FileResult& r, DiagnosticSink& sink) {
    sink.begin_file(r.path);
    for (const auto& d : r.diagnostics) sink.diagnostic(Diagnostic(d));
    for (const auto& s : r.suppressed) sink.suppressed(SuppressedDiagnostic(s));
    sink.end_file(r.path, r.io_error);
}

std::string render_report(const std::vector<FileResult>& results, Format format, const WriterOptions& options) {
    std::ostringstream out;
    auto writer = make_writer(format, out, options);
    Counts counts;
    CountingSink count(*writer, counts);
    for (const auto& r : results) replay(r, count);
    writer->finish(counts);
    return out.str();
}

}  // namespace osplint
