#include "output/diff.h"

#include <deque>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

namespace osplint {

namespace {

constexpr const char* kNoNewline = "\\ No newline at end of file\n";

// One line of the original: its number and its bytes with the terminator.
struct Line {
    uint64_t number = 0;
    uint64_t start = 0;
    std::string bytes;
    bool terminated() const { return !bytes.empty() && (bytes.back() == '\n' || bytes.back() == '\r'); }
};

class Differ {
public:
    Differ(const std::vector<Edit>& edits, const std::string& path, const ByteSink& put, unsigned context,
           DiffStats& stats)
        : edits_(edits), path_(path), put_(put), context_(context), stats_(stats) {}

    // The next line of the original, in order.
    bool line(Line&& l) {
        if (block_) {
            // A block goes on while an edit reaches into this line.
            if (reach_ > l.start) {
                absorb(std::move(l));
                return true;
            }
            if (!end_block()) return false;
        }
        if (next_ < edits_.size() && reaches(edits_[next_], l)) {
            start_block();
            absorb(std::move(l));
            return true;
        }
        if (hunk_) {
            pending_.push_back(std::move(l));
            if (pending_.size() > 2 * context_) return end_hunk();
            return true;
        }
        before_.push_back(std::move(l));
        if (before_.size() > context_) before_.pop_front();
        return true;
    }

    // The end of the original (`lines` lines, `size` bytes).
    bool finish(uint64_t lines, uint64_t size) {
        if (block_ && !end_block()) return false;
        if (next_ < edits_.size()) {
            // Insertions at the very end, after a terminated last line.
            start_block();
            block_start_ = size;
            first_line_ = lines + 1;
            while (next_ < edits_.size()) {
                in_block_.push_back(edits_[next_]);
                ++next_;
            }
            if (!end_block()) return false;
        }
        return !hunk_ || end_hunk();
    }

private:
    // Whether an edit starts on this line: an insertion at a line's start
    // belongs to that line, at the end of an unterminated last line to it.
    static bool reaches(const Edit& e, const Line& l) {
        const uint64_t end = l.start + l.bytes.size();
        return e.begin < end || (e.begin == end && !l.terminated());
    }

    void start_block() {
        if (!hunk_) {
            hunk_ = true;
            body_.clear();
            old_count_ = new_count_ = 0;
            old_start_ = 0;
            for (auto& c : before_) context_line(c);
            before_.clear();
        }
        for (auto& c : pending_) context_line(c);
        pending_.clear();
        block_ = true;
        block_old_.clear();
        block_lines_.clear();
        in_block_.clear();
        reach_ = 0;
    }

    void absorb(Line&& l) {
        if (block_lines_.empty()) {
            block_start_ = l.start;
            first_line_ = l.number;
        }
        while (next_ < edits_.size() && reaches(edits_[next_], l)) {
            reach_ = std::max<uint64_t>(reach_, edits_[next_].end);
            in_block_.push_back(edits_[next_]);
            ++next_;
        }
        block_old_ += l.bytes;
        block_lines_.push_back(std::move(l));
    }

    void context_line(const Line& l) {
        if (old_start_ == 0) old_start_ = l.number;
        body_ += ' ';
        body_ += l.bytes;
        if (!l.terminated()) body_ += "\n" + std::string(kNoNewline);
        ++old_count_;
        ++new_count_;
    }

    bool end_block() {
        block_ = false;
        if (old_start_ == 0) old_start_ = first_line_;
        std::string fixed = block_old_;
        for (size_t j = in_block_.size(); j-- > 0;) {
            const Edit& e = in_block_[j];
            const size_t b = static_cast<size_t>(e.begin - block_start_);
            const size_t n = static_cast<size_t>(std::min<uint64_t>(e.end, block_start_ + block_old_.size()) - e.begin);
            fixed.replace(b, n, e.text);
        }
        for (const auto& l : block_lines_) {
            body_ += '-';
            body_ += l.bytes;
            if (!l.terminated()) body_ += "\n" + std::string(kNoNewline);
            ++old_count_;
            ++stats_.removed;
        }
        for (size_t p = 0; p < fixed.size();) {
            size_t q = fixed.find('\n', p);
            const bool last = q == std::string::npos;
            q = last ? fixed.size() : q + 1;
            body_ += '+';
            body_.append(fixed, p, q - p);
            if (last) body_ += "\n" + std::string(kNoNewline);
            ++new_count_;
            ++stats_.added;
            p = q;
        }
        block_lines_.clear();
        block_old_.clear();
        in_block_.clear();
        return true;
    }

    bool end_hunk() {
        const size_t keep = std::min<size_t>(pending_.size(), context_);
        for (size_t j = 0; j < keep; ++j) context_line(pending_[j]);
        // What follows the trailing context is the leading context of the next hunk.
        before_.clear();
        for (size_t j = std::max(keep, pending_.size() > context_ ? pending_.size() - context_ : 0); j < pending_.size(); ++j)
            before_.push_back(std::move(pending_[j]));
        pending_.clear();
        hunk_ = false;
        if (!header_done_) {
            const std::string p = std::filesystem::path(path_).lexically_normal().string();
            const std::string a = p.empty() || p[0] == '/' ? p : "a/" + p;
            const std::string b = p.empty() || p[0] == '/' ? p : "b/" + p;
            if (!put_(fmt::format("--- {}\n+++ {}\n", a, b))) return false;
            header_done_ = true;
        }
        const uint64_t a = old_count_ ? old_start_ : old_start_ - 1;
        const int64_t new_start = static_cast<int64_t>(old_start_) + delta_;
        const int64_t c = new_count_ ? new_start : new_start - 1;
        ++stats_.hunks;
        delta_ += static_cast<int64_t>(new_count_) - static_cast<int64_t>(old_count_);
        return put_(fmt::format("@@ -{},{} +{},{} @@\n", a, old_count_, c, new_count_)) && put_(body_);
    }

    const std::vector<Edit>& edits_;
    const std::string& path_;
    const ByteSink& put_;
    unsigned context_;
    DiffStats& stats_;
    size_t next_ = 0;
    std::deque<Line> before_;   // untouched lines before the next change
    std::vector<Line> pending_; // untouched lines after the last change of the open hunk
    bool hunk_ = false;
    bool header_done_ = false;
    std::string body_;
    uint64_t old_start_ = 0, old_count_ = 0, new_count_ = 0;
    int64_t delta_ = 0;  // lines added minus removed by the hunks written
    bool block_ = false;
    std::string block_old_;
    std::vector<Line> block_lines_;
    std::vector<Edit> in_block_;
    uint64_t block_start_ = 0;
    uint64_t first_line_ = 0;
    uint64_t reach_ = 0;
};

}  // namespace

bool write_unified_diff(ByteSource& original, const std::vector<Edit>& edits, const std::string& path,
                        const ByteSink& put, std::string& error, DiffStats* stats, unsigned context) {
    DiffStats local;
    DiffStats& s = stats ? *stats : local;
    if (edits.empty()) return true;
    Differ differ(edits, path, put, context, s);
    LineStream stream(original, size_t(1) << 20);
    LineRef ref;
    uint64_t lines = 0, size = 0;
    while (stream.next(ref)) {
        Line l;
        l.number = ref.line;
        l.start = stream.last_start();
        l.bytes.reserve(ref.text.size() + ref.terminator.size());
        l.bytes.append(ref.text);
        l.bytes.append(ref.terminator);
        lines = l.number;
        size = l.start + l.bytes.size();
        if (!differ.line(std::move(l))) {
            error = "write error";
            return false;
        }
    }
    if (stream.error()) {
        error = stream.stop_reason().empty() ? original.error() : stream.stop_reason();
        return false;
    }
    if (!differ.finish(lines, size)) {
        error = "write error";
        return false;
    }
    return true;
}

}  // namespace osplint
