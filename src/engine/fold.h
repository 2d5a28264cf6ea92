// Folding: the findings of one kind beyond the first few of a file shown as one.
//
// A wrong work offset can make every move of a posted program break the
// travel limits: a million findings that differ only in their numbers. Of each
// kind (a rule and its message with every number as '#', or a key the rule
// gives), a file shows the first `keep`; the next one is held as the
// representative of the others, which are only counted; at the end of the
// file the representative comes with their count and the place of the last.
//
// The engine folds as rules report (a rule that reports in bulk asks
// RuleContext::folded first and skips building findings that would only be
// counted); the output pipeline folds with the same Folder when a baseline
// must see every finding first.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "osplint/diagnostic.h"

namespace osplint {

// The kind of a finding: a hash of its rule and of its message with each
// number (a run of digits and points, with its sign) read as one '#'.
uint64_t message_kind(std::string_view rule, std::string_view message);
// The kind of a finding from a key its rule chooses.
uint64_t keyed_kind(std::string_view rule, std::string_view key);

class Folder {
public:
    explicit Folder(uint64_t keep) : keep_(keep) {}

    enum class Verdict {
        Show,   // pass it on now
        Hold,   // the representative of the folded ones: give it to hold()
        Count,  // only counted (its range noted as the last so far)
    };
    // What to do with the next finding of `kind`, starting at `range`.
    Verdict next(uint64_t kind, ByteRange range) {
        // The same kind as the last one, already folding: only counted.
        if (last_ != kNoSlot && last_kind_ == kind && kinds_[last_].holding) {
            Kind& k = kinds_[last_];
            ++k.counted;
            ++folded_;
            k.last = range;
            return Verdict::Count;
        }
        return next_kind(kind, range);
    }
    // Keeps the representative of `kind` (after a Hold verdict).
    void hold(uint64_t kind, Diagnostic&& d);
    // The representatives of the file, in the order they were held, each with
    // the count of the findings it stands for, the place of the last (resolved
    // by `resolve(kind, byte range)`) and a note saying so. Empties the folder
    // for the next file.
    template <class Resolve>
    std::vector<Diagnostic> finish(Resolve&& resolve) {
        std::vector<Diagnostic> out;
        for (uint64_t kind : order_) {
            Kind& k = kinds_[index_.at(kind)];
            if (!k.held) continue;
            Diagnostic d = std::move(*k.held);
            if (k.counted) annotate(d, k.counted, resolve(kind, k.last));
            out.push_back(std::move(d));
        }
        kinds_.clear();
        index_.clear();
        order_.clear();
        last_ = kNoSlot;
        return out;
    }
    // Findings folded into representatives so far (not shown on their own).
    uint64_t folded() const { return folded_; }
    bool enabled() const { return keep_ > 0; }

    static constexpr size_t kMaxKinds = 4096;  // kinds followed per file; others are never folded

private:
    struct Kind {
        uint64_t shown = 0;
        std::optional<Diagnostic> held;
        bool holding = false;  // a Hold verdict was given
        uint64_t counted = 0;
        ByteRange last;
    };
    static void annotate(Diagnostic& d, uint64_t counted, const SourceRange& last);
    Verdict next_kind(uint64_t kind, ByteRange range);

    uint64_t keep_;
    std::vector<Kind> kinds_;                       // in the order first met
    std::unordered_map<uint64_t, uint32_t> index_;  // kind -> its place in kinds_
    std::vector<uint64_t> order_;
    // The kind of the last call of next() and its place: a rule that reports
    // on every move reports the same kind again and again.
    static constexpr uint32_t kNoSlot = UINT32_MAX;
    uint64_t last_kind_ = 0;
    uint32_t last_ = kNoSlot;
    uint64_t folded_ = 0;
};

}  // namespace osplint
