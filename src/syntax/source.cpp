// Source text, line index and column arithmetic (see source.h).
#include "syntax/source.h"

#include <iconv.h>

#include <algorithm>
#include <cerrno>

#include "support/io.h"

namespace osplint {

namespace {

// Length of the well-formed UTF-8 sequence at s[i] (1-4) and its code point, or 0
// when the bytes there are not a well-formed sequence (overlong forms, surrogates
// and values above U+10FFFF are ill-formed).
uint32_t decode_utf8(std::string_view s, size_t i, uint32_t& cp) {
    const auto b0 = static_cast<unsigned char>(s[i]);
    if (b0 < 0x80) {
        cp = b0;
        return 1;
    }
    uint32_t len;
    uint32_t min;
    if (b0 >= 0xC2 && b0 <= 0xDF) {
        len = 2, cp = b0 & 0x1F, min = 0x80;
    } else if (b0 >= 0xE0 && b0 <= 0xEF) {
        len = 3, cp = b0 & 0x0F, min = 0x800;
    } else if (b0 >= 0xF0 && b0 <= 0xF4) {
        len = 4, cp = b0 & 0x07, min = 0x10000;
    } else {
        return 0;
    }
    if (i + len > s.size()) return 0;
    for (uint32_t k = 1; k < len; ++k) {
        const auto b = static_cast<unsigned char>(s[i + k]);
        if ((b & 0xC0) != 0x80) return 0;
        cp = (cp << 6) | (b & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
    return len;
}

// One column step: bytes consumed and UTF-16 units of the character at s[i].
struct Step {
    uint32_t bytes;
    uint32_t utf16;
};

Step step_at(std::string_view s, size_t i) {
    uint32_t cp = 0;
    const uint32_t len = decode_utf8(s, i, cp);
    if (len == 0) return {1, 1};  // an invalid byte counts as one unit
    return {len, cp > 0xFFFF ? 2u : 1u};
}

// Byte length of a line's terminator starting at `i` (0 when there is none).
uint32_t terminator_at(std::string_view s, size_t i) {
    if (i >= s.size()) return 0;
    if (s[i] == '\n') return 1;
    if (s[i] == '\r') return i + 1 < s.size() && s[i + 1] == '\n' ? 2 : 1;
    return 0;
}

void append_replacement(std::string& out) { out += "\xEF\xBF\xBD"; }

}  // namespace

ColumnCount count_columns(std::string_view bytes) {
    ColumnCount c;
    for (size_t i = 0; i < bytes.size();) {
        const auto b = static_cast<unsigned char>(bytes[i]);
        if (b < 0x80) {  // fast path for ASCII
            ++c.cp, ++c.utf16, ++i;
            continue;
        }
        const Step st = step_at(bytes, i);
        ++c.cp;
        c.utf16 += st.utf16;
        i += st.bytes;
    }
    return c;
}

uint32_t bytes_for_columns(std::string_view line, uint32_t units, ColumnUnit unit) {
    const auto size = static_cast<uint32_t>(line.size());
    if (unit == ColumnUnit::Byte) return std::min(units, size);
    uint32_t pos = 0;
    uint32_t done = 0;
    while (pos < size && done < units) {
        const Step st = step_at(line, pos);
        const uint32_t cost = unit == ColumnUnit::CodePoint ? 1 : st.utf16;
        if (done + cost > units) break;  // would split a surrogate pair: stay before it
        done += cost;
        pos += st.bytes;
    }
    return pos;
}

Position resolve_position(std::string_view text, uint32_t line_start, uint32_t line, uint32_t offset) {
    const auto size = static_cast<uint32_t>(text.size());
    line_start = std::min(line_start, size);
    offset = std::clamp(offset, line_start, size);
    Position p;
    p.line = line;
    p.byte_col = offset - line_start;
    const ColumnCount c = count_columns(text.substr(line_start, offset - line_start));
    p.cp_col = c.cp;
    p.utf16_col = c.utf16;
    return p;
}

SourceText::SourceText(std::string text) : text_(std::move(text)) {
    starts_.push_back(0);
    const std::string_view s = text_;
    const char* const b = s.data();
    for (const char* p = b; (p = find_line_break(p, b + s.size()));) {
        p += terminator_at(s, static_cast<size_t>(p - b));
        starts_.push_back(static_cast<uint32_t>(p - b));
    }
}

uint32_t SourceText::line_of(uint32_t offset) const {
    // Last line start <= offset.
    const auto it = std::upper_bound(starts_.begin(), starts_.end(), offset);
    return static_cast<uint32_t>(it - starts_.begin());  // >= 1 since starts_[0] == 0
}

uint32_t SourceText::line_start(uint32_t line) const {
    if (line == 0) line = 1;
    if (line > starts_.size()) line = static_cast<uint32_t>(starts_.size());
    return starts_[line - 1];
}

std::string_view SourceText::line_text(uint32_t line) const {
    if (line == 0 || line > starts_.size()) return {};
    const uint32_t begin = starts_[line - 1];
    if (line == starts_.size()) return std::string_view(text_).substr(begin);  // unterminated
    // Every other line ends with CRLF, LF or a lone CR just before the next start.
    uint32_t end = starts_[line];
    if (end - begin >= 2 && text_[end - 2] == '\r' && text_[end - 1] == '\n')
        end -= 2;
    else
        end -= 1;
    return std::string_view(text_).substr(begin, end - begin);
}

Position SourceText::position(uint32_t offset) const {
    offset = std::min(offset, size());
    const uint32_t line = line_of(offset);
    return resolve_position(text_, starts_[line - 1], line, offset);
}

uint32_t SourceText::offset_of(uint32_t line, uint32_t column, ColumnUnit unit) const {
    if (line == 0) line = 1;
    if (line > starts_.size()) line = static_cast<uint32_t>(starts_.size());
    return starts_[line - 1] + bytes_for_columns(line_text(line), column, unit);
}

bool is_valid_utf8(std::string_view bytes) {
    for (size_t i = 0; i < bytes.size();) {
        if (static_cast<unsigned char>(bytes[i]) < 0x80) {
            ++i;
            continue;
        }
        uint32_t cp = 0;
        const uint32_t len = decode_utf8(bytes, i, cp);
        if (len == 0) return false;
        i += len;
    }
    return true;
}

std::string decode_for_display(std::string_view bytes) {
    if (is_valid_utf8(bytes)) return std::string(bytes);

    std::string out;
    out.reserve(bytes.size() * 3 / 2 + 4);
    iconv_t cd = iconv_open("UTF-8", "CP932");
    if (cd == reinterpret_cast<iconv_t>(-1)) {
        // No converter: keep ASCII and valid UTF-8, replace everything else.
        for (size_t i = 0; i < bytes.size();) {
            uint32_t cp = 0;
            const uint32_t len = decode_utf8(bytes, i, cp);
            if (len == 0) {
                append_replacement(out);
                ++i;
            } else {
                out.append(bytes.substr(i, len));
                i += len;
            }
        }
        return out;
    }

    char buffer[256];
    size_t pos = 0;
    while (pos < bytes.size()) {
        char* in = const_cast<char*>(bytes.data() + pos);
        size_t in_left = bytes.size() - pos;
        char* dst = buffer;
        size_t dst_left = sizeof buffer;
        const size_t rc = iconv(cd, &in, &in_left, &dst, &dst_left);
        const int err = rc == static_cast<size_t>(-1) ? errno : 0;
        out.append(buffer, static_cast<size_t>(dst - buffer));
        pos = bytes.size() - in_left;
        if (rc != static_cast<size_t>(-1)) break;  // all converted
        if (err == E2BIG) continue;                // output buffer full: go on
        // EILSEQ (invalid) or EINVAL (truncated at the end): replace one byte.
        append_replacement(out);
        ++pos;
        iconv(cd, nullptr, nullptr, nullptr, nullptr);  // reset the shift state
    }
    iconv_close(cd);
    return out;
}

}  // namespace osplint
