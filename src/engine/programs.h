// Program names defined outside the file being checked: the subprogram files
// (.SSB/.SUB/.LIB/.MSB) of a directory, which the control searches for CALL
// targets of a main program.
#pragma once

#include <filesystem>

#include "engine/analyzer.h"

namespace osplint {

bool is_subprogram_file(const std::filesystem::path& p);
// Adds the program names of every subprogram file in `dir` (not recursive).
void collect_directory_program_names(const std::filesystem::path& dir, ProgramNames& out);

}  // namespace osplint
