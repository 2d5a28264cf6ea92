// Language server: what the requests answer, computed from the program model,
// the analysis and the catalog. Pure functions of their inputs (no server
// state, no I/O), so each is tested on its own.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/record.h"
#include "engine/workspace.h"
#include "lsp/document.h"
#include "lsp/text.h"
#include "semantics/config.h"

namespace osplint::lsp {

inline constexpr std::string_view kSource = "osplint";
inline constexpr std::string_view kRuleDocBase = "https://github.com/osplint/osplint/blob/main/docs/rules/";

// An LSP MarkupContent of Markdown text.
json markdown(std::string text);

// --- diagnostics ---------------------------------------------------------
// One LSP Diagnostic: range, severity, code, codeDescription, source,
// message, relatedInformation (notes with a range), data {version, fixes}.
json to_lsp_diagnostic(const Diagnostic& d, const std::string& uri, Encoding enc, int64_t version);
// The text of findings as to_lsp_diagnostic writes them, up to and after
// their version, by what they say and where (lines and columns, not bytes):
// kept from one publication of a document to the next, whose findings are
// mostly the same ones.
using DiagnosticTexts = std::unordered_map<std::string, std::pair<std::string, std::string>>;
// The publishDiagnostics notification of `diags` (uri, diagnostics, and the
// version when it is not negative), as the text MessageWriter::send would
// write; `texts` is left with those of `diags`.
std::string publish_text(const std::string& uri, int64_t version, const std::vector<Diagnostic>& diags, Encoding enc,
                         DiagnosticTexts& texts);

// --- hover ---------------------------------------------------------------
// `at` is the block of the hovered line with its modal states (lsp/document.h:
// block_at), or null when it is not known. Returns null when there is nothing to say.
json hover(const DocumentModel& doc, const BlockRecord* at, const Config& config, uint32_t offset, Encoding enc);

// Meaning of a common G or M code ("G81", "M52"), or nullopt.
std::optional<std::string_view> code_meaning(std::string_view code);
// The Markdown documentation of one macro argument; `plane` 17/18/19 or 0 (unknown).
std::string argument_doc(const MacroSpec& spec, const ArgSpec& arg, int plane, const ModalState* state);

// --- completion (completion.cpp) ----------------------------------------
// `line` is the whole line, `column` the cursor as a byte offset in it;
// `programs` are subprogram names defined in the file and beside it.
json completion(std::string_view line, uint32_t column, const Config& config, const ProgramNames& programs);

// --- code actions --------------------------------------------------------
// Quick fixes from the fixes carried in the diagnostics' data, and a
// suppression comment per rule. `text` and `version` are the document now.
json code_actions(const std::string& uri, const json& params, const SourceText& text, int64_t version, Encoding enc);

}  // namespace osplint::lsp
