#include "support/text.h"

#include <algorithm>
#include <cstring>
#include <vector>

namespace osplint {

std::string upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = ascii_upper(c);
    return out;
}

size_t edit_distance(std::string_view a, std::string_view b) {
    // Optimal string alignment: three rows of the table.
    std::vector<size_t> two(b.size() + 1), one(b.size() + 1), cur(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) one[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const bool same = ascii_upper(a[i - 1]) == ascii_upper(b[j - 1]);
            cur[j] = std::min({one[j] + 1, cur[j - 1] + 1, one[j - 1] + (same ? 0 : 1)});
            if (i > 1 && j > 1 && ascii_upper(a[i - 1]) == ascii_upper(b[j - 2]) &&
                ascii_upper(a[i - 2]) == ascii_upper(b[j - 1]))
                cur[j] = std::min(cur[j], two[j - 2] + 1);
        }
        std::swap(two, one);
        std::swap(one, cur);
    }
    return one[b.size()];
}

std::string closest_match(std::string_view word, const std::vector<std::string_view>& candidates) {
    const size_t limit = std::min<size_t>(3, std::max<size_t>(1, word.size() / 3));
    std::string best;
    size_t best_d = limit + 1;
    for (auto c : candidates) {
        if (c.empty()) continue;
        const size_t d = edit_distance(word, c);
        if (d < best_d) {
            best_d = d;
            best = std::string(c);
        }
    }
    return best;
}

std::string_view trim_blanks(std::string_view s) {
    size_t b = 0, e = s.size();
    while (b < e && is_blank(s[b])) ++b;
    while (e > b && is_blank(s[e - 1])) --e;
    return s.substr(b, e - b);
}

std::string file_extension(std::string_view path) {
    const size_t slash = path.find_last_of("/\\");
    const size_t dot = path.rfind('.');
    if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) return {};
    return upper(path.substr(dot + 1));
}

bool is_program_file(std::string_view path) {
    const std::string e = file_extension(path);
    return e == "MIN" || e == "SSB" || e == "SUB" || e == "SDF" || e == "LIB" || e == "NC" || e == "MSB";
}

bool is_subprogram_file(std::string_view path) {
    const std::string e = file_extension(path);
    return e == "SSB" || e == "SUB" || e == "LIB" || e == "MSB";
}

bool is_schedule_file(std::string_view path) { return file_extension(path) == "SDF"; }

std::string abbreviate(std::string_view s, size_t max) {
    if (s.size() <= max) return std::string(s);
    size_t cut = max > 3 ? max - 3 : 0;
    while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;
    return std::string(s.substr(0, cut)) + "...";
}

bool contains_ci(std::string_view hay, std::string_view needle) {
    const auto up = ascii_upper;
    if (needle.empty()) return true;
    if (hay.size() < needle.size()) return false;
    const char first = up(needle[0]);
    const bool letter = first >= 'A' && first <= 'Z';
    const char* const last = hay.data() + (hay.size() - needle.size());
    for (const char* p = hay.data(); p <= last; ++p) {
        // A first character that has no other case is found by memchr (`+ limit`).
        if (!letter) {
            p = static_cast<const char*>(std::memchr(p, first, static_cast<size_t>(last - p) + 1));
            if (!p) return false;
        } else if (up(*p) != first) {
            continue;
        }
        size_t k = 1;
        while (k < needle.size() && up(p[k]) == up(needle[k])) ++k;
        if (k == needle.size()) return true;
    }
    return false;
}

}  // namespace osplint
