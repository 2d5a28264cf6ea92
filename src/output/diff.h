// A unified diff of a program and the edits of its fixes (`check --diff`):
// what `patch -p1` or `git apply` applies to give what `--fix` writes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "api/fix.h"
#include "support/io.h"

namespace osplint {

struct DiffStats {
    uint64_t hunks = 0;
    uint64_t removed = 0;  // lines
    uint64_t added = 0;
};

// Writes the diff of `original` and `original` with `edits` (sorted,
// non-overlapping) to `put`, with `context` lines around each change. The
// header names the file `a/PATH` and `b/PATH` (PATH as given; an absolute
// path is named as it is). Reads the original once, as a stream. False with
// `error` set when it cannot be read.
bool write_unified_diff(ByteSource& original, const std::vector<Edit>& edits, const std::string& path,
                        const ByteSink& put, std::string& error, DiffStats* stats = nullptr, unsigned context = 3);

}  // namespace osplint
