// Small text helpers shared by every layer (ASCII case, blanks), and the kinds
// of program files by extension.
#pragma once

#include <string>
#include <string_view>
#include <vector>

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
