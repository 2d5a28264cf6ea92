// The outline of a file: what its control flow and its program boundaries
// are made of, found without analysing every block.
//
// The analysis engine needs to know, before it walks a program, where the
// program starts and ends, whether it is a subprogram (an RTS anywhere in it
// makes it one), which blocks jump or loop, which sequence names are jumped to,
// and which comments are suppression directives. Those blocks are rare in
// posted programs, and each of them holds one of a few letters: GOTO, DO, RTS
// and program names an O or a T, END and WHILE an E or a W, IF the pair I F, a
// sequence-name reference (`G85 N0207`) an N that does not start its line,
// a directive `osplint:` an O. `outline_file` reads the input in chunks,
// looks for those bytes sixteen at a time, and parses only the lines that hold
// one, with the same front end as the analysis (so nothing is decided twice).
// A CALL or MODIN line (its macro's name holds an O) is passed over unparsed
// when its arguments hold none of those bytes (outline_passes_over).
// An input of many megabytes is cut at line starts into parts, one per core,
// outlined at once and joined (OutlineOptions::parts).
// The lines before the file's first block with content are parsed one by one
// (they decide the first program's name), and so are the lines that follow a
// directive on a comment-only line, up to the block it applies to.
//
// Positions in the outline are line numbers and the byte offsets of line
// starts (the scan counts line breaks as it looks for candidates).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "support/io.h"
#include "syntax/model.h"

namespace osplint {

class FastLineParser;

// A statement that changes the control flow: GOTO, IF, WHILE, DO or END.
struct FlowStatement {
    StmtKind kind = StmtKind::Goto;
    std::string name;  // jump target (GOTO, IF)
    int loop = -1;     // loop number (WHILE, DO, END)
    friend bool operator==(const FlowStatement&, const FlowStatement&) = default;
};

// A block holding flow statements.
struct FlowSite {
    uint32_t line = 0;    // 1-based
    uint32_t offset = 0;  // start of its line
    uint32_t next = 0;    // start of the next line (the end of the input for the last one)
    bool block_delete = false;
    std::vector<FlowStatement> statements;  // in the order written
    friend bool operator==(const FlowSite&, const FlowSite&) = default;
};

struct ProgramOutline {
    uint32_t line = 1;     // its first line
    uint32_t offset = 0;   // start of its first line
    std::string name;      // "OTEST"; empty when the file starts without a name
    ByteRange name_range;
    bool has_rts = false;      // an RTS anywhere in it
    bool has_content = false;  // a block with something the control executes
    std::vector<FlowSite> flow;             // in line order
    std::vector<std::string> references;    // sequence names jumped to or referenced by an N word; sorted, unique
};

// A line holding `osplint:` directive comments.
struct DirectiveSite {
    uint32_t line = 0;    // 1-based
    uint32_t offset = 0;  // start of the line
    std::string text;     // the line without its terminator
    std::vector<ByteRange> comments;  // every comment of the line (absolute offsets)
    size_t program = 0;   // index into FileOutline::programs
    // Start of the line a `disable` applies to: this one when the block has
    // content, else the next block with content (none at the end of the file).
    std::optional<uint32_t> target;
    uint32_t target_line = 0;  // its line number (0: none)
};

struct FileOutline {
    std::vector<ProgramOutline> programs;  // none for an empty input, else at least one
    std::vector<DirectiveSite> directives;
    // Start of the file's first block with content or a program name (the
    // lines up to it are all parsed); none when there is no such block.
    std::optional<uint32_t> first_block;
    uint64_t size = 0;         // bytes read
    uint32_t lines = 0;        // blocks (lines) in the input
    uint64_t lines_parsed = 0; // lines handed to the front end (for tests and benchmarks)
    uint32_t parts = 1;        // parts it was read in (OutlineOptions::parts; for tests)
    std::string error;         // set when the input could not be read (or is too large)
    bool ok() const { return error.empty(); }
    // Where program `i` ends (the next one's start, or the end of the input).
    uint64_t program_end(size_t i) const { return i + 1 < programs.size() ? programs[i + 1].offset : size; }
};

struct OutlineOptions {
    size_t chunk_size = size_t(1) << 20;
    // Only the program names are wanted (a sibling file's names for CALL
    // targets): flow sites and directives are left out.
    bool names_only = false;
    // The input is cut at line starts into this many parts, outlined at once
    // on threads of their own and joined (the outline is the same). 0: as
    // many as the machine has cores, each of at least `min_part_size` bytes;
    // 1: one part. Only a source that can make another reader is cut.
    unsigned parts = 0;
    uint64_t min_part_size = uint64_t(8) << 20;
};

// Outlines what `src` holds. Never throws for bad input; `error` is set when
// the input cannot be read. A part of the input (OutlineOptions::parts) whose
// outline cannot be joined to the one before it (no block with content
// before it yet, or a directive waiting for its target block) makes the
// whole input read again in one part, as does an error in any part.
FileOutline outline_file(ByteSource& src, const OutlineOptions& options = {});

// Whether the bytes [p, e) hold one of the bytes an outlined line must hold
// (see above). `line_start` says p starts a line. Exposed for tests.
bool may_hold_outline_item(const char* p, const char* e, bool line_start);

// Whether a line's text (its terminator left out) holds only blanks and one
// comment or more, closed on the line, none of them a suppression directive:
// the outline passes over such a line without parsing it. Exposed for tests.
bool comments_only(std::string_view text);

// Whether the outline passes over `line` without parsing it: a CALL or
// MODIN alone on its line (no sequence name, no block delete before it)
// whose arguments either hold none of the bytes an outlined item must hold
// or are all `Pname=number` (FastLineParser::plain_call). The outline would
// take nothing from its block. With `last_plain`, the last line plain_call
// passed over (kept there): a line like it (passes_like) is passed over
// without plain_call. Exposed for tests.
bool outline_passes_over(FastLineParser& parser, const LineRef& line, std::string* last_plain = nullptr);

// Whether `text` is `passed`, a line outline_passes_over passed over, but
// for the values of its `name=value` items, each a plain number on both
// lines (FastLineParser::plain_value_end): outline_passes_over passes it over
// too (those values hold none of the bytes an outlined item must hold, and
// plain_call reads them as it read the others). Exposed for tests.
bool passes_like(std::string_view passed, std::string_view text);

}  // namespace osplint
