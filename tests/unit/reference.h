// The reference analysis the engine is tested against (differential tests,
// the fuzzer): the simplest thing that can be right, with nothing streamed.
//
//   * the whole file parsed by the tree-sitter front end (the grammar is the
//     definition of the syntax);
//   * the outline read off the parsed blocks;
//   * per program, the modal state at every block to a fixpoint of a plain
//     worklist over the flow graph (engine/flow.h's edges), the states of
//     every block kept;
//   * every rule shown every block (no plain-move shortcut), in order;
//   * the findings sorted, then the suppression directives applied.
//
// It shares with the engine only what defines the language: the transfer
// function, the edges of a block, the rules, the directives' meaning.
#pragma once

#include <string>
#include <string_view>

#include "api/check.h"
#include "osplint/diagnostic.h"
#include "semantics/config.h"
#include "syntax/outline.h"
#include "syntax/source.h"

namespace osplint::testing {

// The outline of a parsed file, read off its blocks.
FileOutline reference_outline(const ProgramFile& file);

// The findings of `text`, as the engine must find them (options: known
// programs and the rule selection are honoured; the rest is the engine's).
FileResult reference_check(const std::string& path, std::string_view text, const Config& config,
                           const AnalysisOptions& options = {});

// Every field of a check result, one item per line.
std::string dump_result(const FileResult& r);
// Every field of an outline, one item per line.
std::string dump_outline(const FileOutline& o);

}  // namespace osplint::testing
