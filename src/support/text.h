// Small text helpers shared by every layer (ASCII case, blanks), and the kinds
// of program files by extension.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace osplint {

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }
inline char ascii_upper(char c) { return c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c; }
inline char ascii_lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }
// An ASCII letter or digit (as std::isalnum in the "C" locale).
inline bool is_alnum(char c) { return (c >= '0' && c <= '9') || (ascii_upper(c) >= 'A' && ascii_upper(c) <= 'Z'); }

// ASCII upper case of `s` (bytes outside a-z unchanged).
std::string upper(std::string_view s);
// Equal ignoring ASCII case.
inline bool iequals(std::string_view a, std::string_view b) {  // inline: the catalog's lookups call it per argument
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (ascii_upper(a[i]) != ascii_upper(b[i])) return false;
    return true;
}
// How many of the first n bytes at a and b are the same before the first that
// differs (n when all are): 16 at a time, for the lines a posted program
// repeats but for a value or two.
inline size_t same_prefix(const char* a, const char* b, size_t n) {
    size_t i = 0;
#if defined(__SSE2__)
    const auto first_difference = [&](size_t at) {
        const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a + at));
        const __m128i y = _mm_loadu_si128(reinterpret_cast<const __m128i*>(b + at));
        return ~static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(x, y))) & 0xffffu;
    };
    if (n >= 16) {
        for (; i + 16 <= n; i += 16)
            if (const unsigned d = first_difference(i)) return i + static_cast<size_t>(__builtin_ctz(d));
        if (i == n) return n;
        // The last bytes: the 16 that end the range, those before i known the same.
        if (const unsigned d = first_difference(n - 16)) return n - 16 + static_cast<size_t>(__builtin_ctz(d));
        return n;
    }
    if (n >= 8) {  // two words of 8 (little-endian: the first differing byte is the lowest)
        const auto first_in_word = [&](size_t at) {
            uint64_t x, y;
            std::memcpy(&x, a + at, 8);
            std::memcpy(&y, b + at, 8);
            return x == y ? 8u : static_cast<unsigned>(__builtin_ctzll(x ^ y)) / 8;
        };
        if (const unsigned k = first_in_word(0); k < 8) return k;
        if (const unsigned k = first_in_word(n - 8); k < 8) return n - 8 + k;
        return n;
    }
#endif
    while (i < n && a[i] == b[i]) ++i;
    return i;
}
// Whether `hay` holds `needle`, ignoring ASCII case.
bool contains_ci(std::string_view hay, std::string_view needle);
// `s` without leading and trailing blanks (space, tab, form feed, vertical tab).
std::string_view trim_blanks(std::string_view s);

// Edit distance (insertions, deletions, substitutions, swaps of two neighbours),
// ignoring ASCII case.
size_t edit_distance(std::string_view a, std::string_view b);
// The candidate nearest to `word` for a "did you mean" hint: within a third of
// the word's length (at least 1, at most 3 edits); empty when none is that near.
std::string closest_match(std::string_view word, const std::vector<std::string_view>& candidates);

// The extension of the last component of a path, upper case, without the dot
// ("PART.min" -> "MIN"; "" when there is none).
std::string file_extension(std::string_view path);

// Program files osplint checks: .MIN .SSB .SUB .SDF .LIB .NC .MSB, any case.
bool is_program_file(std::string_view path);
// Files that hold subprograms only (.SSB .SUB .LIB .MSB, any case): each of
// their programs starts with the caller's state, which is unknown, and the
// control searches them for the CALL targets of a main program.
bool is_subprogram_file(std::string_view path);
// Schedule programs (.SDF).
bool is_schedule_file(std::string_view path);

// A string cut to at most `max` bytes for a message, with "..." when cut (never
// inside a UTF-8 sequence).
std::string abbreviate(std::string_view s, size_t max);

}  // namespace osplint
