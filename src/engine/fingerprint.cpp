#include "engine/fingerprint.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>

#include <fmt/format.h>

namespace osplint {
namespace {

struct Fnv {
    uint64_t h = 1469598103934665603ull;
    void mix(std::string_view s) {
        for (unsigned char c : s) {
            h ^= c;
            h *= 1099511628211ull;
        }
        h ^= 0xff;
        h *= 1099511628211ull;
    }
};

inline size_t slot_of(uint64_t key, size_t mask) { return static_cast<size_t>(key * 0x9E3779B97F4A7C15ull) & mask; }
// The counter of `key` in sketch row `row`: the high bits of a product with an odd constant of the row.
inline size_t sketch_index(uint64_t key, size_t row) {
    static constexpr uint64_t kMul[OccurrenceCounter::kSketchRows] = {
        0xD6E8FEB86659FD93ull, 0xA0761D6478BD642Full, 0xE7037ED1A0B428DBull, 0x8EBC6AF09C88C6E3ull};
    constexpr unsigned kBits = std::countr_zero(OccurrenceCounter::kSketchWidth);
    return row * OccurrenceCounter::kSketchWidth + static_cast<size_t>((key * kMul[row]) >> (64 - kBits));
}

}  // namespace

std::string fingerprint_text(std::string_view line, uint32_t line_start, const std::vector<Comment>* comments) {
    // The comments are in order: one pass over the line and them.
    size_t k = 0;
    auto in_comment = [&](uint32_t offset) {
        if (!comments) return false;
        while (k < comments->size() && (*comments)[k].range.end <= offset) ++k;
        return k < comments->size() && (*comments)[k].range.contains(offset);
    };
    std::string norm;
    for (uint32_t i = 0; i < line.size(); ++i)
        if (!std::isspace(static_cast<unsigned char>(line[i])) && !in_comment(line_start + i)) norm += line[i];
    if (norm.empty())
        for (char c : line)
            if (!std::isspace(static_cast<unsigned char>(c))) norm += c;
    return norm;
}

uint64_t fingerprint_key(std::string_view rule, std::string_view program, std::string_view block_text) {
    Fnv f;
    f.mix(rule);
    f.mix(program);
    f.mix(block_text);
    return f.h;
}

std::string make_fingerprint(uint64_t key, int occurrence) {
    // FNV-1a 64, printed as hex: stable across platforms and runs.
    Fnv f{key};
    f.mix(std::to_string(occurrence));
    return fmt::format("{:016x}", f.h);
}

std::string make_fingerprint(std::string_view rule, std::string_view program, std::string_view block_text,
                             int occurrence) {
    return make_fingerprint(fingerprint_key(rule, program, block_text), occurrence);
}

bool OccurrenceCounter::insert(uint64_t key) {
    if (key == 0) key = 1;  // 0 marks an empty slot
    if ((used_ + 1) * 2 > slots_.size()) {
        std::vector<uint64_t> old = std::move(slots_);
        slots_.assign(old.empty() ? 1024 : old.size() * 2, 0);
        used_ = 0;
        for (uint64_t k : old)
            if (k) insert(k);
    }
    const size_t mask = slots_.size() - 1;
    for (size_t i = slot_of(key, mask);; i = (i + 1) & mask) {
        if (slots_[i] == key) return false;
        if (slots_[i] == 0) {
            slots_[i] = key;
            ++used_;
            return true;
        }
    }
}


bool OccurrenceCounter::contains(uint64_t key) const {
    if (key == 0) key = 1;
    if (slots_.empty()) return false;
    const size_t mask = slots_.size() - 1;
    for (size_t i = slot_of(key, mask);; i = (i + 1) & mask) {
        if (slots_[i] == key) return true;
        if (slots_[i] == 0) return false;
    }
}

void OccurrenceCounter::to_sketch() {
    sketch_.assign(kSketchRows * kSketchWidth, 0);
    for (uint64_t k : slots_) {
        if (!k) continue;
        const auto it = repeats_.find(k);
        const uint32_t n = it == repeats_.end() ? 1 : static_cast<uint32_t>(it->second);
        for (size_t r = 0; r < kSketchRows; ++r) sketch_[sketch_index(k, r)] += n;
    }
    std::vector<uint64_t>().swap(slots_);
    used_ = 0;
    std::unordered_map<uint64_t, int>().swap(repeats_);
}

int OccurrenceCounter::sketch_next(uint64_t key) {
    if (key == 0) key = 1;  // as in the table
    uint32_t least = UINT32_MAX;
    for (size_t r = 0; r < kSketchRows; ++r) least = std::min(least, ++sketch_[sketch_index(key, r)]);
    return static_cast<int>(std::min<uint32_t>(least, INT32_MAX));
}

size_t OccurrenceCounter::bytes() const {
    return slots_.capacity() * sizeof(uint64_t) + sketch_.capacity() * sizeof(uint32_t) +
           repeats_.size() * (sizeof(uint64_t) + sizeof(int) + 2 * sizeof(void*)) +
           repeats_.bucket_count() * sizeof(void*);
}

bool OccurrenceCounter::same_counts(const OccurrenceCounter& o) const {
    if (sketched() != o.sketched()) return false;
    if (sketched()) return sketch_ == o.sketch_;
    if (used_ != o.used_ || repeats_ != o.repeats_) return false;
    if (used_ == 0) return true;
    for (uint64_t key : slots_)
        if (key && !o.contains(key)) return false;
    return true;
}

int OccurrenceCounter::next(uint64_t key) {
    if (!sketched() && used_ >= exact_keys_ && !contains(key)) to_sketch();
    if (sketched()) return sketch_next(key);
    if (insert(key)) return 1;
    int& n = repeats_[key];
    if (n == 0) n = 1;
    return ++n;
}

int OccurrenceCounter::next(std::string_view rule, std::string_view program, std::string_view block_text) {
    return next(fingerprint_key(rule, program, block_text));
}

}  // namespace osplint
