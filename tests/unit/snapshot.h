// Snapshots of a rule's findings on a fixture, pinned in a file beside it
// (tests/rules/OSP104/m52.MIN.snap), and a line diff to show how the output
// differs from the file.
//
// The format is plain text, one finding per block of lines, blocks separated
// by an empty line, in the order of the findings (position, then rule, then
// message). Positions are LINE:COLUMN, 1-based, the column counted in code
// points, as the text report shows them; a range is START-END (END excluded).
//
//   # OSP104 on m52.MIN
//
//   OSP104 m52-on-call-line error 3:30-3:33
//     message: M52 on a CALL line is ...
//     note 3:1-3:5: the call
//     note: a note without a place
//     fix (safe): Replace M52 by PM=52
//       edit 3:30-3:33: "PM=52"
//
// A text (a message, a note, a title) is written with \n, \r, \t and \\
// escaped, and any other control byte as \xNN; a replacement is quoted, with
// \" escaped too.
#pragma once

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "osplint/diagnostic.h"

namespace osplint::testing {

inline std::string snapshot_escape(std::string_view s, bool quoted = false) {
    std::string out;
    for (char c : s) {
        switch (c) {
        case '\n': out += "\\n"; break;
        case '\r': out += "\\r"; break;
        case '\t': out += "\\t"; break;
        case '\\': out += "\\\\"; break;
        default:
            if (quoted && c == '"') {
                out += "\\\"";
            } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned char>(c));
                out += buf;
            } else {
                out += c;
            }
        }
    }
    return out;
}

inline std::string snapshot_position(const Position& p) {
    return std::to_string(p.line) + ":" + std::to_string(p.cp_col + 1);
}

inline std::string snapshot_range(const SourceRange& r) {
    return snapshot_position(r.start) + "-" + snapshot_position(r.end);
}

// The snapshot of the findings `found` of `rule` on the fixture `name`.
inline std::string snapshot_of(std::string_view rule, std::string_view name, const std::vector<Diagnostic>& found) {
    std::ostringstream out;
    out << "# " << rule << " on " << name << "\n";
    if (found.empty()) out << "\n(no findings)\n";
    for (const auto& d : found) {
        out << "\n" << d.rule << " " << d.name << " " << severity_name(d.severity) << " " << snapshot_range(d.range)
            << "\n";
        out << "  message: " << snapshot_escape(d.message) << "\n";
        if (d.folded) out << "  folded: " << d.folded << " more, the last at " << snapshot_range(*d.folded_last) << "\n";
        for (const auto& n : d.notes) {
            out << "  note";
            if (n.range) out << " " << snapshot_range(*n.range);
            out << ": " << snapshot_escape(n.message) << "\n";
        }
        for (const auto& f : d.fixes) {
            out << "  fix (" << (f.safe ? "safe" : "unsafe") << "): " << snapshot_escape(f.title) << "\n";
            for (const auto& e : f.edits)
                out << "    edit " << snapshot_range(e.range) << ": \"" << snapshot_escape(e.replacement, true) << "\"\n";
        }
    }
    return out.str();
}

inline std::vector<std::string> snapshot_lines(std::string_view text) {
    std::vector<std::string> out;
    size_t i = 0;
    while (i < text.size()) {
        size_t e = text.find('\n', i);
        if (e == std::string_view::npos) e = text.size();
        out.emplace_back(text.substr(i, e - i));
        i = e + 1;
    }
    if (!text.empty() && text.back() != '\n') out.back() += "\\ (no newline at the end)";
    return out;
}

// A line diff of `expected` (the file) and `actual` (what the test made):
// lines only in the file start with "-", lines only in the output with "+",
// and up to two lines of context around each change start with " ". Texts of
// a few hundred lines: a plain longest-common-subsequence table.
inline std::string line_diff(std::string_view expected, std::string_view actual) {
    const auto a = snapshot_lines(expected), b = snapshot_lines(actual);
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<uint32_t>> lcs(n + 1, std::vector<uint32_t>(m + 1, 0));
    for (size_t i = n; i-- > 0;)
        for (size_t j = m; j-- > 0;)
            lcs[i][j] = a[i] == b[j] ? lcs[i + 1][j + 1] + 1 : std::max(lcs[i + 1][j], lcs[i][j + 1]);
    struct Line {
        char mark;
        const std::string* text;
    };
    std::vector<Line> script;
    size_t i = 0, j = 0;
    while (i < n || j < m) {
        if (i < n && j < m && a[i] == b[j]) {
            script.push_back({' ', &a[i]});
            ++i, ++j;
        } else if (i < n && (j == m || lcs[i + 1][j] >= lcs[i][j + 1])) {
            script.push_back({'-', &a[i++]});
        } else {
            script.push_back({'+', &b[j++]});
        }
    }
    constexpr size_t kContext = 2;
    std::vector<bool> shown(script.size(), false);
    for (size_t k = 0; k < script.size(); ++k) {
        if (script[k].mark == ' ') continue;
        for (size_t c = k >= kContext ? k - kContext : 0; c < std::min(script.size(), k + kContext + 1); ++c)
            shown[c] = true;
    }
    std::string out;
    bool gap = false;
    for (size_t k = 0; k < script.size(); ++k) {
        if (!shown[k]) {
            gap = true;
            continue;
        }
        if (gap && !out.empty()) out += "  ...\n";
        gap = false;
        out += script[k].mark;
        out += *script[k].text;
        out += '\n';
    }
    return out;
}

}  // namespace osplint::testing
