#include "support/glob.h"

#include <vector>

namespace osplint {
namespace {

// The end of the bracket expression starting at p[i] == '[' (the index of its
// ']'), or npos when it is not closed.
size_t bracket_end(std::string_view p, size_t i) {
    size_t j = i + 1;
    if (j < p.size() && (p[j] == '!' || p[j] == '^')) ++j;
    if (j < p.size() && p[j] == ']') ++j;  // a ']' first is a member
    for (; j < p.size(); ++j)
        if (p[j] == ']') return j;
        else if (p[j] == '/') return std::string_view::npos;
    return std::string_view::npos;
}

bool bracket_matches(std::string_view set, char c) {  // set: between '[' and ']'
    bool negate = false;
    size_t i = 0;
    if (i < set.size() && (set[i] == '!' || set[i] == '^')) {
        negate = true;
        ++i;
    }
    bool found = false;
    while (i < set.size()) {
        char lo = set[i];
        if (i + 2 < set.size() && set[i + 1] == '-') {
            if (lo <= c && c <= set[i + 2]) found = true;
            i += 3;
        } else {
            if (c == lo) found = true;
            ++i;
        }
    }
    return found != negate;
}

// One component against one component pattern (no '/' in either).
bool match_component(std::string_view p, std::string_view s) {
    size_t pi = 0, si = 0;
    size_t star_p = std::string_view::npos, star_s = 0;
    while (si < s.size()) {
        if (pi < p.size()) {
            const char pc = p[pi];
            if (pc == '*') {
                star_p = pi++;
                star_s = si;
                continue;
            }
            if (pc == '?') {
                ++pi;
                ++si;
                continue;
            }
            if (pc == '[') {
                const size_t end = bracket_end(p, pi);
                if (end != std::string_view::npos) {
                    if (bracket_matches(p.substr(pi + 1, end - pi - 1), s[si])) {
                        pi = end + 1;
                        ++si;
                        continue;
                    }
                } else if (s[si] == '[') {  // an unclosed '[' is itself
                    ++pi;
                    ++si;
                    continue;
                }
            } else if (pc == s[si]) {
                ++pi;
                ++si;
                continue;
            }
        }
        if (star_p == std::string_view::npos) return false;
        pi = star_p + 1;
        si = ++star_s;
    }
    while (pi < p.size() && p[pi] == '*') ++pi;
    return pi == p.size();
}

std::vector<std::string_view> split(std::string_view s) {
    std::vector<std::string_view> parts;
    size_t start = 0;
    for (size_t i = 0; i <= s.size(); ++i)
        if (i == s.size() || s[i] == '/') {
            if (i > start) parts.push_back(s.substr(start, i - start));  // "a//b" is "a/b"
            start = i + 1;
        }
    return parts;
}

bool match_parts(const std::vector<std::string_view>& p, size_t pi, const std::vector<std::string_view>& s, size_t si) {
    while (pi < p.size()) {
        if (p[pi] == "**") {
            // Collapse runs of "**"; then try every number of components.
            while (pi + 1 < p.size() && p[pi + 1] == "**") ++pi;
            if (pi + 1 == p.size()) return true;
            for (size_t k = si; k <= s.size(); ++k)
                if (match_parts(p, pi + 1, s, k)) return true;
            return false;
        }
        if (si >= s.size() || !match_component(p[pi], s[si])) return false;
        ++pi;
        ++si;
    }
    return si == s.size();
}

}  // namespace

bool glob_match(std::string_view pattern, std::string_view path) {
    if (pattern.empty()) return path.empty();
    return match_parts(split(pattern), 0, split(path), 0);
}

bool glob_valid(std::string_view pattern, std::string_view* why) {
    if (pattern.empty()) {
        if (why) *why = "an empty pattern matches nothing";
        return false;
    }
    for (size_t i = 0; i < pattern.size(); ++i)
        if (pattern[i] == '[') {
            const size_t end = bracket_end(pattern, i);
            if (end == std::string_view::npos) {
                if (why) *why = "'[' without its closing ']'";
                return false;
            }
            i = end;
        }
    return true;
}

}  // namespace osplint
