#include "lsp/document.h"

#include "api/check.h"

namespace osplint::lsp {
namespace {

class StopAt final : public BlockObserver {
public:
    explicit StopAt(uint32_t line) : line_(line) {}
    bool block(const BlockView& view, const LineRef& line) override {
        if (line.line < line_) return true;
        if (line.line == line_) found = record_block(view, line);
        return false;
    }
    std::optional<BlockRecord> found;

private:
    uint32_t line_;
};

}  // namespace

std::optional<BlockRecord> block_at(const DocumentModel& doc, const Config& config, const ProgramNames* known,
                                    SubprogramSummaries* summaries, uint32_t line) {
    StopAt stop(line);
    AnalysisOptions options;
    options.known_programs = known;
    options.summaries = summaries;
    options.observer = &stop;
    options.run_rules = false;
    MemorySource src(doc.text());
    DiscardFindings sink;  // hover runs no rules; the directives' own findings are dropped too
    check_source(doc.path, src, config, options, sink);
    return std::move(stop.found);
}

}  // namespace osplint::lsp
