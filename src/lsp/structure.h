// Language server: the structure of a document. Folding ranges (programs,
// WHILE/DO ... END loops as the engine pairs them, MODIN ... MODOUT, runs of
// comment lines), semantic tokens (what each name and word is), the symbols
// of a document, and the programs of the open documents and of the workspace
// folder.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lsp/document.h"
#include "lsp/text.h"

namespace osplint::lsp {

// --- folding ---------------------------------------------------------------
json folding_ranges(const DocumentModel& doc);

// --- semantic tokens -------------------------------------------------------
// The legend, in the order of the indices the tokens use.
inline constexpr std::string_view kTokenTypes[] = {
    "function",   // a program name, a CALL / MODIN target
    "parameter",  // an argument of a CALL / MODIN (`PX=`)
    "label",      // a sequence name, a GOTO / IF target
    "variable",   // VC1, locals, system variables
    "comment",    // ( ... )
    "keyword",    // CALL, MODIN, MODOUT, GOTO, IF, WHILE, DO, END, RTS, ...
    "macro",      // a G or M code
};
inline constexpr std::string_view kTokenModifiers[] = {"declaration"};
json semantic_tokens_legend();
// The tokens of lines [first, last] (1-based; 0 = to the end), encoded as
// the LSP relative integers with columns in `enc`.
json semantic_tokens(const DocumentModel& doc, Encoding enc, uint32_t first = 1, uint32_t last = 0);

// --- document symbols ------------------------------------------------------
// Programs, with their sequence names (at most kMaxSequenceSymbols per program).
inline constexpr size_t kMaxSequenceSymbols = 5000;
json document_symbols(const DocumentModel& doc, Encoding enc);

// --- workspace symbols -----------------------------------------------------
struct SymbolSource {
    std::string uri;
    std::shared_ptr<const DocumentModel> doc;
};
// The program files (.MIN .SSB .SUB .SDF .LIB .NC .MSB, any case) under `dir`
// (at most `max_files`, each at most 64 MiB), except the paths in `skip`,
// read with their outlines (program names only).
std::vector<SymbolSource> folder_documents(const std::filesystem::path& dir, const std::vector<std::string>& skip,
                                           size_t max_files = 2000);
// The programs whose name contains `query` (any case), as SymbolInformation.
inline constexpr size_t kMaxWorkspaceSymbols = 1000;
json workspace_symbols(const std::vector<SymbolSource>& sources, std::string_view query, Encoding enc);

}  // namespace osplint::lsp
