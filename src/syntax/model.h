// The program model: what every rule reads.
//
// Files -> programs -> blocks. A block is one line of the part program (the
// control's unit of execution). It carries its words, assignments, statements
// and comments, each with exact byte ranges into the source text. Expressions
// live in a small per-block arena (`Block::exprs`) and are referenced by index.
//
// No front-end types appear here: the tree-sitter front end (editing) and the
// streaming front end (batch) both fill these structures, and the differential
// test compares what they produce field by field (see `operator==`).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "osplint/diagnostic.h"

namespace osplint {


using ExprId = int32_t;  // index into Block::exprs, or -1 for "none"
inline constexpr ExprId kNoExpr = -1;

enum class ExprKind : uint8_t {
    Number,    // 12, -.75 is Unary(-, Number(.75)); `number` holds the value
    HexConst,  // #81H; `number` holds the value, `text` the literal
    String,    // 'END OF BAR'; `text` holds the contents without quotes
    Empty,     // EMPTY
    Variable,  // VC12, VC[..], V5, VTOFX[16], VTOHT[a,b], PX; `text` = name as written
               // without subscripts (upper case); `children` = subscripts
    Unary,     // `op` is "-", "+" or "NOT"; one child
    Binary,    // `op` is + - * / EQ NE GT GE LT LE AND OR EOR MOD? (no: MOD is a function)
    Function,  // SIN[..] ATAN2[a,b] ...; `text` = function name; `children` = args
    Bracket,   // [ expr ]; one child
    Error,     // unparsable piece (the block also has a SyntaxError)
};

struct ExprNode {
    ExprKind kind = ExprKind::Error;
    std::string op;    // operator for Unary/Binary
    std::string text;  // variable / function name, string contents, hex literal
    double number = 0; // Number / HexConst value
    std::vector<ExprId> children;
    ByteRange range;
    friend bool operator==(const ExprNode&, const ExprNode&) = default;
};

// An address word: `X-.75`, `G0`, `M52`, `X=XPOS+8`, `FA=200`, `PR=5` (call
// argument), `Q5` (repeat count). Multi-letter names with `=` that are not
// arguments of a call are local-variable assignments: they are kept as words
// (the model cannot tell `FA=` the address from `FA=` the local) and the
// analyzer decides from context.
struct Word {
    std::string address;      // upper case: "X", "G", "FA", "PR"
    ByteRange range;          // the whole word
    ByteRange address_range;  // just the address letters
    ByteRange value_range;    // the value text (after `=` when present)
    bool equals = false;      // written `ADDR=expr`
    ExprId value = kNoExpr;   // the value as an expression
    std::optional<double> number;  // set when the value is a (signed) numeric literal
    std::string value_text;   // the value as written (e.g. "00", "-.75", "XPOS+8")
    friend bool operator==(const Word&, const Word&) = default;
};

// `VC12 = VC11 + 1`, `VTOFX[16]=VTOFX[6]`, `VUACM[1]='TEXT'`.
struct Assignment {
    ExprId target = kNoExpr;  // a Variable node
    ExprId value = kNoExpr;
    ByteRange range;
    friend bool operator==(const Assignment&, const Assignment&) = default;
};

enum class StmtKind : uint8_t {
    Call,       // CALL Oname ... ; name = "ONAME"
    Modin,      // MODIN Oname ...
    Modout,     // MODOUT
    Rts,        // RTS
    Goto,       // GOTO Nname ; name = "NNAME"
    If,         // IF [cond] Nname ; expr = cond, name = target
    While,      // WHILE [cond] DO n ; expr = cond, loop = n
    Do,         // DO n
    End,        // END n  (also bare END of schedule programs / DEF blocks: loop = -1)
    Ncyl,       // NCYL prefix
    Noex,       // NOEX prefix
    CoordCalc,  // BHC LAA ARC GRDX GRDY DGRDX DGRDY SQRX SQRY OMIT RSTRT ; name = keyword
    Mnemonic,   // any other keyword command (MSG, NMSG, DEF, CLEAR, DRAW, COPY, ...) ; name = keyword
};

struct Statement {
    StmtKind kind = StmtKind::Mnemonic;
    ByteRange range;          // the whole statement (keyword .. last operand)
    ByteRange keyword_range;  // CALL / IF / GOTO ...
    std::string name;         // call target (ONAME), jump target (NNAME), keyword
    ByteRange name_range;
    ExprId expr = kNoExpr;    // IF / WHILE condition
    int loop = -1;            // DO / END / WHILE loop number
    // The keyword and its target ("MODIN OG87C", "GOTO N10"; the keyword alone when there is none).
    ByteRange head_range() const {
        return {keyword_range.begin, name_range.empty() ? keyword_range.end : name_range.end};
    }
    friend bool operator==(const Statement&, const Statement&) = default;
};

struct Comment {
    ByteRange range;  // including the parentheses
    friend bool operator==(const Comment&, const Comment&) = default;
};

struct SyntaxError {
    ByteRange range;
    std::string message;  // "expected ..." where the front end can tell
    friend bool operator==(const SyntaxError&, const SyntaxError&) = default;
};

enum class LineKind : uint8_t {
    Block,     // an ordinary block (possibly empty or comment-only)
    TapeMark,  // `%` or `%%`
    Header,    // `$NAME.EXT%` tape header
};

struct Label {
    std::string name;  // upper case, with its letter: "N100", "NSTOP", "OZAGR"
    ByteRange range;
    friend bool operator==(const Label&, const Label&) = default;
};

struct Block {
    LineKind kind = LineKind::Block;
    uint32_t line = 0;        // 1-based line number of the block
    uint32_t line_start = 0;  // byte offset of the start of that line
    ByteRange range;          // the line without its terminator
    std::optional<Label> program_name;  // `OTEST` starting a program
    std::optional<Label> sequence;      // `N100` / `NSTOP` at the block start
    bool block_delete = false;          // `/`
    ByteRange block_delete_range;
    std::vector<Word> words;
    std::vector<Assignment> assignments;
    std::vector<Statement> statements;
    std::vector<Comment> comments;
    std::vector<ExprNode> exprs;
    std::vector<SyntaxError> errors;

    // True when the block has nothing the control executes (blank / comments only).
    bool is_empty() const {
        return kind == LineKind::Block && !program_name && !sequence && words.empty() &&
               assignments.empty() && statements.empty();
    }
    const ExprNode* expr(ExprId id) const {
        return id >= 0 && static_cast<size_t>(id) < exprs.size() ? &exprs[id] : nullptr;
    }
    // First word with this address (upper case), or nullptr.
    const Word* find(std::string_view address) const {
        for (const auto& w : words)
            if (w.address == address) return &w;
        return nullptr;
    }
    // Whether a word `address` with this exact numeric value is present (G/M codes).
    bool has_code(std::string_view address, double value) const {
        for (const auto& w : words)
            if (w.address == address && w.number && *w.number == value) return true;
        return false;
    }
    const Statement* statement(StmtKind k) const {
        for (const auto& s : statements)
            if (s.kind == k) return &s;
        return nullptr;
    }
    friend bool operator==(const Block&, const Block&) = default;
};

// The commonest block of a posted program, read without building it: a
// plain move of the simplest shape (`X-53.7 Y-40. F2500`, glued words with
// literal values, G0 to G3 and X, Y, Z, F only, after an optional sequence
// number `N120`), as FastLineParser::plain_move reads it. Its words are those
// the Block of the same line would have, with their address, signed number
// and range only; its sequence number is the Block's Label.
struct PlainMoveWord {
    char address = 0;   // X, Y, Z, F or G
    double number = 0;  // with its sign
    ByteRange range;    // the whole word
};
struct PlainMove {
    static constexpr size_t kMaxWords = 8;
    std::array<PlainMoveWord, kMaxWords> words;
    size_t count = 0;
    // `N` and digits as written (the Label's name), in the parsed line's
    // text; empty when the line has no sequence name.
    std::string_view sequence;
    ByteRange sequence_range;
    const PlainMoveWord* begin() const { return words.data(); }
    const PlainMoveWord* end() const { return words.data() + count; }
};

// A program inside a file: from its `O` name (or the file start when the name
// is omitted) to the block before the next program name.
struct Program {
    std::string name;      // "OTEST", empty when the file starts without a name
    ByteRange name_range;
    uint32_t first_block = 0;  // index into ProgramFile::blocks
    uint32_t end_block = 0;    // one past the last block
    friend bool operator==(const Program&, const Program&) = default;
};

}  // namespace osplint
