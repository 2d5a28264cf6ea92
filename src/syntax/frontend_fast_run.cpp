// FastLineParser::plain_run: a run of lines of the strictest plain-move shape
// (frontend_fast.h), read straight from the stream's buffer without parsing
// their numbers, except the last word of each address.
//
// A line shorter than 32 bytes made of X, Y, Z and F words only is checked
// 32 bytes at a time (frontend_fast_quick.h); any other line, and any line
// that check is unsure of, by the byte-by-byte check (line_words), which
// alone decides.
#include <array>
#include <cstdint>

#include "support/io.h"
#include "syntax/frontend_fast.h"
#include "syntax/frontend_fast_lexer.h"
#include "syntax/frontend_fast_quick.h"

namespace osplint {

using namespace fast_detail;

namespace {

constexpr char kAddress[] = {'X', 'Y', 'Z', 'F', 'G'};
constexpr size_t kSlots = 5;
constexpr uint32_t kNone = UINT32_MAX;

// Where the last word of each address of a line starts (the address
// letter), by slot of kAddress; kNone where it has none.
using LineWords = std::array<uint32_t, kSlots>;
using IntDigits = FastLineParser::IntDigits;

// The byte-by-byte check of the line at p: whether it is a plain move of the
// strictest shape (spaces, then X Y Z F words `X-12.5` and G0 to G3, glued
// or separated by spaces), whole in s[0, n); sets `end` to its terminator.
bool line_words(const char* s, size_t n, size_t p, size_t& end, LineWords& out, const IntDigits& int_digits,
                bool& over) {
    out.fill(kNone);
    bool words = false;
    size_t q = p;
    while (true) {
        while (q < n && s[q] == ' ') ++q;
        if (q >= n) return false;  // not whole here
        const char c = s[q];
        if (c == '\n' || c == '\r') break;
        size_t slot = 0;
        while (slot < kSlots && kAddress[slot] != c) ++slot;
        if (slot == kSlots) return false;
        const size_t begin = q++;
        if (slot != 4 && q < n && (s[q] == '+' || s[q] == '-')) ++q;
        size_t digits = 0;
        while (q < n && is_digit(s[q])) ++q, ++digits;
        if (slot < 3 && digits > int_digits[slot]) {  // may be past a bound: not in a run
            over = true;
            return false;
        }
        if (slot == 4) {
            // G0 to G3, digits only (G00 ... G03).
            if (digits == 0 || digits > 2 || s[q - 1] > '3' || (digits == 2 && s[q - 2] != '0')) return false;
        } else if (q < n && s[q] == '.') {
            ++q;
            while (q < n && is_digit(s[q])) ++q, ++digits;
        }
        if (digits == 0 || digits > 15 || q >= n ||
            !(s[q] == ' ' || s[q] == '\n' || s[q] == '\r' || (s[q] >= 'A' && s[q] <= 'Z')))
            return false;
        out[slot] = static_cast<uint32_t>(begin);
        words = true;
    }
    if (!words || q - p > kMaxLineLength) return false;
    end = q;
    return true;
}

#if OSPLINT_QUICK_LINES
// Whether a word of the quick line has more digits before its point than
// `int_digits` allows its axis.
bool quick_digits_over(const char* s, const QuickLine& line, const IntDigits& int_digits) {
    const __m128i lo = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s));
    const __m128i hi = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s + 16));
    const uint64_t digit = digits_in(lo, hi);
    const uint64_t sign = equal_to(lo, hi, '-') | equal_to(lo, hi, '+');
    const uint64_t axes[3] = {line.x, line.y, line.z};
    for (size_t k = 0; k < 3; ++k) {
        if (!axes[k] || int_digits[k] >= 16) continue;  // a value has 15 digits at most
        // Where each value's digits start: after the address and its sign.
        const uint64_t after = axes[k] << 1;
        uint64_t over = (after & ~sign) | ((after & sign) << 1);
        // A run of int_digits + 1 digits from there.
        for (unsigned j = 0; j <= int_digits[k] && over; ++j) over &= digit >> j;
        if (over) return true;
    }
    return false;
}
#endif

// The value of the word whose address is at s[begin], accepted by line_words.
PlainMoveWord read_word(const char* s, uint32_t begin, uint32_t base, size_t slot) {
    size_t q = begin + 1;
    const char sign = (s[q] == '+' || s[q] == '-') ? s[q] : 0;
    if (sign) ++q;
    const size_t digits = q;
    while (is_digit(s[q]) || s[q] == '.') ++q;
    double v = 0;
    scan_number<false>(s + digits, s + q, v);
    PlainMoveWord out;
    out.address = kAddress[slot];
    out.number = sign == '-' ? -v : v;
    out.range = {base + begin, base + static_cast<uint32_t>(q)};
    return out;
}

}  // namespace

FastLineParser::PlainRun FastLineParser::plain_run(std::string_view text, uint32_t base, uint32_t max_lines,
                                                   uint64_t start_limit, uint64_t end_limit,
                                                   uint32_t first_line, uint32_t nth,
                                                   FunctionRef<void(size_t, uint32_t)> every_nth,
                                                   IntDigits int_digits) {
    const bool bounded = int_digits[0] < 16 || int_digits[1] < 16 || int_digits[2] < 16;
    std::array<uint32_t, kSlots> last;  // where the last word of each address starts
    last.fill(kNone);
    const char* const s = text.data();
    const size_t n = text.size();
    PlainRun run;
    LineWords words;
    size_t p = 0;
    uint32_t to_nth = (nth - first_line % nth) % nth;  // lines to go to the next multiple of nth
    while (run.lines < max_lines && base + p < start_limit) {
        size_t q = 0;
        bool quick = false;  // quick_line took it
#if OSPLINT_QUICK_LINES
        QuickLine line;
        if (n - p > 32) {
            const int e = quick_line_end(s + p);
            if (e >= 0 && quick_line(s + p, e, line)) {
                if (bounded && quick_digits_over(s + p, line, int_digits)) {
                    run.over = true;
                    break;
                }
                q = p + static_cast<size_t>(e);
                quick = true;
            }
        }
#endif
        if (!quick) {
            if (!line_words(s, n, p, q, words, int_digits, run.over)) break;
        }
        size_t next = q + 1;
        if (s[q] == '\r') {
            if (q + 1 >= n) break;  // CR LF or CR alone: the next byte decides
            if (s[q + 1] == '\n') ++next;
        }
        if (base + next >= end_limit) break;
#if OSPLINT_QUICK_LINES
        if (quick) {
            const uint64_t masks[4] = {line.x, line.y, line.z, line.f};
            for (size_t k = 0; k < 4; ++k)
                if (masks[k]) last[k] = static_cast<uint32_t>(p) + static_cast<uint32_t>(63 - __builtin_clzll(masks[k]));
        } else
#endif
            for (size_t k = 0; k < kSlots; ++k)
                if (words[k] != kNone) last[k] = words[k];
        if (to_nth == 0) {
            every_nth(p, first_line + run.lines);
            to_nth = nth;
        }
        --to_nth;
        run.last_start = p;
        ++run.lines;
        p = next;
    }
    run.bytes = p;
    for (size_t slot = 0; slot < kSlots; ++slot)
        if (last[slot] != kNone) run.last.words[run.last.count++] = read_word(s, last[slot], base, slot);
    fast_lines_ += run.lines;
    return run;
}

}  // namespace osplint
