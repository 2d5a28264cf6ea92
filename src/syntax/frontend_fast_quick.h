// The quick check of the fast front end: whether a line shorter than 32 bytes
// is a plain move made of upper-case X, Y, Z and F words only
// (`X-53.7 Y-40. Z.5`, glued or separated by spaces), 32 bytes at a time:
// one mask per class of byte, and the shape of the words from those masks.
// Used by FastLineParser::plain_run (frontend_fast_run.cpp), whose
// byte-by-byte check decides every line this one does not accept: it only
// ever answers "this is such a line, and here are its words" or "unsure".
// tests/unit/test_fast_frontend.cpp compares the two on random lines.
#pragma once

#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#define OSPLINT_QUICK_LINES 1
#else
#define OSPLINT_QUICK_LINES 0
#endif

namespace osplint::fast_detail {

#if OSPLINT_QUICK_LINES

// The words of a line the quick check accepted, as masks of its bytes (bit i:
// byte i of the line).
struct QuickLine {
    uint64_t x = 0, y = 0, z = 0, f = 0;  // the address letters
};

// The bytes of the 32 at lo, hi equal to c, as a mask.
inline uint64_t equal_to(__m128i lo, __m128i hi, char c) {
    const __m128i k = _mm_set1_epi8(c);
    return static_cast<uint64_t>(static_cast<uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(lo, k)))) |
           static_cast<uint64_t>(static_cast<uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(hi, k)))) << 16;
}

inline uint64_t digits_in(__m128i lo, __m128i hi) {
    const __m128i below = _mm_set1_epi8('0' - 1), above = _mm_set1_epi8('9' + 1);
    const __m128i l = _mm_and_si128(_mm_cmpgt_epi8(lo, below), _mm_cmplt_epi8(lo, above));
    const __m128i h = _mm_and_si128(_mm_cmpgt_epi8(hi, below), _mm_cmplt_epi8(hi, above));
    return static_cast<uint64_t>(static_cast<uint32_t>(_mm_movemask_epi8(l))) |
           static_cast<uint64_t>(static_cast<uint32_t>(_mm_movemask_epi8(h))) << 16;
}

// The index of the first LF or CR of the 32 bytes at s, or -1.
inline int quick_line_end(const char* s) {
    const __m128i lo = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s));
    const __m128i hi = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s + 16));
    const uint64_t breaks = equal_to(lo, hi, '\n') | equal_to(lo, hi, '\r');
    return breaks ? __builtin_ctzll(breaks) : -1;
}

// Whether the line of `e` bytes (e < 32) at s, 32 bytes at s readable, is
// made of spaces and X, Y, Z and F words (one at least) whose values are
// an optional sign, then digits with at most one point among them, at least
// one digit and at most 15 bytes. The bytes from s[e] on are not looked at.
inline bool quick_line(const char* s, int e, QuickLine& out) {
    const __m128i lo = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s));
    const __m128i hi = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s + 16));
    const uint64_t line = (uint64_t(1) << e) - 1;
    const uint64_t x = equal_to(lo, hi, 'X') & line, y = equal_to(lo, hi, 'Y') & line;
    const uint64_t z = equal_to(lo, hi, 'Z') & line, f = equal_to(lo, hi, 'F') & line;
    const uint64_t address = x | y | z | f;
    const uint64_t digit = digits_in(lo, hi) & line;
    const uint64_t point = equal_to(lo, hi, '.') & line;
    const uint64_t sign = (equal_to(lo, hi, '-') | equal_to(lo, hi, '+')) & line;
    const uint64_t value = digit | point | sign;
    // Nothing but words and spaces.
    if ((line & ~(address | value | equal_to(lo, hi, ' '))) != 0 || address == 0) return false;
    const uint64_t after_address = address << 1;
    // Every address has a value right after it, and every value an address
    // right before it; a sign only first in a value, and a digit or a point
    // after it.
    if ((after_address & ~value) != 0) return false;
    if ((value & ~(value << 1) & ~after_address) != 0) return false;
    if ((sign & ~after_address) != 0 || (sign & ~((digit | point) >> 1)) != 0) return false;
    // A point with no digit on either side: a value with no digit.
    if ((point & ~(digit >> 1) & ~(digit << 1)) != 0) return false;
    // A second point: right after a point's digits (the carry of the sum
    // runs through them), or right after a point.
    const uint64_t after_point = point << 1;
    const uint64_t after_fraction = ((digit + (after_point & digit)) & ~digit) | (after_point & ~digit);
    if ((after_fraction & point) != 0) return false;
    // A value of 16 bytes or more.
    uint64_t run = value;
    run &= run >> 1;
    run &= run >> 2;
    run &= run >> 4;
    run &= run >> 8;
    if (run != 0) return false;
    out.x = x;
    out.y = y;
    out.z = z;
    out.f = f;
    return true;
}

#endif

}  // namespace osplint::fast_detail
