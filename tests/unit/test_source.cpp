// Source text: line index, positions and columns, decoding for display.
#include <doctest/doctest.h>

#include <string>

#include "syntax/source.h"

using namespace osplint;

TEST_CASE("count_columns counts code points and UTF-16 units") {
    CHECK(count_columns("G0 X1").cp == 5);
    CHECK(count_columns("G0 X1").utf16 == 5);

    const ColumnCount e = count_columns("\xC3\xA9");  // é: 2 bytes
    CHECK(e.cp == 1);
    CHECK(e.utf16 == 1);

    const ColumnCount emoji = count_columns("\xF0\x9F\x98\x80");  // U+1F600, outside the BMP
    CHECK(emoji.cp == 1);
    CHECK(emoji.utf16 == 2);

    // Invalid bytes count one unit each; a truncated sequence is invalid.
    const ColumnCount bad = count_columns("\xFF\xFE\xE3\x81");
    CHECK(bad.cp == 4);
    CHECK(bad.utf16 == 4);
    // Shift-JIS "加工" (0x89 0xC1 0x8D 0x48): 0x48 is ASCII 'H' after an invalid lead byte.
    const ColumnCount sjis = count_columns("\x89\xC1\x8D\x48");
    CHECK(sjis.cp == 4);
}

TEST_CASE("bytes_for_columns never splits a character") {
    const std::string line = "\xF0\x9F\x98\x80" "a\xC3\xA9";  // 😀 a é
    CHECK(bytes_for_columns(line, 1, ColumnUnit::Utf16) == 0);  // inside the surrogate pair
    CHECK(bytes_for_columns(line, 2, ColumnUnit::Utf16) == 4);
    CHECK(bytes_for_columns(line, 3, ColumnUnit::Utf16) == 5);
    CHECK(bytes_for_columns(line, 1, ColumnUnit::CodePoint) == 4);
    CHECK(bytes_for_columns(line, 3, ColumnUnit::CodePoint) == 7);
    CHECK(bytes_for_columns(line, 99, ColumnUnit::CodePoint) == 7);  // clamped
    CHECK(bytes_for_columns(line, 5, ColumnUnit::Byte) == 5);
    CHECK(bytes_for_columns(line, 99, ColumnUnit::Byte) == 7);
}

TEST_CASE("line index with LF, CRLF and lone CR") {
    const SourceText src("G0\r\nG1\rG2\nG3");
    REQUIRE(src.line_count() == 4);
    CHECK(src.line_text(1) == "G0");
    CHECK(src.line_text(2) == "G1");
    CHECK(src.line_text(3) == "G2");
    CHECK(src.line_text(4) == "G3");
    CHECK(src.line_start(1) == 0);
    CHECK(src.line_start(2) == 4);
    CHECK(src.line_start(3) == 7);
    CHECK(src.line_start(4) == 10);
    // A terminator belongs to the line it ends.
    CHECK(src.line_of(2) == 1);  // '\r' of CRLF
    CHECK(src.line_of(3) == 1);  // '\n' of CRLF
    CHECK(src.line_of(4) == 2);
    CHECK(src.line_of(6) == 2);  // lone CR
    CHECK(src.line_of(12) == 4);
    CHECK(src.line_of(1000) == 4);  // past the end: last line
    CHECK(src.line_text(0).empty());
    CHECK(src.line_text(5).empty());
}

TEST_CASE("a final newline opens an empty last line; no final newline is fine") {
    const SourceText with("G0\nG1\n");
    CHECK(with.line_count() == 3);
    CHECK(with.line_text(3).empty());
    CHECK(with.position(6).line == 3);

    const SourceText without("G0\nRTS");
    CHECK(without.line_count() == 2);
    CHECK(without.line_text(2) == "RTS");
    CHECK(without.position(6) == Position{2, 3, 3, 3});

    const SourceText crlf_end("G0\r\n");
    CHECK(crlf_end.line_count() == 2);
    CHECK(crlf_end.line_text(1) == "G0");

    const SourceText empty("");
    CHECK(empty.line_count() == 1);
    CHECK(empty.line_text(1).empty());
    CHECK(empty.position(0) == Position{1, 0, 0, 0});
}

TEST_CASE("positions count tabs as one column and multi-byte characters once") {
    const SourceText src("\tG0 (\xE5\x8A\xA0\xE5\xB7\xA5) X1\n(\xF0\x9F\x98\x80)Y");
    // "X1" after a tab, "G0 (", two 3-byte characters and ") ".
    const uint32_t x = static_cast<uint32_t>(src.text().find("X1"));
    const Position p = src.position(x);
    CHECK(p.line == 1);
    CHECK(p.byte_col == 13);
    CHECK(p.cp_col == 9);
    CHECK(p.utf16_col == 9);

    const uint32_t y = static_cast<uint32_t>(src.text().rfind('Y'));
    const Position q = src.position(y);
    CHECK(q.line == 2);
    CHECK(q.byte_col == 6);
    CHECK(q.cp_col == 3);
    CHECK(q.utf16_col == 4);  // the emoji takes two UTF-16 units
}

TEST_CASE("Shift-JIS comment: columns count invalid bytes one by one") {
    // "G0 (加工) X1" with the comment in Shift-JIS.
    const SourceText src(std::string("G0 (\x89\xC1\x8D\x48) X1"));
    const uint32_t x = static_cast<uint32_t>(src.text().find("X1"));
    const Position p = src.position(x);
    CHECK(p.byte_col == 10);
    CHECK(p.cp_col == 10);  // 0x89, 0xC1, 0x8D invalid; 0x48 is 'H'
    CHECK(p.utf16_col == 10);
}

TEST_CASE("offset_of and position round-trip in every unit") {
    const SourceText src("N1 G0 (\xC3\xA9t\xC3\xA9)\r\n\t(\xF0\x9F\x98\x80) X1\rM30");
    for (uint32_t off = 0; off <= src.size(); ++off) {
        const char c = off < src.size() ? src.text()[off] : 0;
        // Only offsets at character starts (not continuation bytes) and not inside a CRLF.
        if ((static_cast<unsigned char>(c) & 0xC0) == 0x80) continue;
        const Position p = src.position(off);
        const uint32_t start = src.line_start(p.line);
        const uint32_t line_end = start + static_cast<uint32_t>(src.line_text(p.line).size());
        if (off > line_end) continue;  // the LF of a CRLF resolves to the CR's column
        INFO("offset " << off);
        CHECK(src.offset_of(p.line, p.byte_col, ColumnUnit::Byte) == off);
        CHECK(src.offset_of(p.line, p.cp_col, ColumnUnit::CodePoint) == off);
        CHECK(src.offset_of(p.line, p.utf16_col, ColumnUnit::Utf16) == off);
    }
    // Clamping: columns past the end stop at the end of the line (not in the next line).
    CHECK(src.offset_of(1, 999, ColumnUnit::CodePoint) == src.line_start(1) + src.line_text(1).size());
    CHECK(src.offset_of(99, 0, ColumnUnit::Byte) == src.line_start(3));
}

TEST_CASE("resolve_position works from a known line start") {
    const std::string text = "G0\nX\xC3\xA9" "1";
    const Position p = resolve_position(text, 3, 2, 6);
    CHECK(p == Position{2, 3, 2, 2});
    // Offsets before the line start or past the end are clamped.
    CHECK(resolve_position(text, 3, 2, 1).byte_col == 0);
    CHECK(resolve_position(text, 3, 2, 100).byte_col == 4);
}

TEST_CASE("is_valid_utf8 rejects ill-formed sequences") {
    CHECK(is_valid_utf8("G0 X1 (plain)"));
    CHECK(is_valid_utf8("\xE5\x8A\xA0\xE5\xB7\xA5"));
    CHECK(is_valid_utf8("\xF0\x9F\x98\x80"));
    CHECK_FALSE(is_valid_utf8("\xC0\xAF"));          // overlong '/'
    CHECK_FALSE(is_valid_utf8("\xED\xA0\x80"));      // surrogate
    CHECK_FALSE(is_valid_utf8("\xF4\x90\x80\x80"));  // above U+10FFFF
    CHECK_FALSE(is_valid_utf8("\xE5\x8A"));          // truncated
    CHECK_FALSE(is_valid_utf8("\x89\xC1\x8D\x48"));  // Shift-JIS
}

TEST_CASE("decode_for_display: UTF-8 as is, else Shift-JIS, else U+FFFD") {
    CHECK(decode_for_display("(TOOL \xE5\x8A\xA0\xE5\xB7\xA5)") == "(TOOL \xE5\x8A\xA0\xE5\xB7\xA5)");
    // Shift-JIS 加工 and ソ (whose second byte is a backslash).
    CHECK(decode_for_display("(\x89\xC1\x8D\x48)") == "(\xE5\x8A\xA0\xE5\xB7\xA5)");
    CHECK(decode_for_display("\x83\x5C") == "\xE3\x82\xBD");
    // Half-width katakana (single byte in Shift-JIS).
    CHECK(decode_for_display("\xB1") == "\xEF\xBD\xB1");
    // A lead byte at the end and a byte that is neither: replaced, the rest kept.
    CHECK(decode_for_display("A\x89") == "A\xEF\xBF\xBD");
    CHECK(decode_for_display("\xFF" "B\x89\xC1") == "\xEF\xBF\xBD" "B\xE5\x8A\xA0");
    CHECK(decode_for_display("") == "");
}
