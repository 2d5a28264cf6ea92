// Where a line stops being valid (the tree-sitter front end's own reading of
// a line, frontend_ts_grammar.h lists the files).
#pragma once

#include <cstddef>
#include <string_view>

namespace osplint::ts_detail {

// Tree-sitter tells whether a line has a syntax error; its recovery does not
// tell where the text stopped making sense. This reads the line again with
// the grammar's rules (grammar/grammar.js, grammar/src/scanner.c) and returns
// the offset in `line` of the first character that cannot continue the block
// as written: stray or unknown characters, the token where something else is
// required, the opening `'` of an unclosed string, or the end of the line
// when it ends while something is still required. Blanks never carry the
// error. npos when the whole line is valid. It is used only to place the
// first error of a line that tree-sitter rejected.
std::size_t first_line_error(std::string_view line);

// How much of a line tree-sitter is given. Its runtime fails on brackets
// nested some 65,000 deep, and its error recovery does work that grows with
// the square of the tokens it skips (a run of 30,000 `]` takes a minute).
// So a line whose expressions nest deeper than kMaxExprDepth is not parsed
// at all (`too_deep`: where the expression too deep starts), and a line is
// read at most kMaxErrorTail bytes past its first error (`cut`: the bytes
// from there on are read as blanks). npos: no bound applies.
inline constexpr std::size_t kMaxErrorTail = 64;
struct LineBound {
    std::size_t too_deep = std::string_view::npos;
    std::size_t cut = std::string_view::npos;
};
LineBound bound_line(std::string_view line);

}  // namespace osplint::ts_detail
