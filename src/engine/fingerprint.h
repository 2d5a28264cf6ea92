// Fingerprints: the identity of a finding that survives edits elsewhere in
// the file (baselines, SARIF partialFingerprints). Made of the rule, the
// program's name, the text of the finding's block with blanks folded and
// comments left out, and the occurrence of that combination in the file —
// never the line number.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "syntax/model.h"

namespace osplint {

// The text that identifies a finding's block: the line with blanks folded and
// comments (`comments`, absolute offsets; may be null) left out, so that
// neither a shifted line nor a comment added to the block changes it. A
// comment-only line keeps its comments.
std::string fingerprint_text(std::string_view line, uint32_t line_start, const std::vector<Comment>* comments);
// rule + program + block text + occurrence, as 16 hex digits (FNV-1a 64).
std::string make_fingerprint(std::string_view rule, std::string_view program, std::string_view block_text,
                             int occurrence);
// The same in two steps, for many findings of one rule on one block: the hash
// of rule + program + block text (once), then the fingerprint of an occurrence.
uint64_t fingerprint_key(std::string_view rule, std::string_view program, std::string_view block_text);
std::string make_fingerprint(uint64_t key, int occurrence);

// Counts the occurrences of (rule, program, block text) in one file. Keeps a
// 64-bit hash of each distinct combination in an open-addressing table (8 to
// 16 bytes each), and a count only for the combinations seen more than once.
// Past `exact_keys` distinct combinations (kExactKeys: about a million, 16 MB
// of table), it counts in a sketch of fixed size instead (kSketchRows rows of
// kSketchWidth counters, 8 MB; the table is freed), so that memory stops
// growing with the findings: each combination's occurrence is then the least
// of its counters. It stays unique (every occurrence of a combination raises
// all its counters, so their least) and the same for the same file, but a
// combination that shares its counters with others starts above 1, and a
// finding added or removed before it may change it.
class OccurrenceCounter {
public:
    static constexpr size_t kExactKeys = size_t(1) << 20;
    static constexpr size_t kSketchRows = 4;
    static constexpr size_t kSketchWidth = size_t(1) << 19;
    explicit OccurrenceCounter(size_t exact_keys = kExactKeys) : exact_keys_(exact_keys) {}

    // The 1-based occurrence of this combination, counting this one.
    int next(std::string_view rule, std::string_view program, std::string_view block_text);
    // The same by fingerprint_key.
    int next(uint64_t key);
    // Whether `o` counted the same keys as often (in whatever order).
    bool same_counts(const OccurrenceCounter& o) const;
    void clear() {
        slots_.clear();
        used_ = 0;
        repeats_.clear();
        sketch_.clear();
    }
    // Whether it counts in the sketch, and the bytes its tables hold.
    bool sketched() const { return !sketch_.empty(); }
    size_t bytes() const;

private:
    bool insert(uint64_t key);  // false when the key was there already
    bool contains(uint64_t key) const;
    void to_sketch();
    int sketch_next(uint64_t key);
    size_t exact_keys_;
    std::vector<uint64_t> slots_;  // 0: empty
    size_t used_ = 0;
    std::unordered_map<uint64_t, int> repeats_;
    std::vector<uint32_t> sketch_;  // empty: counting exactly
};

}  // namespace osplint
