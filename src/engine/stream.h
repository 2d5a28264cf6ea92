// The streaming check of a file: the batch path of `osplint check`.
//
// The file is read in chunks and never held whole: each line is parsed into a
// Block (analyzer/frontend_fast.h), fed through the modal-state transfer
// function (resolve_call / apply_block) and handed to every rule at once, so
// only the current block and modal state are kept. The result is the one
// check_text gives for the same text (same diagnostics, positions,
// fingerprints and suppressions); tests/unit/test_fast_frontend.cpp compares
// the two.
//
// A program with jumps or loops (GOTO, IF, WHILE, DO, END) needs the
// control-flow fixpoint, and one whose rules ask whether a sequence name exists
// (`G85 N0207`) needs all its sequence names: that program's blocks (only that
// program's) are read again into memory and analysed as analyze() does. The same happens when an RTS turns
// the first program of a main file into a subprogram after its start, and
// when a program name follows the comment lines that open a file.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "engine/analyzer.h"
#include "semantics/config.h"
#include "osplint/osplint.h"

namespace osplint {

// What the streaming check did (for tests and the benchmark).
struct StreamStats {
    uint64_t bytes = 0;              // size of the input
    uint64_t lines_parsed = 0;       // lines parsed, counting lines read again
    uint64_t fast_lines = 0;         // ... by the hand-written parser
    uint64_t fallback_lines = 0;     // ... by the tree-sitter front end
    uint64_t programs = 0;           // programs analysed
    uint64_t buffered_programs = 0;  // ... of which with the control-flow fixpoint
    uint64_t restarts = 0;           // programs read again
    uint64_t max_buffered_blocks = 0;
    uint64_t source_loads = 0;       // a rule asked for the whole source text (see RuleContext::source)
};

struct StreamOptions {
    size_t chunk_size = size_t(1) << 20;  // bytes read at a time
    StreamStats* stats = nullptr;         // filled when set
};

// check_file / check_text with the streaming front end and analysis.
// `options.keep_states` is not supported here (the trace and the language
// server use check_text's path).
FileResult check_file_fast(const std::string& path, const Config& config, const AnalysisOptions& options = {},
                           const StreamOptions& stream = {});
FileResult check_text_fast(const std::string& path, std::string_view text, const Config& config,
                           const AnalysisOptions& options = {}, const StreamOptions& stream = {});
// Checks what can be read from `fd` (reported under `path`). A regular file is
// read in place; anything else (a pipe, a terminal) is copied as it is read to
// an unlinked temporary file, which is what the check reads back when a
// program must be read again.
FileResult check_fd_fast(int fd, const std::string& path, const Config& config, const AnalysisOptions& options = {},
                         const StreamOptions& stream = {});

// Copies everything readable from `fd` to an unlinked temporary file and
// returns a descriptor of it positioned at its start (-1 and `error` set on
// failure). For stdin: its program names can then be collected and the text
// checked without holding it in memory.
int spool_to_temporary_file(int fd, std::string& error);

// collect_program_names (analyzer.h) over a file or descriptor, read in chunks.
// Returns false when it cannot be read.
bool collect_program_names_file(const std::string& path, ProgramNames& out);
bool collect_program_names_fd(int fd, ProgramNames& out);

// Every field of a check result, one item per line (for differential tests).
std::string dump_result(const FileResult& r);

}  // namespace osplint
