// The fast front end: a hand-written lexer and block parser for the common
// block shapes of part programs, used by the engine's walk (engine/engine.cpp).
//
// The tree-sitter grammar (grammar/) stays the single definition of the syntax.
// The hand-written parser recognises a subset of it — the lines CAM
// post-processors write by the million — and produces exactly the Block the
// tree-sitter front end produces for them (every field, every byte range; see
// tests/unit/test_fast_frontend.cpp). Any line it does not fully recognise
// (keywords other than CALL/MODIN/RTS/MODOUT/NCYL/NOEX/GOTO/IF/WHILE/DO/END,
// functions, strings, keyword operators not between blanks, syntax errors,
// non-ASCII text outside comments, ...) is parsed by
// the tree-sitter front end on its own, with its offsets shifted to the line's
// place in the file. The grammar is line oriented, so a line without syntax
// errors parses the same alone and in its file; a line with one is parsed on
// its own by the tree-sitter front end too (frontend.h), so that its error
// recovery does not depend on the lines around it.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "support/io.h"
#include "support/function_ref.h"
#include "syntax/model.h"
#include "syntax/source.h"

namespace osplint {


// Parses lines into Blocks. Keeps its scratch storage (and the storage of the
// Block it fills) between calls, so that parsing a stream of ordinary blocks
// does not allocate. A Block it filled may be passed again to take the next
// line only as it left it: a CALL that repeats the call before it but for
// some argument values is written over that call's block (again_lines).
class FastLineParser {
public:
    FastLineParser();
    ~FastLineParser();
    FastLineParser(const FastLineParser&) = delete;
    FastLineParser& operator=(const FastLineParser&) = delete;

    // Fills `out` with the block of `line`. Returns true when the hand-written
    // parser handled the line, false when the tree-sitter front end did.
    bool parse(const LineRef& line, Block& out);

    // Only the hand-written parser: false (and `out` unspecified) when the line
    // is outside the subset it recognises.
    bool parse_fast_only(const LineRef& line, Block& out);

    // As parse, but a CALL or MODIN whose arguments are all `Pname=number`
    // (the shape posts write) keeps only its statement: no words, no
    // expressions for the arguments. Such arguments hold no sequence name, no
    // jump and no comment, so what the outline reads of the block
    // (syntax/outline.h) is the same as from parse.
    bool parse_outline(const LineRef& line, Block& out);
    // Whether `line` is such a CALL or MODIN, alone on its line (no sequence
    // name, block delete or comment): parse_outline would make of it its
    // statement only, which the outline takes nothing from.
    bool plain_call(const LineRef& line);
    // Where the macro's name ends when `line` starts with `CALL` or `MODIN`
    // and `O` and a name, as parse reads them (no sequence name, no block
    // delete before them); 0 for any other line.
    uint32_t call_head_end(const LineRef& line);
    // Where the value of a `Pname=number` argument at `p` of `text` ends, as
    // plain_call reads it: an optional sign, then a decimal literal of at
    // most 15 digits, then a blank, a line break or the end of the text; `p`
    // when there is no such value there. (A line holds no line break: the
    // walk reads repeats from its input's buffer, where one ends the line.)
    // Inline: the walk asks it for every value of a repeated line.
    static uint32_t plain_value_end(std::string_view text, uint32_t p) {
        double unused;
        return plain_value_at<false>(text, p, unused);
    }
    // The same, and its value as parse reads it (the sign applied) in `value`.
    static uint32_t plain_value(std::string_view text, uint32_t p, double& value) {
        return plain_value_at<true>(text, p, value);
    }

    // As parse, but a plain move of the simplest shape (last_plain) is filled
    // in part: its sequence name and, of each word, the address, the range and
    // the number (what is_plain_move_block and apply_plain_move read; the
    // other fields of its words are left as they were). last_partial() says
    // so: parse the line again for the whole block. Any other line is whole.
    bool parse_moves(const LineRef& line, Block& out);
    bool last_partial() const;

    // The words of `line` when it is a plain move of the simplest shape (one
    // that parse_moves keeps in part), with at most PlainMove::kMaxWords
    // words and no sequence name but `N` and digits: what parse_moves keeps
    // of each, read by the same scan, but into `out` instead of a block, and
    // the sequence name's text and range. False for any other line (the
    // caller then parses it). For a sweep that needs only the values.
    bool plain_move(const LineRef& line, PlainMove& out);

    // Lines of the strictest shape parse_moves keeps in part: upper-case X, Y,
    // Z and F words (an optional sign, then at most 15 digits with at most one
    // point) and G0 to G3 (digits only), glued or separated by spaces, one
    // word at least, each line ended by LF, CR LF or CR. Across
    // such lines only the last word of each address decides what they leave
    // (in absolute mode, or while the mode is unknown), so a run of them is
    // read without the numbers but those.
    struct PlainRun {
        size_t bytes = 0;       // the lines read, terminators included
        size_t last_start = 0;  // where the last of them starts in the text
        uint32_t lines = 0;
        PlainMove last;         // the last word of each address met (its number read)
        bool over = false;      // it stopped before a move with a word past `int_digits`
    };
    // Reads such lines from the start of `text` (at offset `base` of the
    // file), whole lines only: at most `max_lines`, each starting before
    // `start_limit` and ending, terminator included, before `end_limit`
    // (offsets of the file). Stops before any other line. The first line is
    // line `first_line`; `every_nth(start, line)` is told the start (in
    // `text`) of each line read whose number is a multiple of `nth`.
    // `int_digits`: for X, Y and Z, the most digits a word's value may have
    // before its point (so its magnitude is below 10 to that power); the run
    // also stops before a line with a word of more (kAnyDigits: no bound).
    static constexpr uint8_t kAnyDigits = 255;
    using IntDigits = std::array<uint8_t, 3>;
    PlainRun plain_run(std::string_view text, uint32_t base, uint32_t max_lines, uint64_t start_limit,
                       uint64_t end_limit, uint32_t first_line, uint32_t nth,
                       FunctionRef<void(size_t, uint32_t)> every_nth,
                       IntDigits int_digits = {kAnyDigits, kAnyDigits, kAnyDigits});

    // Whether the last line parsed is a plain move (analyzer.h:
    // is_plain_move_block) of the simplest shape: glued literal words only. A
    // false answer proves nothing: ask is_plain_move_block then.
    bool last_plain() const { return last_plain_; }
    // Lines handled by each parser so far.
    uint64_t fast_lines() const { return fast_lines_; }
    // Of those, the CALL and MODIN lines that repeat the line filled into
    // the same block before them but for some argument values (and blanks):
    // that block was updated in place (frontend_fast_again.cpp).
    uint64_t again_lines() const;
    // Whether the last line parsed was such a line: its block differs from
    // what it held before only in its words' values and ranges (and its own
    // line and range). So long as fills() has not changed, the parser filled
    // no block in any other way since.
    bool last_again() const;
    uint64_t fills() const;
    uint64_t fallback_lines() const { return fallback_lines_; }

private:
    // What plain_value_end and plain_value share. With at most 15 digits the
    // digits as an integer and the power of ten are exact doubles, so their
    // quotient is the correctly rounded value (as the line parser computes it).
    template <bool kValue>
    [[gnu::always_inline]] static uint32_t plain_value_at(std::string_view text, uint32_t p, double& value) {
        static constexpr double kPow10[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7,
                                            1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
        const char* s = text.data();
        const uint32_t n = static_cast<uint32_t>(text.size());
        uint32_t e = p;
        bool minus = false;
        if (e < n && (s[e] == '-' || s[e] == '+')) minus = s[e++] == '-';
        uint64_t m = 0;
        const uint32_t first = e;
        unsigned d = 0;
        for (; e < n && (d = static_cast<unsigned char>(s[e]) - unsigned('0')) < 10; ++e)
            if (kValue) m = m * 10 + d;
        uint32_t digits = e - first, fraction = 0;
        if (e < n && s[e] == '.') {
            const uint32_t f = ++e;
            for (; e < n && (d = static_cast<unsigned char>(s[e]) - unsigned('0')) < 10; ++e)
                if (kValue) m = m * 10 + d;
            fraction = e - f;
            digits += fraction;
        }
        if (digits == 0 || digits > 15) return p;
        if (e < n && !value_may_end(s[e])) return p;
        if (kValue) {
            value = fraction ? static_cast<double>(m) / kPow10[fraction] : static_cast<double>(m);
            if (minus) value = -value;
        }
        return e;
    }
    // A blank or a line break.
    static bool value_may_end(char c) {
        return c == ' ' || (c >= '\t' && c <= '\r');  // tab, LF, VT, FF, CR
    }

    struct Impl;
    Impl* impl_;
    uint64_t fast_lines_ = 0;
    bool last_plain_ = false;
    uint64_t fallback_lines_ = 0;
};

// The tree-sitter front end applied to one line alone, with every offset of
// the result shifted to the line's place in its file.
void parse_line_tree_sitter(const LineRef& line, Block& out);

// Adds `delta` to every byte offset of `b` (the ranges that are set).
void shift_block(Block& b, int64_t delta);

// Calls `f(const LineRef&)` for every line of `text` that is a block: every
// terminated line, and the last line when it is not empty (the same lines
// parse_program_file makes blocks of). `base` is added to every offset and
// `first_line` is the number of the first line.
template <class F>
void for_each_line(std::string_view text, F&& f, uint32_t base = 0, uint32_t first_line = 1) {
    size_t i = 0;
    uint32_t line = first_line;
    const size_t n = text.size();
    while (i < n) {
        size_t e = i;
        while (e < n && text[e] != '\n' && text[e] != '\r') ++e;
        size_t t = e;
        if (t < n) t += (text[t] == '\r' && t + 1 < n && text[t + 1] == '\n') ? 2 : 1;
        LineRef l{text.substr(i, e - i), text.substr(e, t - e), line, static_cast<uint32_t>(base + i)};
        f(static_cast<const LineRef&>(l));
        ++line;
        i = t;
    }
}

// The whole text parsed line by line with FastLineParser: the same ProgramFile
// parse_program_file makes (used by the differential tests and the fuzzer).
ProgramFile parse_program_file_fast(std::string path, std::string text, uint64_t* fallback_lines = nullptr);

// A readable dump of every field of a block (for test and fuzzer reports).
std::string dump_block(const Block& b);

}  // namespace osplint
