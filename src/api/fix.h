// Fixes: choosing the ones applied together, composing rounds of them, and
// writing the fixed program. `osplint check --fix` and `--diff` use these:
//
//   check (every finding, no folding) -> choose the fixes that do not touch
//   each other -> apply them to a temporary copy -> check the copy -> choose
//   again -> ... until no fix is left (at most kMaxFixRounds rounds)
//
// The result is one list of edits against the original bytes, which is
// written over the file atomically (--fix), or printed as a diff (--diff).
// The program is never held whole: the copies are temporary files and the
// edits are read against the original as a stream.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "api/check.h"
#include "osplint/diagnostic.h"
#include "support/io.h"

namespace osplint {

// Replaces the bytes [begin, end) of a text by `text` (an insertion when
// begin == end).
struct Edit {
    uint32_t begin = 0;
    uint32_t end = 0;
    std::string text;
    friend bool operator==(const Edit&, const Edit&) = default;
};

// Collects one file's findings and the fixes among them that may be applied:
// the safe ones, and the unsafe ones too when `unsafe` is set. A finding's
// first applicable fix stands for it.
class FixCollector final : public DiagnosticSink {
public:
    explicit FixCollector(bool unsafe) : unsafe_(unsafe) {}
    void diagnostic(Diagnostic&& d) override;
    void end_file(const std::string& path, const std::string& io_error) override;

    // The fixes that can be applied together: in the order of their first
    // edit, a fix is taken when none of its edits overlaps an edit already
    // taken (two insertions at one place overlap; identical fixes count
    // once). The others wait for the next round. Sorted, non-overlapping.
    std::vector<Edit> choose(uint64_t& chosen, uint64_t& waiting) const;

    uint64_t syntax_errors() const { return syntax_errors_; }
    uint32_t first_syntax_error_line() const { return first_syntax_line_; }
    uint64_t unsafe_left() const { return unsafe_left_; }  // unsafe fixes not taken (without `unsafe`)
    const std::string& io_error() const { return io_error_; }

private:
    bool unsafe_;
    std::vector<std::vector<Edit>> fixes_;
    uint64_t syntax_errors_ = 0;
    uint32_t first_syntax_line_ = 0;
    uint64_t unsafe_left_ = 0;
    std::string io_error_;
};

// The edits of `original` that make the same text as applying `earlier` to
// it and then `later` (edits of that result). Both lists sorted and
// non-overlapping; so is the result. Reads the original bytes that lie
// between merged edits; false with `error` set when it cannot.
bool compose_edits(ByteSource& original, const std::vector<Edit>& earlier, const std::vector<Edit>& later,
                   std::vector<Edit>& out, std::string& error);

// Hands `original` with `edits` applied to `put`, in pieces. False with
// `error` set when the original cannot be read (or `put` returns false).
using ByteSink = std::function<bool(std::string_view)>;
bool apply_edits(ByteSource& original, const std::vector<Edit>& edits, const ByteSink& put, std::string& error);

// Writes `original` with `edits` applied over the file `target`, atomically
// (write_file_atomically), unless that file is no longer the one that was
// read, whose stamp is `read`: it changed while it was being checked, or it
// was replaced. False with `error` set then ("it changed while it was being
// checked"), and the file is left as it is.
bool write_fixes(const std::string& target, const FileStamp& read, ByteSource& original,
                 const std::vector<Edit>& edits, std::string& error);

inline constexpr unsigned kMaxFixRounds = 10;

// What fixing one program comes to.
struct FixPlan {
    std::vector<Edit> edits;  // against the original bytes: empty when nothing is to change
    uint64_t fixes = 0;       // fixes applied, over all rounds
    unsigned rounds = 0;
    // Set when the program is left as it is, and why (it could not be read,
    // it has syntax errors, a fix would break its syntax, the fixes did not
    // settle). `edits` is then empty.
    std::string refused;
    bool failed = false;      // `refused` is an error of osplint or of the input, not a state of the program
};

// Checks `original` (every finding, nothing folded), applies the fixes that
// go together, checks the result again, and so on until nothing more is to
// fix. A program with syntax errors (OSP001) is not fixed: what a fix would
// touch cannot be trusted. `unsafe` applies the unsafe fixes too.
FixPlan plan_fixes(const std::string& path, ByteSource& original, const Config& config,
                   const AnalysisOptions& options, bool unsafe);

}  // namespace osplint
