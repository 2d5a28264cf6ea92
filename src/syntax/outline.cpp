#include "syntax/outline.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <limits>
#include <thread>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "syntax/directive.h"
#include "syntax/frontend_fast.h"
#include "syntax/frontend_fast_lexer.h"
#include "support/io.h"
#include "support/text.h"
#include "support/threads.h"

namespace osplint {
namespace {

inline bool is_break(char c) { return c == '\n' || c == '\r'; }

// Bits set in a 16-bit mask (without relying on a POPCNT instruction).
inline uint32_t count_bits(unsigned v) {
    v = v - ((v >> 1) & 0x5555u);
    v = (v & 0x3333u) + ((v >> 2) & 0x3333u);
    v = (v + (v >> 4)) & 0x0F0Fu;
    return (v + (v >> 8)) & 0x1Fu;
}

// A candidate found by next_candidate, and the line ends before it.
struct Scan {
    const char* candidate = nullptr;  // nullptr: none in the range
    uint32_t line_ends = 0;           // line ends in [p, candidate) (or in [p, e))
};

// Whether the 'N' at p, first on its line, may be an N word (`N=60`, `N+1`:
// a value, so a reference) rather than the line's sequence name. The line
// parser takes a sequence name where a digit follows the N, or a letter and
// no '=' or '[' after the name (`NAT=1` is an assignment). Anything else
// makes the N a word. The line is whole in [p, e).
inline bool n_word_at_line_start(const char* p, const char* e) {
    using fast_detail::is_alnum;
    ++p;
    if (p >= e || fast_detail::is_digit(*p)) return false;
    if (!fast_detail::is_letter(*p)) return !is_break(*p);
    while (p < e && is_alnum(*p)) ++p;
    while (p < e && fast_detail::is_blank(*p)) ++p;
    return p < e && (*p == '=' || *p == '[');
}

// The first byte of [p, e) that may belong to an outlined item (see the
// header), and the number of lines that end before it. p starts a line when
// `line_start`. Bytes 16 at a time: a letter folded to lower case by OR 0x20
// equals 'o', 'e', 't' or 'w'; an 'f' right after an 'i'; an 'n' not right
// after a line break, or right after one and maybe an N word
// (n_word_at_line_start). No other byte maps to a lower-case letter under OR
// 0x20. A line ends at an LF, or at a CR
// that no LF follows.
Scan next_candidate(const char* p, const char* e, bool line_start) {
    Scan out;
    unsigned after_break = line_start ? 1u : 0u;
    unsigned after_i = 0;
#if defined(__SSE2__)
    const __m128i fold = _mm_set1_epi8(0x20);
    const __m128i o = _mm_set1_epi8('o'), le = _mm_set1_epi8('e'), t = _mm_set1_epi8('t'), w = _mm_set1_epi8('w');
    const __m128i n = _mm_set1_epi8('n'), i = _mm_set1_epi8('i'), f = _mm_set1_epi8('f');
    const __m128i lf = _mm_set1_epi8('\n'), cr = _mm_set1_epi8('\r');
    for (; e - p >= 16; p += 16) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
        const __m128i l = _mm_or_si128(v, fold);
        const __m128i oetw = _mm_or_si128(_mm_or_si128(_mm_cmpeq_epi8(l, o), _mm_cmpeq_epi8(l, le)),
                                          _mm_or_si128(_mm_cmpeq_epi8(l, t), _mm_cmpeq_epi8(l, w)));
        const unsigned m = static_cast<unsigned>(_mm_movemask_epi8(oetw));
        const unsigned nm = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(l, n)));
        const unsigned im = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(l, i)));
        const unsigned lfm = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(v, lf)));
        const unsigned crm = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(v, cr)));
        const unsigned brk = lfm | crm;
        unsigned ends = lfm | (crm & ~(lfm >> 1));
        if ((crm & 0x8000u) && e - p > 16 && p[16] == '\n') ends &= 0x7FFFu;  // a CRLF across the boundary
        const unsigned line_start_n = nm & ((brk << 1) | after_break) & 0xFFFFu;
        unsigned cand = m | (nm & ~((brk << 1) | after_break));
        for (unsigned b = line_start_n; b; b &= b - 1) {
            const unsigned k = static_cast<unsigned>(__builtin_ctz(b));
            if (n_word_at_line_start(p + k, e)) cand |= 1u << k;
        }
        if (im | after_i) {
            const unsigned fm = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(l, f)));
            cand |= fm & ((im << 1) | after_i);
        }
        cand &= 0xFFFFu;
        if (cand) {
            const unsigned k = static_cast<unsigned>(__builtin_ctz(cand));
            out.candidate = p + k;
            out.line_ends += count_bits(ends & ((1u << k) - 1u));
            return out;
        }
        out.line_ends += count_bits(ends);
        after_break = (brk >> 15) & 1u;
        after_i = (im >> 15) & 1u;
    }
#endif
    for (; p < e; ++p) {
        const char l = static_cast<char>(*p | 0x20);
        if (l == 'o' || l == 'e' || l == 't' || l == 'w' || (l == 'n' && (!after_break || n_word_at_line_start(p, e))) ||
            (l == 'f' && after_i)) {
            out.candidate = p;
            return out;
        }
        if (ends_line(p, e)) ++out.line_ends;
        after_break = is_break(*p) ? 1u : 0u;
        after_i = l == 'i' ? 1u : 0u;
    }
    return out;
}

}  // namespace

bool comments_only(std::string_view text) {
    size_t i = 0;
    bool any = false;
    while (true) {
        while (i < text.size() && is_blank(text[i])) ++i;
        if (i == text.size()) return any;
        if (text[i] != '(') return false;
        size_t close = i + 1;
        for (; close < text.size() && text[close] != ')'; ++close) {
            const auto c = static_cast<unsigned char>(text[close]);
            if ((c < 0x20 && c != '\t') || c == 0x7F) return false;
        }
        if (close == text.size()) return false;
        const ByteRange comment{static_cast<uint32_t>(i), static_cast<uint32_t>(close + 1)};
        if (parse_directive(text, comment).is_directive) return false;
        any = true;
        i = close + 1;
    }
}

namespace {

// Whether [p, e), inside one line and not at its start, holds a byte
// next_candidate would take: next_candidate without the line ends and the N
// at a line's start, for the arguments of a call line. But for a letter
// between a P and an `=` (`PT=35.`, `PN=2`): the last letter of an argument's
// name, which no keyword ends with; it is no N word either (a letter comes
// before it).
bool candidate_inside_line(const char* p, const char* e) {
    const char* const begin = p;
    const auto in_name = [&](const char* c) { return c > begin && c + 1 < e && (c[-1] | 0x20) == 'p' && c[1] == '='; };
    unsigned after_i = 0;
#if defined(__SSE2__)
    const __m128i fold = _mm_set1_epi8(0x20);
    const __m128i o = _mm_set1_epi8('o'), le = _mm_set1_epi8('e'), t = _mm_set1_epi8('t'), w = _mm_set1_epi8('w');
    const __m128i n = _mm_set1_epi8('n'), i = _mm_set1_epi8('i'), f = _mm_set1_epi8('f');
    const auto chunk = [&](const char* at) {
        const __m128i l = _mm_or_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(at)), fold);
        const __m128i any = _mm_or_si128(_mm_or_si128(_mm_cmpeq_epi8(l, o), _mm_cmpeq_epi8(l, le)),
                                         _mm_or_si128(_mm_or_si128(_mm_cmpeq_epi8(l, t), _mm_cmpeq_epi8(l, w)),
                                                      _mm_cmpeq_epi8(l, n)));
        const unsigned im = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(l, i)));
        if (unsigned m = static_cast<unsigned>(_mm_movemask_epi8(any))) {
            for (; m; m &= m - 1)
                if (!in_name(at + __builtin_ctz(m))) return true;
        }
        if (im | after_i) {
            const unsigned fm = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(l, f)));
            if (fm & ((im << 1) | after_i)) return true;
        }
        after_i = (im >> 15) & 1u;
        return false;
    };
    for (; e - p >= 16; p += 16)
        if (chunk(p)) return true;
    // The last bytes of a range of 16 or more: the 16 that end it, read
    // again in part (they held nothing, `i` and `f` across them included).
    if (p < e && e - begin >= 16) {
        after_i = 0;
        return chunk(e - 16);
    }
#endif
    for (; p < e; ++p) {
        const char l = static_cast<char>(*p | 0x20);
        if (((l == 'o' || l == 'e' || l == 't' || l == 'w' || l == 'n') && !in_name(p)) || (l == 'f' && after_i))
            return true;
        after_i = l == 'i' ? 1u : 0u;
    }
    return false;
}

bool is_flow(StmtKind k) {
    return k == StmtKind::Goto || k == StmtKind::If || k == StmtKind::While || k == StmtKind::Do ||
           k == StmtKind::End;
}

class Outliner {
public:
    Outliner(ByteSource& src, const OutlineOptions& options) : src_(src), options_(options) {}
    // An outliner of the part of the input from `start` (a line start after
    // the file's first block with content) on: its lines are numbered from 1,
    // and its first program stands for the one the part starts in.
    Outliner(ByteSource& src, const OutlineOptions& options, uint64_t start) : src_(src), options_(options) {
        base_ = start;
        first_found_ = true;
        first_offset_ = std::numeric_limits<uint32_t>::max();
        out_.programs.emplace_back();
    }

    // After run: whether the outline of the next part can be joined to this
    // one (the first block with content was found and no directive waits for
    // its target).
    bool settled() const { return first_found_ && pending_.empty(); }

    FileOutline run() {
        while (true) {
            if (pos_ >= complete_) {
                if (eof_) break;
                if (!refill()) break;
                continue;
            }
            if (!first_found_ || !pending_.empty()) {
                take_line();
                continue;
            }
            const Scan scan = next_candidate(buf_.data() + pos_, buf_.data() + complete_, true);
            line_ += scan.line_ends;
            if (!scan.candidate) {
                pos_ = complete_;
                continue;
            }
            const char* ls = scan.candidate;
            while (ls > buf_.data() + pos_ && !is_break(ls[-1])) --ls;
            pos_ = static_cast<size_t>(ls - buf_.data());
            if (!skip_unparsed_line()) take_line();
        }
        for (auto& p : out_.programs) {
            std::sort(p.references.begin(), p.references.end());
            p.references.erase(std::unique(p.references.begin(), p.references.end()), p.references.end());
        }
        out_.size = base_ + end_;
        // Every line end ends a block; so does the end of an unterminated last line.
        out_.lines = line_ - 1 + (out_.size > 0 && !is_break(last_byte_) ? 1 : 0);
        return std::move(out_);
    }

private:
    // Reads more input behind what is left; sets complete_ to the end of the
    // last whole line in the buffer.
    bool refill() {
        if (pos_ > 0) {
            std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
            end_ -= pos_;
            base_ += pos_;
            complete_ = complete_ > pos_ ? complete_ - pos_ : 0;
            pos_ = 0;
        }
        const size_t chunk = line_buffer_size(src_, std::max<size_t>(options_.chunk_size, 16));
        if (buf_.size() < chunk) buf_.resize(chunk);
        if (end_ == buf_.size()) buf_.resize(buf_.size() * 2);  // a line longer than the buffer
        const int64_t r = src_.read(base_ + end_, buf_.data() + end_, buf_.size() - end_);
        if (r < 0) {
            out_.error = src_.error();
            return false;
        }
        if (r == 0) eof_ = true;
        end_ += static_cast<size_t>(r);
        if (r > 0) last_byte_ = buf_[end_ - 1];
        if (base_ + end_ > kMaxInputSize) {
            out_.error = kTooLargeMessage;
            return false;
        }
        if (eof_) {
            complete_ = end_;
            return true;
        }
        if (end_ - pos_ > kMaxLineLength && !find_line_break(buf_.data() + pos_, buf_.data() + end_)) {
            out_.error = line_too_long_message(line_);  // one line, and no end in sight
            return false;
        }
        // The last line break that surely ends a line (a CR at the very end may
        // be the first half of a CRLF).
        size_t k = end_;
        while (k > pos_) {
            const char c = buf_[k - 1];
            if (c == '\n' || (c == '\r' && k < end_)) break;
            --k;
        }
        complete_ = k;
        return true;
    }

    // Parses the line at pos_ exactly and takes what the outline needs of it.
    void take_line() {
        const char* p = buf_.data() + pos_;
        const char* e = buf_.data() + complete_;
        const char* brk = find_line_break(p, e);
        size_t text = brk ? static_cast<size_t>(brk - p) : static_cast<size_t>(e - p);
        size_t term = 0;
        if (brk) term = (*brk == '\r' && brk + 1 < buf_.data() + end_ && brk[1] == '\n') ? 2 : 1;
        LineRef line{std::string_view(p, text), std::string_view(p + text, term), line_,
                     static_cast<uint32_t>(base_ + pos_)};
        pos_ += text + term;
        if (term) ++line_;
        ++out_.lines_parsed;
        parser_.parse_outline(line, block_);
        take(block_, line);
    }

    // A line that gives the outline nothing is passed over unparsed (the
    // letters of its text made it a candidate). Only while no directive waits
    // for its target (run takes every line then):
    // - a line of comments only, none of them a suppression directive
    //   (comments_only): no program name, no flow, no block a directive
    //   waits for;
    // - a CALL or MODIN with plain arguments only (outline_passes_over).
    bool skip_unparsed_line() {
        const char* p = buf_.data() + pos_;
        const char* brk = find_line_break(p, buf_.data() + complete_);
        if (!brk) return false;
        const size_t text = static_cast<size_t>(brk - p);
        const size_t term = (*brk == '\r' && brk + 1 < buf_.data() + end_ && brk[1] == '\n') ? 2 : 1;
        const LineRef line{std::string_view(p, text), std::string_view(brk, term), line_,
                           static_cast<uint32_t>(base_ + pos_)};
        size_t i = 0;
        while (i < text && is_blank(p[i])) ++i;
        if (i < text && p[i] == '(' ? !comments_only(line.text) : !outline_passes_over(parser_, line, &last_plain_))
            return false;
        pos_ += text + term;
        ++line_;
        return true;
    }

    void take(const Block& b, const LineRef& line) {
        if (out_.programs.empty()) out_.programs.emplace_back();  // the file's first line (line 1, offset 0)
        if (!first_found_) {
            if (b.program_name || (b.kind == LineKind::Block && !b.is_empty())) {
                first_found_ = true;
                first_offset_ = line.start;
                out_.first_block = line.start;
                ProgramOutline& p = out_.programs.front();
                p.has_content = true;
                if (b.program_name) {
                    p.name = b.program_name->name;
                    p.name_range = b.program_name->range;
                }
            }
        } else if (b.program_name && line.start != first_offset_) {
            ProgramOutline p;
            p.line = line.line;
            p.offset = line.start;
            p.name = b.program_name->name;
            p.name_range = b.program_name->range;
            p.has_content = true;
            out_.programs.push_back(std::move(p));
        }
        if (options_.names_only) return;
        ProgramOutline& p = out_.programs.back();
        FlowSite site;
        for (const auto& st : b.statements) {
            if (st.kind == StmtKind::Rts) p.has_rts = true;
            if (!is_flow(st.kind)) continue;
            site.statements.push_back({st.kind, st.name, st.loop});
            if ((st.kind == StmtKind::Goto || st.kind == StmtKind::If) && !st.name.empty())
                p.references.push_back(st.name);
        }
        for (const auto& w : b.words)
            if (w.address == "N" && !w.value_text.empty()) p.references.push_back("N" + w.value_text);
        if (!site.statements.empty()) {
            site.line = line.line;
            site.offset = line.start;
            site.next = line.end();
            site.block_delete = b.block_delete;
            p.flow.push_back(std::move(site));
        }
        const bool target = suppression_target(b);
        if (target) {
            for (size_t k : pending_) {
                out_.directives[k].target = line.start;
                out_.directives[k].target_line = line.line;
            }
            pending_.clear();
        }
        if (!b.comments.empty() && has_directive(b, line.text)) {
            DirectiveSite d;
            d.line = line.line;
            d.offset = line.start;
            d.text.assign(line.text);
            for (const auto& c : b.comments) d.comments.push_back(c.range);
            d.program = out_.programs.size() - 1;
            if (target) {
                d.target = line.start;
                d.target_line = line.line;
            } else {
                pending_.push_back(out_.directives.size());
            }
            out_.directives.push_back(std::move(d));
        }
    }

    ByteSource& src_;
    const OutlineOptions& options_;
    FileOutline out_;
    FastLineParser parser_;
    Block block_;
    std::vector<char> buf_;
    uint64_t base_ = 0;   // offset of buf_[0]
    size_t pos_ = 0;      // next line start
    size_t end_ = 0;      // bytes in buf_
    size_t complete_ = 0; // end of the last whole line in buf_
    bool eof_ = false;
    uint32_t line_ = 1;   // number of the line at pos_
    char last_byte_ = '\n';
    bool first_found_ = false;
    uint32_t first_offset_ = 0;
    std::vector<size_t> pending_;  // directives waiting for their target block
    std::string last_plain_;       // the last line plain_call passed over (outline_passes_over)
};

}  // namespace

bool may_hold_outline_item(const char* p, const char* e, bool line_start) {
    return next_candidate(p, e, line_start).candidate != nullptr;
}

bool outline_passes_over(FastLineParser& parser, const LineRef& line, std::string* last_plain) {
    const uint32_t head = parser.call_head_end(line);
    if (head == 0) return false;
    const char* rest = line.text.data() + head;
    if (!candidate_inside_line(rest, line.text.data() + line.text.size())) return true;
    // A posted program calls the same macro line after line, with other values.
    if (last_plain && !last_plain->empty() && passes_like(*last_plain, line.text)) return true;
    if (!parser.plain_call(line)) return false;
    if (last_plain) last_plain->assign(line.text);
    return true;
}

namespace {
// The first offset from i in a and j in b where they differ (or one ends), as (i, j).
void skip_same(std::string_view a, size_t& i, std::string_view b, size_t& j) {
    const size_t k = same_prefix(a.data() + i, b.data() + j, std::min(a.size() - i, b.size() - j));
    i += k;
    j += k;
}
}  // namespace

bool passes_like(std::string_view passed, std::string_view text) {
    const auto value_byte = [](char c) { return (c >= '0' && c <= '9') || c == '.' || c == '+' || c == '-'; };
    const auto blank = [](char c) { return c == ' ' || c == '\t'; };
    size_t i = 0, j = 0;
    while (true) {
        skip_same(passed, i, text, j);
        if (i == passed.size() && j == text.size()) return true;
        // They differ inside a value, or just after one: back to where it starts,
        // after the `=` (and blanks) of its item. The bytes backed over are the same on both lines.
        size_t k = i;
        while (k > 0 && value_byte(passed[k - 1])) --k;
        size_t eq = k;
        while (eq > 0 && blank(passed[eq - 1])) --eq;
        if (eq == 0 || passed[eq - 1] != '=' || i - k > j) return false;
        const size_t at = j - (i - k);
        const uint32_t end_passed = FastLineParser::plain_value_end(passed, static_cast<uint32_t>(k));
        const uint32_t end_text = FastLineParser::plain_value_end(text, static_cast<uint32_t>(at));
        if (end_passed == k || end_text == at || (end_passed <= i && end_text <= j)) return false;
        i = end_passed;
        j = end_text;
    }
}

namespace {

// Where part k of n of [0, size) starts: the line start at or after k/n of
// it, nullopt when none is found within a line's longest length.
std::optional<uint64_t> part_start(ByteSource& src, uint64_t size, uint64_t at) {
    std::vector<char> buf(64 * 1024);
    for (uint64_t from = at - 1; from < size && from < at + kMaxLineLength;) {
        const int64_t r = src.read(from, buf.data(), buf.size());
        if (r <= 0) return std::nullopt;
        const char* p = buf.data();
        const char* lf = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(r)));
        if (lf) return from + static_cast<uint64_t>(lf - p) + 1;
        from += static_cast<uint64_t>(r);
    }
    return std::nullopt;
}

// Adds the outline of the part after `into`'s (`part`, its lines numbered
// from 1) to `into`, which holds `lines` lines.
void join_part(FileOutline& into, FileOutline&& part, uint32_t lines) {
    const size_t last = into.programs.size() - 1;
    for (auto& d : part.directives) {
        d.line += lines;
        if (d.target_line) d.target_line += lines;
        d.program += last;
        into.directives.push_back(std::move(d));
    }
    for (auto& p : part.programs) {
        p.line += lines;
        for (auto& f : p.flow) f.line += lines;
    }
    // The part's first program goes on with the last one before it.
    ProgramOutline& going_on = into.programs.back();
    ProgramOutline& first = part.programs.front();
    going_on.has_rts = going_on.has_rts || first.has_rts;
    going_on.flow.insert(going_on.flow.end(), std::make_move_iterator(first.flow.begin()),
                         std::make_move_iterator(first.flow.end()));
    if (!first.references.empty()) {
        auto& refs = going_on.references;
        const auto middle = refs.insert(refs.end(), first.references.begin(), first.references.end());
        std::inplace_merge(refs.begin(), middle, refs.end());
        refs.erase(std::unique(refs.begin(), refs.end()), refs.end());
    }
    into.programs.insert(into.programs.end(), std::make_move_iterator(part.programs.begin() + 1),
                         std::make_move_iterator(part.programs.end()));
    into.size = part.size;
    into.lines += part.lines;
    into.lines_parsed += part.lines_parsed;
    ++into.parts;
}

// The outline of `src` read in parts at once, nullopt when it is not cut (or
// a part cannot be joined, or one could not be read: the caller reads it whole).
std::optional<FileOutline> outline_in_parts(ByteSource& src, const OutlineOptions& options) {
    const std::optional<uint64_t> size = src.size();
    if (!size || options.parts == 1 || *size > kMaxInputSize) return std::nullopt;
    uint64_t parts = options.parts;
    if (parts == 0) parts = std::max(1u, std::thread::hardware_concurrency());
    parts = std::min<uint64_t>({parts, *size / std::max<uint64_t>(options.min_part_size, 1), 64});
    if (parts < 2) return std::nullopt;
    std::vector<uint64_t> starts{0};
    for (uint64_t k = 1; k < parts; ++k) {
        const std::optional<uint64_t> at = part_start(src, *size, std::max<uint64_t>(*size * k / parts, 1));
        if (at && *at > starts.back() && *at < *size) starts.push_back(*at);
    }
    if (starts.size() < 2) return std::nullopt;
    starts.push_back(*size);
    const size_t n = starts.size() - 1;
    // Each part reads its own reader, up to the next part's start.
    std::vector<std::unique_ptr<ByteSource>> readers(n);
    for (size_t k = 1; k < n; ++k)
        if (!(readers[k] = src.another_reader())) return std::nullopt;
    struct Part {
        FileOutline outline;
        bool settled = false;
    };
    std::vector<Part> done(n);
    std::atomic<size_t> next{1};
    const auto outline_part = [&](size_t k) {
        WindowSource window(k == 0 ? src : *readers[k], 0, starts[k + 1]);
        std::optional<Outliner> o;
        if (k == 0) o.emplace(window, options);
        else o.emplace(window, options, starts[k]);
        done[k].outline = o->run();
        done[k].settled = o->settled();
    };
    const auto work = [&] {
        for (size_t k; (k = next.fetch_add(1)) < n;) outline_part(k);
    };
    run_on_threads(static_cast<unsigned>(n - 1), work, [&] {
        outline_part(0);
        work();
    });
    FileOutline out = std::move(done[0].outline);
    for (size_t k = 1; k < n; ++k) {
        if (!done[k - 1].settled || !out.ok() || !done[k].outline.ok()) return std::nullopt;
        join_part(out, std::move(done[k].outline), out.lines);
    }
    return out;
}

}  // namespace

FileOutline outline_file(ByteSource& src, const OutlineOptions& options) {
    if (std::optional<FileOutline> parts = outline_in_parts(src, options)) return std::move(*parts);
    Outliner o(src, options);
    return o.run();
}

}  // namespace osplint
