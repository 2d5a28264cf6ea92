// Inline expectations in test programs, written as OSP comments:
//   (expect: OSP104)            the block on this line has an OSP104 finding
//   (expect: OSP101, OSP104)    several findings on this line
//   (expect-next: OSP001 col 7) the next line has an OSP001 finding at column 7
//                               (1-based, in code points)
#pragma once

#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "api/check.h"
#include "api/config.h"

namespace osplint::testing {

struct Expected {
    uint32_t line = 0;
    std::string rule;
    std::optional<uint32_t> column;
    bool operator<(const Expected& o) const {
        return std::tie(line, rule) < std::tie(o.line, o.rule);
    }
};

inline std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

inline std::vector<Expected> parse_expectations(const std::string& text) {
    std::vector<Expected> out;
    uint32_t line = 1;
    size_t i = 0;
    while (i <= text.size()) {
        size_t e = text.find_first_of("\r\n", i);
        if (e == std::string::npos) e = text.size();
        std::string l = text.substr(i, e - i);
        for (std::string tag : {"(expect:", "(expect-next:"}) {
            size_t p = l.find(tag);
            if (p == std::string::npos) continue;
            size_t close = l.find(')', p);
            std::string body = l.substr(p + tag.size(), close == std::string::npos ? std::string::npos : close - p - tag.size());
            std::istringstream ws(body);
            std::string tok;
            std::vector<Expected> here;
            while (ws >> tok) {
                while (!tok.empty() && tok.back() == ',') tok.pop_back();
                if (tok == "col") {
                    uint32_t c = 0;
                    ws >> c;
                    if (!here.empty()) here.back().column = c;
                } else if (tok.rfind("OSP", 0) == 0) {
                    here.push_back({tag == "(expect:" ? line : line + 1, tok, std::nullopt});
                }
            }
            out.insert(out.end(), here.begin(), here.end());
        }
        if (e >= text.size()) break;
        i = e + ((text[e] == '\r' && e + 1 < text.size() && text[e + 1] == '\n') ? 2 : 1);
        ++line;
    }
    return out;
}

// Compares findings with expectations; returns human-readable mismatches.
inline std::vector<std::string> compare(const std::vector<Expected>& expected, const std::vector<Diagnostic>& found,
                                        const std::set<std::string>& rules_considered) {
    std::vector<std::string> problems;
    std::multiset<Expected> want(expected.begin(), expected.end());
    std::multiset<Expected> remaining = want;
    for (const auto& d : found) {
        if (!rules_considered.empty() && !rules_considered.count(d.rule)) continue;
        Expected key{d.range.start.line, d.rule, std::nullopt};
        auto it = remaining.find(key);
        if (it == remaining.end()) {
            problems.push_back("unexpected " + d.rule + " at line " + std::to_string(d.range.start.line) + ":" +
                               std::to_string(d.range.start.cp_col + 1) + ": " + d.message);
            continue;
        }
        if (it->column && *it->column != d.range.start.cp_col + 1)
            problems.push_back(d.rule + " at line " + std::to_string(d.range.start.line) + " expected column " +
                               std::to_string(*it->column) + ", found " + std::to_string(d.range.start.cp_col + 1) +
                               ": " + d.message);
        remaining.erase(it);
    }
    for (const auto& e : remaining)
        if (rules_considered.empty() || rules_considered.count(e.rule))
            problems.push_back("missing " + e.rule + " at line " + std::to_string(e.line));
    return problems;
}

}  // namespace osplint::testing
