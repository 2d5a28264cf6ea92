#include "output/pipeline.h"

#include <fmt/format.h>

namespace osplint {

uint64_t FoldingSink::kind_of(const Diagnostic& d) {
    // FNV-1a over the rule, a separator and the message with each number (a
    // run of digits and points, with its sign) read as one '#'.
    uint64_t h = 1469598103934665603ull;
    auto mix = [&](unsigned char c) {
        h ^= c;
        h *= 1099511628211ull;
    };
    for (char c : d.rule) mix(static_cast<unsigned char>(c));
    mix(0x1f);
    const std::string& m = d.message;
    auto digit = [&](size_t i) { return i < m.size() && m[i] >= '0' && m[i] <= '9'; };
    bool in_number = false;
    for (size_t i = 0; i < m.size(); ++i) {
        const char c = m[i];
        // A sign belongs to the number it starts.
        const bool part = digit(i) || (in_number && c == '.') || (!in_number && (c == '-' || c == '+') && digit(i + 1));
        if (part && !in_number) mix('#');
        if (!part) mix(static_cast<unsigned char>(c));
        in_number = part;
    }
    return h;
}

void FoldingSink::begin_file(const std::string& path) {
    kinds_.clear();
    order_.clear();
    next_.begin_file(path);
}

void FoldingSink::diagnostic(Diagnostic&& d) {
    if (keep_ == 0) {
        next_.diagnostic(std::move(d));
        return;
    }
    const uint64_t key = kind_of(d);
    auto it = kinds_.find(key);
    if (it == kinds_.end()) {
        if (kinds_.size() >= kMaxKinds) {
            next_.diagnostic(std::move(d));
            return;
        }
        it = kinds_.emplace(key, Kind{}).first;
    }
    Kind& k = it->second;
    if (k.shown < keep_) {
        ++k.shown;
        next_.diagnostic(std::move(d));
        return;
    }
    if (!k.first) {
        order_.push_back(it->first);
        k.first = std::move(d);
        k.last = k.first->range;
    } else {
        k.last = d.range;
    }
    ++k.folded;
}

void FoldingSink::end_file(const std::string& path, const std::string& io_error) {
    for (const uint64_t key : order_) {
        Kind& k = kinds_[key];
        Diagnostic d = std::move(*k.first);
        if (k.folded > 1) {
            d.folded = k.folded - 1;
            d.folded_last = k.last;
            counts_.folded += d.folded;
            d.notes.push_back({fmt::format("and {} more like this in this file, the last on line {} (shown as one; "
                                           "--fold 0 reports each)",
                                           d.folded, k.last.start.line),
                               k.last});
        }
        next_.diagnostic(std::move(d));
    }
    kinds_.clear();
    order_.clear();
    next_.end_file(path, io_error);
}

void LimitSink::begin_file(const std::string& path) {
    shown_ = omitted_ = omitted_items_ = 0;
    first_omitted_.reset();
    next_.begin_file(path);
}

void LimitSink::diagnostic(Diagnostic&& d) {
    if (max_ == 0 || shown_ < max_) {
        ++shown_;
        next_.diagnostic(std::move(d));
        return;
    }
    ++omitted_items_;
    omitted_ += 1 + d.folded;
    if (!first_omitted_) first_omitted_ = std::move(d);
    else last_omitted_ = d.range;
}

void LimitSink::end_file(const std::string& path, const std::string& io_error) {
    if (first_omitted_) {
        Diagnostic d = std::move(*first_omitted_);
        if (omitted_items_ > 1) {
            // Findings folded before were counted as folded then.
            counts_.folded += omitted_items_ - 1;
            d.folded = omitted_ - 1;
            d.folded_last = last_omitted_;
            d.notes.push_back({fmt::format("{} more findings in this file are not shown (--max-findings {})",
                                           omitted_ - 1, max_),
                               std::nullopt});
        }
        next_.diagnostic(std::move(d));
        first_omitted_.reset();
    }
    next_.end_file(path, io_error);
}

}  // namespace osplint
