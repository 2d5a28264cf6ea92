// FastLineParser::Impl (frontend_fast.h): the hand-written parser's state
// and the utilities its parts share (frontend_fast_lexer.h lists the files).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "syntax/frontend_fast.h"
#include "syntax/frontend_fast_lexer.h"

namespace osplint {

struct FastLineParser::Impl {
    fast_detail::Recycler<ExprNode> expr_pool;
    fast_detail::Recycler<Word> word_pool;
    size_t exprs_used = 0;
    size_t words_used = 0;
    size_t exprs_have = 0;  // b->exprs.size(), kept here (the hot paths compare with it)
    size_t words_have = 0;  // b->words.size()

    const char* s = nullptr;
    uint32_t n = 0;
    uint32_t base = 0;
    Block* b = nullptr;
    int depth = 0;  // bracket nesting inside an expression
    bool plain = false;  // the last line is a plain move (simple_line)
    bool sentinel = false;  // the terminator follows the text in memory (simple_line_in)
    bool outline = false;   // parse_outline: plain CALL arguments are skipped
    bool moves_only = false;  // parse_moves: simple_line keeps a plain move in part, fails on anything else
    bool partial = false;     // the last line was kept in part (parse_moves)
    // Deeper lines are left to the tree-sitter front end (bounded recursion here).
    static constexpr int kMaxDepth = 64;

    enum class Ctx { Block, CallArgs };

    // ------------------------------------------------------------ utilities

    uint32_t skip_blanks(uint32_t p) const {
        while (p < n && fast_detail::is_blank(s[p])) ++p;
        return p;
    }

    ByteRange abs(uint32_t b0, uint32_t e0) const { return {base + b0, base + e0}; }

    // A comment at p (s[p] == '('): its end, or kFail when it is not closed on
    // the line or holds a control character.
    uint32_t comment(uint32_t p) {
        uint32_t q = p + 1;
#if defined(__SSE2__)
        // 16 bytes at a time up to the first `)` or control byte (a tab aside).
        const __m128i close = _mm_set1_epi8(')'), tab = _mm_set1_epi8('\t'), del = _mm_set1_epi8(0x7F);
        const __m128i space = _mm_set1_epi8(0x20);
        for (; n - q >= 16; q += 16) {
            const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s + q));
            // Bytes below 0x20 as unsigned: those whose saturated difference from 0x20 is not zero.
            const __m128i control = _mm_andnot_si128(_mm_cmpeq_epi8(v, tab),
                                                     _mm_xor_si128(_mm_cmpeq_epi8(_mm_subs_epu8(space, v), _mm_setzero_si128()),
                                                                   _mm_set1_epi8(-1)));
            const __m128i stop = _mm_or_si128(_mm_or_si128(_mm_cmpeq_epi8(v, close), _mm_cmpeq_epi8(v, del)), control);
            if (const unsigned m = static_cast<unsigned>(_mm_movemask_epi8(stop))) {
                q += static_cast<uint32_t>(__builtin_ctz(m));
                break;
            }
        }
#endif
        while (q < n && s[q] != ')') {
            const auto c = static_cast<unsigned char>(s[q]);
            if ((c < 0x20 && c != '\t') || c == 0x7F) return fast_detail::kFail;
            ++q;
        }
        if (q >= n) return fast_detail::kFail;
        b->comments.push_back(Comment{abs(p, q + 1)});
        return q + 1;
    }

    // Skips blanks and comments (recording the comments).
    uint32_t skip_extras(uint32_t p) {
        while (true) {
            p = skip_blanks(p);
            if (p < n && s[p] == '(') {
                p = comment(p);
                if (p == fast_detail::kFail) return fast_detail::kFail;
                continue;
            }
            return p;
        }
    }

    // A node at the end of the arena. `op` is the operator of Unary/Binary
    // nodes; a Variable's text is set by the caller.
    OSPLINT_HOT ExprNode& new_expr(ExprKind kind, ByteRange r, char op = '\0') {
        ExprNode& e = exprs_used < exprs_have ? b->exprs[exprs_used++] : take_expr();
        e.kind = kind;
        if (op) fast_detail::set_char(e.op, op);
        else if (!e.op.empty()) e.op.clear();
        if (kind != ExprKind::Variable && !e.text.empty()) e.text.clear();
        e.number = 0;
        if (kind != ExprKind::Unary && kind != ExprKind::Bracket && !e.children.empty()) e.children.clear();
        e.range = r;
        return e;
    }
    ExprId last_expr() const { return static_cast<ExprId>(exprs_used - 1); }
    ExprNode& take_expr() {
        ExprNode& e = expr_pool.take(b->exprs, exprs_used);
        exprs_have = b->exprs.size();
        return e;
    }
    Word& take_word() {
        Word& w = word_pool.take(b->words, words_used);
        words_have = b->words.size();
        return w;
    }

    // A word at the end of the block; the caller sets its address and value text.
    OSPLINT_HOT Word& new_word() {
        Word& w = words_used < words_have ? b->words[words_used++] : take_word();
        w.equals = false;
        w.value = kNoExpr;
        w.number.reset();
        return w;
    }

    std::optional<double> literal_value(ExprId id) const {
        const ExprNode& e = b->exprs[static_cast<size_t>(id)];
        if (e.kind == ExprKind::Number) return e.number;
        if (e.kind == ExprKind::Unary && (e.op == "-" || e.op == "+") && e.children.size() == 1) {
            const ExprNode& inner = b->exprs[static_cast<size_t>(e.children[0])];
            if (inner.kind == ExprKind::Number) return e.op == "-" ? -inner.number : inner.number;
        }
        return std::nullopt;
    }

    // The end of the letters-and-digits run starting at p.
    uint32_t alnum_end(uint32_t p) const {
        while (p < n && fast_detail::is_alnum(s[p])) ++p;
        return p;
    }

    // Upper-case copy of a name (at most kNameMax characters).
    struct Name {
        char text[fast_detail::kNameMax + 1];
        uint32_t len = 0;
        std::string_view view() const { return {text, len}; }
    };
    // A `Pname=number` call argument at p: the end of its name, where its
    // value (sign included) and its digits begin, its end, and the digits'
    // value. Nothing is emitted.
    struct PlainArg {
        uint32_t name_end = 0;
        uint32_t value_begin = 0;
        uint32_t digits_begin = 0;  // after the sign
        uint32_t end = 0;
        double value = 0;  // of the digits, unsigned
    };
    template <bool kValue>
    bool plain_arg(uint32_t p, PlainArg& a) const;
    // Whether [p, n) holds only `Pname=number` arguments (parse_outline).
    bool plain_call_args(uint32_t p) const;
    // Whether the line is `CALL`/`MODIN`, `O` and a name, then such arguments only.
    bool plain_call_line() const;
    // Where `CALL`/`MODIN` and `O` and a name end at the line's start; 0 when they do not.
    uint32_t call_head() const;
    // The word of a plain argument, as assignment() makes it.
    uint32_t plain_arg_word(uint32_t p, const PlainArg& a);
    bool read_name(uint32_t p, uint32_t e, Name& out) const {
        if (e - p > fast_detail::kNameMax) return false;
        out.len = e - p;
        for (uint32_t i = 0; i < out.len; ++i) out.text[i] = fast_detail::upper(s[p + i]);
        out.text[out.len] = '\0';
        // `DO1`, `END1`: the scanner may split a loop number off these.
        if (out.len >= 3 && out.text[0] == 'D' && out.text[1] == 'O' && fast_detail::is_digit(out.text[2])) return false;
        if (out.len >= 4 && out.text[0] == 'E' && out.text[1] == 'N' && out.text[2] == 'D' && fast_detail::is_digit(out.text[3]))
            return false;
        return true;
    }

    // --- Expressions (frontend_fast_expr.cpp) --------------------------------------

    uint32_t number(uint32_t p);
    uint32_t subscripts(uint32_t name_begin, const Name& name, uint32_t open);
    uint32_t unary(uint32_t p);
    static int precedence(char c);
    bool may_end_here(uint32_t p) const;
    uint32_t expr(uint32_t p, int min_prec);

    // --- Block items (frontend_fast.cpp) -------------------------------------------

    OSPLINT_HOT uint32_t word_number(Word& w, uint32_t p);
    OSPLINT_HOT void number_value(Word& w, uint32_t p, uint32_t digits, uint32_t e, double v);
    uint32_t assignment(uint32_t p, uint32_t e, const Name& name, Ctx ctx);
    Word& assigned_word(size_t wi, uint32_t p, uint32_t e);
    uint32_t label_word(uint32_t p, uint32_t e);
    uint32_t keyword_statement(StmtKind kind, uint32_t p, uint32_t e);
    uint32_t call_statement(StmtKind kind, uint32_t p, uint32_t e);
    uint32_t control_statement(const Name& name, uint32_t p, uint32_t e);
    uint32_t jump_target(uint32_t p, Statement& st) const;
    uint32_t loop_number(uint32_t p, int& loop) const;
    static int keyword_precedence(const Name& name);
    static bool is_glued_word(const char* s, uint32_t p, uint32_t n);
    OSPLINT_HOT uint32_t glued_word(uint32_t p);
    uint32_t named_item(uint32_t p, Ctx ctx);
    uint32_t letter_assignment(uint32_t p, char c);
    uint32_t item(uint32_t p, Ctx ctx);

    // --- A call line again (frontend_fast_again.cpp) ------------------------------

    // Where a plain argument (`PX=12.5`) of the line lies: its start, the end
    // of its name, where its value (sign included) begins, and its end.
    struct CallArg {
        uint32_t begin = 0;
        uint32_t name_end = 0;
        uint32_t value_begin = 0;
        uint32_t end = 0;
        bool sign = false;
        bool changed = false;  // again_call: its text is not the last line's
    };
    // The arguments call_statement read, while each is plain (call_plain).
    std::vector<CallArg> call_args;
    bool call_plain = false;
    // The last line filled into `block` when it is a CALL or MODIN at the
    // line's start with plain arguments only, and nothing else: `text` is
    // the line, `args` where its arguments lie.
    struct Again {
        const Block* block = nullptr;
        std::string text;
        uint32_t keyword_end = 0;
        uint32_t name_begin = 0;
        uint32_t head = 0;  // where the name ends
        ByteRange range;    // the block's range when it was filled
        size_t exprs = 0;
        std::vector<CallArg> args;
    };
    Again again;
    uint64_t again_lines = 0;
    std::string last_head;  // the line's start up to the end of the name call_head_end found last, if it did
    bool again_last = false;  // the last line was again_call's
    uint64_t fills = 0;       // the lines run() parsed whole (not again_call's)
    std::vector<double> digits;  // again_call's scratch: each argument's digits' value
    // After a line was parsed whole into b: keeps it as `again` when it is
    // such a call line, forgets `again` otherwise.
    void keep_call(bool ok);
    // When `line` is `again`'s line but for the text of some argument values
    // (and the blanks between arguments), each still a plain number: updates `out`, the block `again` was filled
    // into and that nobody changed since, to the block of `line` in place.
    // False (with `out` to be parsed again) for any other line.
    bool again_call(const LineRef& line, Block& out);

    // --- Prefix: sequence and program names ----------------------------------------

    uint32_t sequence(uint32_t p);
    uint32_t program_name(uint32_t p);
    void set_label(std::optional<Label>& out, uint32_t p, uint32_t e);

    // --- Whole lines ---------------------------------------------------------------

    bool run(const LineRef& line, Block& out, bool moves = false);
    void start(const LineRef& line);
    void restart();
    bool simple_line();
    // With kValues, the words go to `values` (plain_move), not to the block.
    template <bool kSentinel, bool kValues = false>
    bool simple_line_in();
    PlainMove* values = nullptr;
    bool parse_line();
};

}  // namespace osplint
