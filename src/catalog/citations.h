// The manuals osplint cites, and their sections, as one table.
//
// A citation names a manual by its English title and a section by its heading
// as printed in the manual (rendered in English), e.g.
//
//   Fixed cycles manual, "G84 tap cycle"
//   Back counterboring macros manual, "Common rules (3)"
//
// Rules, macro cards and notes build their citation text here from a key
// ("fixed-cycles/g84"); no other file carries a manual's title. The catalog
// (data/macros.toml) records where a fact is printed as a manual number and
// a line ("004:L199"); `cite_source` turns that into the section holding the
// line, so no line number reaches a user. docs/manuals.md lists the manuals.
#pragma once

#include <initializer_list>
#include <span>
#include <string>
#include <string_view>

namespace osplint {

struct Manual {
    std::string_view key;       // "fixed-cycles"
    std::string_view number;    // the manual's number in the catalog's `source` fields ("004")
    std::string_view title;     // "Fixed cycles manual"
    std::string_view japanese;  // "固定サイクル"
    std::string_view program;   // the program family as printed ("OG87EX"), or ""
    std::string_view date;      // "2001-07-30", or "" when undated
    std::string_view covers;    // what it describes
};

struct ManualSection {
    std::string_view key;       // "fixed-cycles/g84"
    std::string_view heading;   // "G84 tap cycle"
    std::string_view japanese;  // "G84 タップサイクル"
    int first_line = 0;         // the lines of the manual the section spans
    int last_line = 0;
};

std::span<const Manual> manuals();
// Every section, in manual order; items of a section follow it.
std::span<const ManualSection> manual_sections();

// By key ("keyway") or number ("002"); nullptr when unknown.
const Manual* find_manual(std::string_view key_or_number);
// By key ("keyway/okylx-notes"); nullptr when unknown.
const ManualSection* find_section(std::string_view key);
// The manual a section belongs to (the part of its key before '/').
const Manual& manual_of(const ManualSection& section);

// `Title, "Heading"` of a section key, or the manual's title for a manual key.
// An unknown key is a programming error: it throws std::out_of_range (the
// unit tests resolve every key the sources use).
std::string cite(std::string_view key);
// Several citations joined by "; ".
std::string cite(std::initializer_list<std::string_view> keys);
// The heading of a section, quoted, without the manual ("\"G84 tap cycle\"").
std::string cite_heading(std::string_view key);

// The innermost section holding the first range of a catalog source
// ("004:L182-223", "000:L26-30, L42"); nullptr when the source names no
// known manual or line, or when the range runs over several sections.
const ManualSection* section_at(std::string_view source);
// `cite` of `section_at(source)`; "" when it resolves to nothing.
std::string cite_source(std::string_view source);

}  // namespace osplint
