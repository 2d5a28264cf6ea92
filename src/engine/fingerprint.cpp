#include "engine/fingerprint.h"

#include <cctype>

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
    for (size_t i = static_cast<size_t>(key * 0x9E3779B97F4A7C15ull) & mask;; i = (i + 1) & mask) {
        if (slots_[i] == key) return false;
        if (slots_[i] == 0) {
            slots_[i] = key;
            ++used_;
            return true;
        }
    }
}

bool OccurrenceCounter::same_counts(const OccurrenceCounter& o) const {
    if (used_ != o.used_ || repeats_ != o.repeats_) return false;
    if (used_ == 0) return true;
    const size_t mask = o.slots_.size() - 1;
    for (uint64_t key : slots_) {
        if (!key) continue;
        for (size_t i = static_cast<size_t>(key * 0x9E3779B97F4A7C15ull) & mask;; i = (i + 1) & mask) {
            if (o.slots_[i] == key) break;
            if (o.slots_[i] == 0) return false;
        }
    }
    return true;
}

int OccurrenceCounter::next(uint64_t key) {
    if (insert(key)) return 1;
    int& n = repeats_[key];
    if (n == 0) n = 1;
    return ++n;
}

int OccurrenceCounter::next(std::string_view rule, std::string_view program, std::string_view block_text) {
    return next(fingerprint_key(rule, program, block_text));
}

}  // namespace osplint
