// The language server's model of one open document: its text with a line
// index and its outline — about one byte per document byte and four per line.
// Blocks are not kept: a request that needs one (hover) parses its line
// again, and walks the document with the engine up to it for its modal state.
#pragma once

#include <optional>
#include <string>

#include "engine/record.h"
#include "engine/summaries.h"
#include "engine/workspace.h"
#include "semantics/config.h"
#include "syntax/outline.h"
#include "syntax/source.h"

namespace osplint::lsp {

class DocumentModel {
public:
    std::string path;  // the file path, or the URI of a document without one
    FileOutline outline;

    void set_text(std::string text) {
        text_ = std::move(text);
        source_.reset();
    }
    const std::string& text() const { return source_ ? source_->text() : text_; }
    // The text with its line index, made when a request first needs it (an
    // analysis does not).
    const SourceText& source() const {
        if (!source_) source_.emplace(std::move(text_));
        return *source_;
    }

private:
    mutable std::string text_;
    mutable std::optional<SourceText> source_;
};

// The block of a 1-based line with the modal state before and after it: the
// engine walks the document (without the rules) and stops there.
std::optional<BlockRecord> block_at(const DocumentModel& doc, const Config& config, const ProgramNames* known,
                                    SubprogramSummaries* summaries, uint32_t line);

}  // namespace osplint::lsp
