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

}  // namespace osplint::ts_detail
