#include "output/pipeline.h"

#include <fmt/format.h>

namespace osplint {

void FoldingSink::diagnostic(Diagnostic&& d) {
    switch (folder_.next(d.kind, d.range.bytes)) {
        case Folder::Verdict::Show: next_.diagnostic(std::move(d)); break;
        case Folder::Verdict::Hold: {
            const uint64_t kind = d.kind;
            folder_.hold(kind, std::move(d));
            break;
        }
        case Folder::Verdict::Count: last_[d.kind] = d.range; break;
    }
}

void FoldingSink::end_file(const std::string& path, const std::string& io_error) {
    auto resolve = [&](uint64_t kind, ByteRange r) {
        auto it = last_.find(kind);
        return it != last_.end() ? it->second : SourceRange{r, {}, {}};
    };
    for (Diagnostic& d : folder_.finish(resolve)) {
        counts_.folded += d.folded;
        next_.diagnostic(std::move(d));
    }
    last_.clear();
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
