#include "engine/fold.h"

#include <fmt/format.h>

namespace osplint {
namespace {

constexpr uint64_t kFnvBasis = 1469598103934665603ull;
constexpr uint64_t kFnvPrime = 1099511628211ull;

uint64_t mix(uint64_t h, unsigned char c) { return (h ^ c) * kFnvPrime; }

uint64_t rule_hash(std::string_view rule) {
    uint64_t h = kFnvBasis;
    for (char c : rule) h = mix(h, static_cast<unsigned char>(c));
    return mix(h, 0x1f);
}

}  // namespace

uint64_t message_kind(std::string_view rule, std::string_view m) {
    uint64_t h = rule_hash(rule);
    auto digit = [&](size_t i) { return i < m.size() && m[i] >= '0' && m[i] <= '9'; };
    bool in_number = false;
    for (size_t i = 0; i < m.size(); ++i) {
        const char c = m[i];
        // A sign belongs to the number it starts.
        const bool part = digit(i) || (in_number && c == '.') || (!in_number && (c == '-' || c == '+') && digit(i + 1));
        if (part && !in_number) h = mix(h, '#');
        if (!part) h = mix(h, static_cast<unsigned char>(c));
        in_number = part;
    }
    return h;
}

uint64_t keyed_kind(std::string_view rule, std::string_view key) {
    uint64_t h = mix(rule_hash(rule), 0x1e);  // apart from every message kind
    for (char c : key) h = mix(h, static_cast<unsigned char>(c));
    return h;
}

Folder::Verdict Folder::next_kind(uint64_t kind, ByteRange range) {
    if (keep_ == 0) return Verdict::Show;
    if (last_ == kNoSlot || last_kind_ != kind) {
        auto it = index_.find(kind);
        if (it == index_.end()) {
            if (kinds_.size() >= kMaxKinds) return Verdict::Show;
            it = index_.emplace(kind, static_cast<uint32_t>(kinds_.size())).first;
            kinds_.emplace_back();
        }
        last_kind_ = kind;
        last_ = it->second;
    }
    Kind& k = kinds_[last_];
    if (k.shown < keep_) {
        ++k.shown;
        return Verdict::Show;
    }
    if (!k.holding) {
        k.holding = true;
        order_.push_back(kind);
        k.last = range;
        return Verdict::Hold;
    }
    ++k.counted;
    ++folded_;
    k.last = range;
    return Verdict::Count;
}

void Folder::hold(uint64_t kind, Diagnostic&& d) { kinds_[index_.at(kind)].held = std::move(d); }

void Folder::annotate(Diagnostic& d, uint64_t counted, const SourceRange& last) {
    d.folded = counted;
    d.folded_last = last;
    d.notes.push_back(
        {fmt::format("and {} more like this in this file, the last on line {} (folded into this one)", counted,
                     last.start.line),
         last});
}

}  // namespace osplint
