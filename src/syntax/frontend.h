// Front ends: turn source text into the program model.
//
// `parse_program_file` uses the tree-sitter grammar (grammar/) and is the
// reference definition of the syntax. Every syntax problem becomes a
// SyntaxError on the block where it occurs (rule OSP001 reports them), so a
// file is never skipped silently.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "syntax/source.h"

namespace osplint {

// A line whose parse has a syntax error is parsed again on its own (as
// parse_line_tree_sitter does): error recovery then depends on that line
// alone, not on its neighbours, and the streaming front end gives the same
// block for it.
ProgramFile parse_program_file(std::string path, std::string text);

// Value of a decimal literal as the grammar lexes it (`12`, `3.`, `.5`, `00`),
// correctly rounded (std::from_chars). nullopt when it is too large for a
// double (some 309 digits before the point): such a literal is a syntax error
// (number_too_large_message) and has no value, so that no infinity reaches the
// analysis. Too many zeros after the point give 0. Shared by both front ends.
std::optional<double> decimal_literal_value(std::string_view digits);
// The message of the syntax error on a literal too large for a double (the
// literal shortened when it is long).
std::string number_too_large_message(std::string_view literal);
// The same without parsing error lines again (for a text of one line).
ProgramFile parse_program_file_once(std::string path, std::string text);

// Splits blocks into programs (an `O` name starts a new one). Shared by the
// front ends so that both agree on program boundaries.
std::vector<Program> split_programs(const std::vector<Block>& blocks);

}  // namespace osplint
