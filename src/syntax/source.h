// Source text and positions.
//
// Internally every location is a byte offset. A Position resolves one for
// display: a 1-based line and 0-based columns counted in bytes, Unicode code
// points and UTF-16 code units (renderers add 1 where their format is 1-based;
// the LSP uses UTF-16 or UTF-8 units as negotiated). Invalid UTF-8 bytes count
// as one code point / one UTF-16 unit each, so columns are always defined.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "osplint/diagnostic.h"
#include "syntax/model.h"

namespace osplint {


// Counts code points and UTF-16 units in `bytes` (invalid bytes count 1 each).
struct ColumnCount {
    uint32_t cp = 0;
    uint32_t utf16 = 0;
};
ColumnCount count_columns(std::string_view bytes);

// Byte length of the prefix of `line` that spans `units` code units in the given
// unit system (0 = bytes, 1 = code points, 2 = UTF-16). Clamped to the line.
enum class ColumnUnit { Byte, CodePoint, Utf16 };
uint32_t bytes_for_columns(std::string_view line, uint32_t units, ColumnUnit unit);

// Resolves `offset` given the byte offset where its line starts and the line number.
Position resolve_position(std::string_view text, uint32_t line_start, uint32_t line, uint32_t offset);

// A whole file held in memory, with a line index.
class SourceText {
public:
    SourceText() = default;
    explicit SourceText(std::string text);
    const std::string& text() const { return text_; }
    uint32_t size() const { return static_cast<uint32_t>(text_.size()); }
    // 1-based line containing `offset` (an offset at a terminator belongs to its line).
    uint32_t line_of(uint32_t offset) const;
    uint32_t line_start(uint32_t line) const;  // byte offset of a 1-based line
    uint32_t line_count() const { return static_cast<uint32_t>(starts_.size()); }
    // The line's text without its terminator (LF, CRLF or lone CR).
    std::string_view line_text(uint32_t line) const;
    Position position(uint32_t offset) const;
    // Byte offset of (line 1-based, column in `unit`, 0-based); clamped.
    uint32_t offset_of(uint32_t line, uint32_t column, ColumnUnit unit) const;

private:
    std::string text_;
    std::vector<uint32_t> starts_;
};

// Comment text for display: as UTF-8 when it is valid UTF-8, otherwise decoded
// from Shift-JIS (CP932); bytes that decode in neither become U+FFFD.
std::string decode_for_display(std::string_view bytes);
bool is_valid_utf8(std::string_view bytes);

// A parsed file: the program model of one source text.
struct ProgramFile {
    std::string path;
    SourceText source;
    std::vector<Block> blocks;
    std::vector<Program> programs;
};

}  // namespace osplint
