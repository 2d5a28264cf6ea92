#include "engine/positions.h"

#include <algorithm>
#include <cstring>

#include "support/text.h"
#include "syntax/source.h"

namespace osplint {

void Window::set(std::string_view t, uint32_t b, uint32_t line) {
    ascii_ = -1;
    memo_ = Position{0, 0, 0, 0};
    text = t;
    base = b;
    first_line = line;
    starts.clear();
    starts.push_back(0);
    for (size_t i = 0; i < t.size(); ++i)
        if (ends_line(t.data() + i, t.data() + t.size())) starts.push_back(static_cast<uint32_t>(i + 1));
}

void Window::set_line(const LineRef& l) {
    ascii_ = -1;
    memo_ = Position{0, 0, 0, 0};
    text = std::string_view(l.text.data(), l.text.size() + l.terminator.size());
    base = l.start;
    first_line = l.line;
    starts.resize(l.terminator.empty() ? 1 : 2);
    starts[0] = 0;
    if (!l.terminator.empty()) starts[1] = static_cast<uint32_t>(text.size());
}

bool Window::has_line(uint32_t line) const {
    return !empty() && line >= first_line && line - first_line < starts.size() &&
           !(line - first_line == starts.size() - 1 && starts.back() == text.size() && starts.size() > 1);
}

Position Window::position(uint32_t offset) const {
    const uint32_t rel = offset - base;
    const auto it = std::upper_bound(starts.begin(), starts.end(), rel);
    const size_t k = static_cast<size_t>(it - starts.begin()) - 1;
    Position p;
    p.line = first_line + static_cast<uint32_t>(k);
    p.byte_col = rel - starts[k];
    // Columns cost nothing in ASCII text, and are counted on from the last
    // position asked for on the same line: a line with many findings is not
    // read again for each of them.
    if (ascii_ < 0) {
        ascii_ = 1;
        for (const char ch : text)
            if (static_cast<unsigned char>(ch) >= 0x80) {
                ascii_ = 0;
                break;
            }
    }
    if (ascii_) {
        p.cp_col = p.utf16_col = p.byte_col;
        return p;
    }
    uint32_t from = starts[k];
    ColumnCount c;
    // The count goes on from the last position only where that position
    // starts a character: from inside a multi-byte sequence its remaining
    // bytes would count as characters of their own.
    const auto starts_char = [&](uint32_t col) {
        return col == 0 || (static_cast<unsigned char>(text[starts[k] + col]) & 0xC0) != 0x80;
    };
    if (memo_.line == p.line && memo_.byte_col <= p.byte_col && starts_char(memo_.byte_col)) {
        from = starts[k] + memo_.byte_col;
        c.cp = memo_.cp_col;
        c.utf16 = memo_.utf16_col;
    }
    const ColumnCount more = count_columns(text.substr(from, rel - from));
    p.cp_col = c.cp + more.cp;
    p.utf16_col = c.utf16 + more.utf16;
    memo_ = p;
    return p;
}

std::string_view Window::line_text(uint32_t line) const {
    const size_t k = line - first_line;
    const uint32_t b = starts[k];
    uint32_t e = k + 1 < starts.size() ? starts[k + 1] : static_cast<uint32_t>(text.size());
    if (k + 1 < starts.size()) {
        if (e - b >= 2 && text[e - 2] == '\r' && text[e - 1] == '\n') e -= 2;
        else e -= 1;
    }
    return text.substr(b, e - b);
}

std::string_view Window::line_terminator(uint32_t line) const {
    const size_t k = line - first_line;
    const std::string_view t = line_text(line);
    const uint32_t e = k + 1 < starts.size() ? starts[k + 1] : static_cast<uint32_t>(text.size());
    const size_t end_of_text = static_cast<size_t>(t.data() - text.data()) + t.size();
    return text.substr(end_of_text, e - end_of_text);
}

Position Positions::position(uint32_t offset) {
    if (size_ && offset > *size_) offset = static_cast<uint32_t>(*size_);
    for (const Window* w : {&current(), static_cast<const Window*>(&held)})
        if (w->contains(offset)) return w->position(offset);
    const LineData& f = find_offset(offset);
    Position p;
    p.line = f.line;
    if (!f.ok) return p;
    p.byte_col = offset - f.start;
    const std::string_view line = f.text;
    const std::string_view term = f.terminator;
    ColumnCount c = count_columns(line.substr(0, std::min<size_t>(p.byte_col, line.size())));
    if (p.byte_col > line.size()) {
        const ColumnCount t = count_columns(term.substr(0, p.byte_col - line.size()));
        c.cp += t.cp;
        c.utf16 += t.utf16;
    }
    p.cp_col = c.cp;
    p.utf16_col = c.utf16;
    return p;
}

LineData Positions::line(uint32_t line) {
    for (const Window* w : {&current(), static_cast<const Window*>(&held)})
        if (w->has_line(line)) {
            LineData d;
            d.ok = true;
            d.line = line;
            d.start = w->line_start(line);
            d.text.assign(w->line_text(line));
            d.terminator.assign(w->line_terminator(line));
            return d;
        }
    return find_line(line);
}

std::string Positions::line_text(uint32_t n, size_t max) {
    for (const Window* w : {&current(), static_cast<const Window*>(&held)})
        if (w->has_line(n)) return abbreviate(w->line_text(n), max);
    const LineData& d = find_line(n);
    return d.ok ? abbreviate(d.text, max) : std::string();
}

// Reads lines from the last checkpoint before the target until `stop` accepts one.
template <class StartOk, class Stop>
const LineData& Positions::scan(StartOk&& start_ok, Stop&& stop) {
    // The checkpoints grow in offset and line: the last one `start_ok` accepts.
    auto it = std::partition_point(checkpoints_.begin(), checkpoints_.end(), start_ok);
    const Checkpoint cp = it == checkpoints_.begin() ? checkpoints_.front() : *(it - 1);
    // A checkpoint is at most 1024 lines back: a small buffer (the stream grows it for a long line).
    LineStream ls(*src_, size_t(16) << 10);
    ls.seek(cp.offset, cp.line);
    LineRef l;
    cache_ = LineData{};
    uint32_t last = cp.line - 1;
    bool terminated = true;
    while (ls.next(l)) {
        last = l.line;
        terminated = !l.terminator.empty();
        if (stop(l)) {
            cache_.ok = true;
            cache_.line = l.line;
            cache_.start = l.start;
            cache_.text.assign(l.text);
            cache_.terminator.assign(l.terminator);
            return cache_;
        }
    }
    // Past the end: the empty line after a final terminator.
    cache_.line = terminated ? last + 1 : std::max<uint32_t>(last, 1);
    return cache_;
}

const LineData& Positions::find_offset(uint32_t offset) {
    if (cache_.ok && offset >= cache_.start &&
        (offset - cache_.start < cache_.text.size() + cache_.terminator.size() ||
         (cache_.terminator.empty() && offset - cache_.start == cache_.text.size())))
        return cache_;
    // The line ends between the last checkpoint (or the line found last, when
    // it is nearer) and the offset are counted in the bytes, a block at a
    // time; only the line that holds the offset is read as a line.
    auto it = std::partition_point(checkpoints_.begin(), checkpoints_.end(),
                                   [&](const Checkpoint& c) { return c.offset <= offset; });
    Checkpoint from = it == checkpoints_.begin() ? checkpoints_.front() : *(it - 1);
    if (cache_.ok && cache_.start <= offset && cache_.start > from.offset) from = {cache_.start, cache_.line};
    if (count_buf_.empty()) count_buf_.resize(size_t(16) << 10);
    uint64_t pos = from.offset;
    uint64_t start = from.offset;
    uint32_t line = from.line;
    bool read_ok = true;
    // A CR is a line end unless an LF follows it: the byte at `offset` is
    // read too, and a CR whose next byte was not read waits for the next block.
    while (pos < offset) {
        const size_t want = static_cast<size_t>(std::min<uint64_t>(count_buf_.size(), offset + 1 - pos));
        const int64_t got = src_->read(pos, count_buf_.data(), want);
        if (got <= 0) {
            read_ok = false;
            break;
        }
        const char* const b = count_buf_.data();
        size_t count = static_cast<size_t>(std::min<uint64_t>(static_cast<uint64_t>(got), offset - pos));
        if (count == static_cast<size_t>(got) && b[count - 1] == '\r') {
            if (count == 1) {
                read_ok = false;
                break;
            }
            --count;
        }
        if (std::memchr(b, '\r', count)) {
            for (size_t i = 0; i < count; ++i)
                if (ends_line(b + i, b + got)) {
                    ++line;
                    start = pos + i + 1;
                }
        } else {
            for (const char* q = b; (q = static_cast<const char*>(std::memchr(q, '\n', count - (q - b)))); ++q) {
                ++line;
                start = pos + static_cast<uint64_t>(q - b) + 1;
            }
        }
        pos += count;
    }
    if (read_ok && read_line_at(start, line)) return cache_;
    // A read that failed or came short: the lines are read one by one.
    return scan([&](const Checkpoint& c) { return c.offset <= offset; },
                [&](const LineRef& l) {
                    const uint64_t end = uint64_t(l.start) + l.text.size() + l.terminator.size();
                    return offset < end || (l.terminator.empty() && offset == end);
                });
}

// The line that starts at `start` (line `line`) into cache_: false when a read fails.
bool Positions::read_line_at(uint64_t start, uint32_t line) {
    cache_ = LineData{};
    cache_.line = line;
    uint64_t pos = start;
    while (true) {
        const int64_t got = src_->read(pos, count_buf_.data(), count_buf_.size());
        if (got < 0) return false;
        if (got == 0) break;  // the end of the input
        const char* const b = count_buf_.data();
        const size_t n = static_cast<size_t>(got);
        const char* e = static_cast<const char*>(std::memchr(b, '\n', n));
        const char* cr = static_cast<const char*>(std::memchr(b, '\r', e ? static_cast<size_t>(e - b) : n));
        if (cr) e = cr;
        cache_.ok = true;
        if (!e) {
            cache_.text.append(b, n);
            pos += n;
            continue;
        }
        cache_.text.append(b, static_cast<size_t>(e - b));
        if (*e == '\n') {
            cache_.terminator = "\n";
        } else {
            char next = 0;
            if (e + 1 < b + n) next = e[1];
            else if (src_->read(pos + n, &next, 1) < 0) return false;
            cache_.terminator = next == '\n' ? "\r\n" : "\r";
        }
        break;
    }
    if (cache_.ok) cache_.start = static_cast<uint32_t>(start);
    return true;
}

const LineData& Positions::find_line(uint32_t n) {
    if (cache_.ok && cache_.line == n) return cache_;
    return scan([&](const Checkpoint& c) { return c.line <= n; }, [&](const LineRef& l) { return l.line == n; });
}

}  // namespace osplint
