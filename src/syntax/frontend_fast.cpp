// The hand-written block parser (see frontend_fast.h): block items, the
// prefix of a line (block delete, sequence or program name), and whole lines,
// with the shape CAM post-processors write by the million taken in one pass.
// Expressions are in frontend_fast_expr.cpp, the lexical layer in
// frontend_fast_lexer.h.
//
// Every decision below mirrors the grammar (grammar/grammar.js), its external
// scanner (grammar/src/scanner.c) and the tree-sitter converter
// (syntax/frontend_ts_convert.cpp): which token a run of letters becomes, which
// ranges a node covers, in which order expression nodes enter the block's
// arena. Wherever the outcome would depend on something this parser does not
// model, it gives up and the line goes to the tree-sitter front end.
#include "syntax/frontend_fast.h"

#include <cstring>

#include "syntax/frontend.h"
#include "syntax/frontend_fast_parser.h"

namespace osplint {

using namespace fast_detail;

// ------------------------------------------------------------------ items

// The glued number of `X-.75` at p: a Number (signed: Unary over it).
OSPLINT_HOT uint32_t FastLineParser::Impl::word_number(Word& w, uint32_t p) {
    uint32_t j = p;
    if (j < n && (s[j] == '+' || s[j] == '-')) ++j;
    const uint32_t digits = j;
    double v = 0;
    j = scan_number_at(s, digits, n, v);
    if (j == digits || (j < n && s[j] == '.')) return kFail;
    number_value(w, p, digits, j, v);
    return j;
}

// The value of a word scanned at [p, e), the digits from `digits` on (a sign
// before them): a Number node, under a Unary one when signed.
OSPLINT_HOT void FastLineParser::Impl::number_value(Word& w, uint32_t p, uint32_t digits, uint32_t e, double v) {
    const char sign = digits > p ? s[p] : 0;
    ExprNode& num = new_expr(ExprKind::Number, abs(digits, e));
    num.number = v;
    const ExprId num_id = last_expr();
    if (sign) {
        ExprNode& un = new_expr(ExprKind::Unary, abs(p, e), sign);
        set_child(un.children, num_id);
        w.value = last_expr();
        w.number = sign == '-' ? -v : v;
    } else {
        w.value = num_id;
        w.number = v;
    }
    w.value_range = abs(p, e);
    set_text(w.value_text, s + p, e - p);
}

// `NAME = expr` or `NAME[..] = expr` with the name at [p, e).
uint32_t FastLineParser::Impl::assignment(uint32_t p, uint32_t e, const Name& name, Ctx ctx) {
    const uint32_t r = skip_blanks(e);
    if (r >= n) return kFail;
    if (s[r] == '[') {
        const size_t assignments = b->assignments.size();
        b->assignments.emplace_back();
        uint32_t q = subscripts(p, name, r);
        if (q == kFail) return kFail;
        const ExprId target = last_expr();
        q = skip_blanks(q);
        if (q >= n || s[q] != '=') return kFail;
        q = expr(q + 1, 0);
        if (q == kFail) return kFail;
        const ExprId value = last_expr();
        Assignment& a = b->assignments[assignments];
        a.target = target;
        a.value = value;
        a.range = {base + p, b->exprs[static_cast<size_t>(value)].range.end};
        return q;
    }
    if (s[r] != '=') return kFail;
    if (ctx == Ctx::Block && name.text[0] == 'V') {
        ExprNode& v = new_expr(ExprKind::Variable, abs(p, e));
        set_text(v.text, name.text, name.len);
        const ExprId target = last_expr();
        const uint32_t q = expr(r + 1, 0);
        if (q == kFail) return kFail;
        const ExprId value = last_expr();
        Assignment a;
        a.target = target;
        a.value = value;
        a.range = {base + p, b->exprs[static_cast<size_t>(value)].range.end};
        b->assignments.push_back(a);
        return q;
    }
    const size_t wi = words_used;
    new_word();
    const uint32_t q = expr(r + 1, 0);
    if (q == kFail) return kFail;
    set_text(assigned_word(wi, p, e).address, name.text, name.len);
    return q;
}

// The word `wi` of an assignment whose name is at [p, e) and whose value is
// the last expression read; its address is the caller's to set.
Word& FastLineParser::Impl::assigned_word(size_t wi, uint32_t p, uint32_t e) {
    Word& w = b->words[wi];
    const ExprId value = last_expr();
    const ByteRange vr = b->exprs[static_cast<size_t>(value)].range;
    w.range = {base + p, vr.end};
    w.address_range = abs(p, e);
    w.equals = true;
    w.value = value;
    w.value_range = vr;
    set_text(w.value_text, s + (vr.begin - base), vr.size());
    w.number = literal_value(value);
    return w;
}

// `N0207` / `NAT3` inside a block: a word with address N, value = the rest.
uint32_t FastLineParser::Impl::label_word(uint32_t p, uint32_t e) {
    Word& w = new_word();
    set_char(w.address, 'N');
    w.range = abs(p, e);
    w.address_range = abs(p, p + 1);
    w.value_range = abs(p + 1, e);
    w.value_text.clear();
    bool digits = true;
    for (uint32_t i = p + 1; i < e; ++i) {
        w.value_text.push_back(upper(s[i]));
        digits = digits && is_digit(s[i]);
    }
    if (digits && e > p + 1) {
        const std::optional<double> v = decimal_literal_value(std::string_view(s + p + 1, e - p - 1));
        if (!v) return kFail;  // too large: the tree-sitter front end reports it
        const size_t wi = words_used - 1;
        ExprNode& num = new_expr(ExprKind::Number, abs(p + 1, e));
        num.number = *v;
        Word& ww = b->words[wi];
        ww.number = num.number;
        ww.value = last_expr();
    }
    return e;
}

uint32_t FastLineParser::Impl::keyword_statement(StmtKind kind, uint32_t p, uint32_t e) {
    Statement st;
    st.kind = kind;
    st.range = abs(p, e);
    st.keyword_range = st.range;
    b->statements.push_back(std::move(st));
    return e;
}

// CALL / MODIN Oname args...: takes the rest of the line.
uint32_t FastLineParser::Impl::call_statement(StmtKind kind, uint32_t p, uint32_t e) {
    const size_t index = b->statements.size();
    keyword_statement(kind, p, e);
    uint32_t q = skip_blanks(e);
    if (q + 1 >= n || (s[q] != 'O' && s[q] != 'o') || !is_alnum(s[q + 1])) return kFail;
    const uint32_t r = alnum_end(q + 1);
    {
        Statement& st = b->statements[index];
        st.name.resize(r - q);
        for (uint32_t i = q; i < r; ++i) st.name[i - q] = upper(s[i]);
        st.name_range = abs(q, r);
    }
    uint32_t end = r;
    uint32_t pos = r;
    if (outline && plain_call_args(r)) return n;
    // Whether every argument is plain, as keep_call wants them.
    call_plain = index == 0 && p == 0;
    call_args.clear();
    while (true) {
        pos = skip_blanks(pos);
        if (pos >= n) break;
        if (s[pos] == '(') {
            call_plain = false;
            pos = comment(pos);
            if (pos == kFail) return kFail;
            continue;
        }
        if (!is_letter(s[pos])) return kFail;
        // `PX=12.5`, the argument posts write by the million, without the
        // general path's keyword and operator checks: its expression ends
        // there when the line does or another P name follows.
        PlainArg a;
        const bool plain = plain_arg<true>(pos, a);
        const uint32_t next = plain ? skip_blanks(a.end) : n;
        if (plain && (next >= n || upper(s[next]) == 'P')) {
            if (call_plain) call_args.push_back({pos, a.name_end, a.value_begin, a.end, a.digits_begin > a.value_begin, false});
            pos = plain_arg_word(pos, a);
        } else {
            call_plain = false;
            pos = item(pos, Ctx::CallArgs);
        }
        if (pos == kFail) return kFail;
        end = pos;
    }
    b->statements[index].range = abs(p, end);
    return n;
}

// GOTO Nname, IF [cond] [GOTO] Nname, WHILE [cond] DO n, DO n, END [n],
// with the keyword at [p, e). A comment inside the statement, a loop number
// that is not plain digits, or a target the scanner might lex otherwise
// sends the line to the tree-sitter front end.
uint32_t FastLineParser::Impl::control_statement(const Name& name, uint32_t p, uint32_t e) {
    const std::string_view kw = name.view();
    StmtKind kind;
    if (kw == "GOTO") kind = StmtKind::Goto;
    else if (kw == "IF") kind = StmtKind::If;
    else if (kw == "WHILE") kind = StmtKind::While;
    else if (kw == "DO") kind = StmtKind::Do;
    else if (kw == "END") kind = StmtKind::End;
    else return kFail;  // EMPTY, NOT, EQ ... where an item belongs
    const size_t index = b->statements.size();
    keyword_statement(kind, p, e);
    uint32_t q = e;
    ExprId cond = kNoExpr;
    if (kind == StmtKind::If || kind == StmtKind::While) {
        q = skip_blanks(q);
        if (q >= n || s[q] != '[') return kFail;
        q = expr(q + 1, 0);
        if (q == kFail) return kFail;
        cond = last_expr();
        q = skip_blanks(q);
        if (q >= n || s[q] != ']') return kFail;
        ++q;
    }
    uint32_t end = e;
    int loop = -1;
    if (kind == StmtKind::If || kind == StmtKind::Goto) {
        q = skip_blanks(q);
        if (kind == StmtKind::If && q + 4 <= n && upper(s[q]) == 'G' && upper(s[q + 1]) == 'O' &&
            upper(s[q + 2]) == 'T' && upper(s[q + 3]) == 'O' && (q + 4 == n || is_blank(s[q + 4])))
            q = skip_blanks(q + 4);
        end = jump_target(q, b->statements[index]);
    } else if (kind == StmtKind::While) {
        q = skip_blanks(q);
        if (q + 2 > n || upper(s[q]) != 'D' || upper(s[q + 1]) != 'O' || (q + 2 < n && !is_blank(s[q + 2])))
            return kFail;
        end = loop_number(skip_blanks(q + 2), loop);
    } else if (kind == StmtKind::Do) {
        end = loop_number(skip_blanks(q), loop);
    } else {
        // END takes a number that follows it; otherwise it stands alone.
        const uint32_t r = skip_blanks(q);
        if (r < n && is_digit(s[r])) end = loop_number(r, loop);
    }
    if (end == kFail) return kFail;
    Statement& st = b->statements[index];
    st.range = abs(p, end);
    st.expr = cond;
    st.loop = loop;
    return end;
}

// The sequence name a jump goes to, at p: `N` and digits, or `N` and a name
// that no `=` or `[` follows; sets the statement's name. Returns its end.
uint32_t FastLineParser::Impl::jump_target(uint32_t p, Statement& st) const {
    if (p + 1 >= n || upper(s[p]) != 'N' || !is_alnum(s[p + 1])) return kFail;
    uint32_t e = p + 1;
    if (is_digit(s[p + 1])) {
        while (e < n && is_digit(s[e])) ++e;
        if (e < n && (is_alnum(s[e]) || s[e] == '.')) return kFail;  // `N10A`: two tokens to the scanner
    } else {
        e = alnum_end(p);
        Name name;
        if (!read_name(p, e, name) || control_keyword(name.text, name.len) != Keyword::None) return kFail;
        const uint32_t after = skip_blanks(e);
        if (after < n && (s[after] == '=' || s[after] == '[')) return kFail;
    }
    st.name.resize(e - p);
    for (uint32_t i = p; i < e; ++i) st.name[i - p] = upper(s[i]);
    st.name_range = abs(p, e);
    return e;
}

// A loop number at p: plain digits (at most nine), nothing glued after them.
uint32_t FastLineParser::Impl::loop_number(uint32_t p, int& loop) const {
    uint32_t e = p;
    int v = 0;
    while (e < n && is_digit(s[e]) && e - p < 9) v = v * 10 + (s[e++] - '0');
    if (e == p || (e < n && (is_alnum(s[e]) || s[e] == '.'))) return kFail;
    loop = v;
    return e;
}

// `Pname=number` at p: a name of P, a letter, then letters or digits (no
// keyword starts with P, and `=` follows it), then an optional sign and a
// decimal literal of at most 15 digits, followed by a blank or the end. The
// number is valued as it is scanned (plain_arg_word does not read it again),
// with kValue; the outline, which only asks whether the line is such, leaves
// a.value unset.
template <bool kValue>
bool FastLineParser::Impl::plain_arg(uint32_t p, PlainArg& a) const {
    const auto cls = [&](uint32_t i) { return kClass[static_cast<unsigned char>(s[i])]; };
    if ((s[p] | 0x20) != 'p' || p + 1 >= n || !(cls(p + 1) & kLetterClass)) return false;  // `P1=`: a glued word
    uint32_t e = p + 2;
    while (e < n && (cls(e) & (kLetterClass | kDigitClass))) ++e;
    if (e - p > kNameMax) return false;
    a.name_end = e;
    p = e;
    while (p < n && (cls(p) & kBlankClass)) ++p;
    if (p >= n || s[p] != '=') return false;
    ++p;
    while (p < n && (cls(p) & kBlankClass)) ++p;
    a.value_begin = p;
    if (p < n && (s[p] == '+' || s[p] == '-')) ++p;
    a.digits_begin = p;
    if (p < n && (s[p] == '+' || s[p] == '-')) return false;  // a second sign
    // The digits' value, unsigned (number_value applies the sign).
    const uint32_t end = FastLineParser::plain_value_at<kValue>(std::string_view(s, n), p, a.value);
    if (end == p) return false;
    a.end = end;
    return true;
}

// Blanks and `Pname=number` items up to the end of the line.
bool FastLineParser::Impl::plain_call_args(uint32_t p) const {
    PlainArg a;
    while (true) {
        p = skip_blanks(p);
        if (p >= n) return true;
        if (!plain_arg<false>(p, a)) return false;
        p = a.end;
    }
}

// The path parse_line takes through such a line (its first item is the
// keyword, call_statement reads the name), with nothing emitted.
uint32_t FastLineParser::Impl::call_head() const {
    if (n == 0 || !is_letter(s[0])) return 0;
    const uint32_t e = alnum_end(0);
    Name name;
    if (!read_name(0, e, name)) return 0;
    const Keyword kw = control_keyword(name.text, name.len);
    if (kw != Keyword::Call && kw != Keyword::Modin) return 0;
    const uint32_t q = skip_blanks(e);
    if (q + 1 >= n || (s[q] != 'O' && s[q] != 'o') || !is_alnum(s[q + 1])) return 0;
    return alnum_end(q + 1);
}

bool FastLineParser::Impl::plain_call_line() const {
    const uint32_t head = call_head();
    return head != 0 && plain_call_args(head);
}

uint32_t FastLineParser::Impl::plain_arg_word(uint32_t p, const PlainArg& a) {
    Name name;
    read_name(p, a.name_end, name);  // a P name: no loop keyword to split
    Word& w = new_word();
    number_value(w, a.value_begin, a.digits_begin, a.end, a.value);
    set_text(w.address, name.text, name.len);
    w.range = {base + p, w.value_range.end};
    w.address_range = abs(p, a.name_end);
    w.equals = true;
    return a.end;
}

// `X-.75`: a letter other than N, O and V directly followed by a number
// (the most common item by far).
bool FastLineParser::Impl::is_glued_word(const char* s, uint32_t p, uint32_t n) {
    if (p + 1 >= n) return false;
    const char c = upper(s[p]);
    const char nx = s[p + 1];
    return c >= 'A' && c <= 'Z' && c != 'N' && c != 'O' && c != 'V' &&
           (is_digit(nx) || nx == '-' || nx == '+' || nx == '.');
}

OSPLINT_HOT uint32_t FastLineParser::Impl::glued_word(uint32_t p) {
    Word& w = new_word();
    set_char(w.address, upper(s[p]));
    w.address_range = abs(p, p + 1);
    const uint32_t e = word_number(w, p + 1);
    if (e == kFail) return kFail;
    w.range = abs(p, e);
    return e;
}

// An item whose name has two letters or more at p: a statement keyword
// (CALL, MODIN, MODOUT, RTS, NCYL, NOEX), `HA`-style words, a label word
// (`NAT3`), or a named assignment (`PX=0`, `VC1=2`, `VTOFX[16]=...`).
uint32_t FastLineParser::Impl::named_item(uint32_t p, Ctx ctx) {
    const uint32_t e = alnum_end(p);
    Name name;
    if (!read_name(p, e, name)) return kFail;
    const uint32_t after = skip_blanks(e);
    const bool operand_follows = after < n && (s[after] == '=' || s[after] == '[');
    const Keyword kw = control_keyword(name.text, name.len);
    if (kw != Keyword::None) {
        if (ctx != Ctx::Block) return kFail;
        switch (kw) {
            case Keyword::Call: return call_statement(StmtKind::Call, p, e);
            case Keyword::Modin: return call_statement(StmtKind::Modin, p, e);
            case Keyword::Modout: return keyword_statement(StmtKind::Modout, p, e);
            case Keyword::Rts: return keyword_statement(StmtKind::Rts, p, e);
            case Keyword::Ncyl: return keyword_statement(StmtKind::Ncyl, p, e);
            case Keyword::Noex: return keyword_statement(StmtKind::Noex, p, e);
            case Keyword::Control: return control_statement(name, p, e);
            default: return kFail;
        }
    }
    if (!operand_follows && command_keyword(name.text, name.len)) return kFail;
    if (name.len == 2 && !operand_follows && (name.text[0] == 'H' || name.text[0] == 'D') &&
        (name.text[1] == 'A' || name.text[1] == 'C')) {
        // `HA`: address H, value "A", no number.
        Word& w = new_word();
        set_char(w.address, name.text[0]);
        w.range = abs(p, e);
        w.address_range = abs(p, p + 1);
        w.value_range = abs(p + 1, e);
        set_char(w.value_text, name.text[1]);
        return e;
    }
    if (name.text[0] == 'N' && !operand_follows) {
        if (ctx != Ctx::Block) return kFail;
        return label_word(p, e);
    }
    if (name.text[0] == 'O' && !operand_follows) return kFail;
    return assignment(p, e, name, ctx);
}

// `X=expr` / `X = expr` at p: a word of address `c` with an expression value.
uint32_t FastLineParser::Impl::letter_assignment(uint32_t p, char c) {
    const uint32_t q = p + 1;
    const uint32_t r = skip_blanks(q);
    if (r >= n || s[r] != '=') return kFail;
    const size_t wi = words_used;
    new_word();
    const uint32_t e = expr(r + 1, 0);
    if (e == kFail) return kFail;
    set_char(assigned_word(wi, p, q).address, c);
    return e;
}

// One item at p (a letter).
uint32_t FastLineParser::Impl::item(uint32_t p, Ctx ctx) {
    if (is_glued_word(s, p, n)) return glued_word(p);
    const char c = upper(s[p]);
    const uint32_t q = p + 1;
    if (q < n && is_letter(s[q])) return named_item(p, ctx);
    // The letter O is never an address (`S15O0` is a typo for S1500).
    if (c == 'O') return kFail;
    const char nx = q < n ? s[q] : '\0';
    if (is_digit(nx)) {
        if (c == 'N' && ctx == Ctx::Block) {
            uint32_t e = q;
            while (e < n && is_digit(s[e])) ++e;
            return label_word(p, e);
        }
        if (c == 'V') {
            uint32_t e = q;
            while (e < n && is_digit(s[e])) ++e;
            if (e - p > kNameMax) return kFail;
            Name name;
            name.len = e - p;
            for (uint32_t i = 0; i < name.len; ++i) name.text[i] = upper(s[p + i]);
            return assignment(p, e, name, ctx);
        }
    }
    if (is_digit(nx) || nx == '+' || nx == '-' || nx == '.') return glued_word(p);
    if (nx == '=' || is_blank(nx)) return letter_assignment(p, c);
    return kFail;
}

// ---------------------------------------------------------------- prefix

// A sequence name at p (s[p] is N/n), or p when there is none.
uint32_t FastLineParser::Impl::sequence(uint32_t p) {
    if (p + 1 >= n) return p;
    if (is_digit(s[p + 1])) {
        uint32_t e = p + 1;
        while (e < n && is_digit(s[e])) ++e;
        set_label(b->sequence, p, e);
        return e;
    }
    if (!is_letter(s[p + 1])) return p;
    const uint32_t e = alnum_end(p);
    Name name;
    if (!read_name(p, e, name)) return kFail;
    if (control_keyword(name.text, name.len) != Keyword::None) return p;  // NCYL, NOEX ... : items
    const uint32_t after = skip_blanks(e);
    const bool operand_follows = after < n && (s[after] == '=' || s[after] == '[');
    if (operand_follows) return p;  // `NAT=1`: an assignment
    if (command_keyword(name.text, name.len)) return kFail;
    set_label(b->sequence, p, e);
    return e;
}

// A program name at p (s[p] is O/o), or p when there is none.
uint32_t FastLineParser::Impl::program_name(uint32_t p) {
    if (p + 1 >= n) return p;
    if (is_digit(s[p + 1])) {
        const uint32_t e = alnum_end(p + 1);
        set_label(b->program_name, p, e);
        return e;
    }
    if (!is_letter(s[p + 1])) return p;
    const uint32_t e = alnum_end(p);
    Name name;
    if (!read_name(p, e, name)) return kFail;
    if (control_keyword(name.text, name.len) != Keyword::None) return kFail;
    const uint32_t after = skip_blanks(e);
    const bool operand_follows = after < n && (s[after] == '=' || s[after] == '[');
    if (operand_follows) return p;  // `OG=1`: an assignment
    if (command_keyword(name.text, name.len)) return kFail;
    set_label(b->program_name, p, e);
    return e;
}

void FastLineParser::Impl::set_label(std::optional<Label>& out, uint32_t p, uint32_t e) {
    if (!out) out.emplace();
    out->name.resize(e - p);
    for (uint32_t i = p; i < e; ++i) out->name[i - p] = upper(s[i]);
    out->range = abs(p, e);
}

// ------------------------------------------------------------------ line

void FastLineParser::Impl::start(const LineRef& line) {
    s = line.text.data();
    n = static_cast<uint32_t>(line.text.size());
    base = line.start;
    sentinel = !line.terminator.empty() && line.terminator.data() == line.text.data() + line.text.size();
}

bool FastLineParser::Impl::run(const LineRef& line, Block& out, bool moves) {
    start(line);
    b = &out;
    if (again.block == &out && !outline && again_call(line, out)) {
        plain = false;
        partial = false;
        ++again_lines;
        again_last = true;
        return true;
    }
    again_last = false;
    ++fills;
    depth = 0;
    exprs_used = 0;
    words_used = 0;
    exprs_have = out.exprs.size();
    words_have = out.words.size();
    out.kind = LineKind::Block;
    out.line = line.line;
    out.line_start = line.start;
    out.range = {line.start, line.start + n};
    out.program_name.reset();
    out.sequence.reset();
    out.block_delete = false;
    out.block_delete_range = {};
    out.assignments.clear();
    out.statements.clear();
    out.comments.clear();
    out.errors.clear();
    plain = false;
    partial = false;
    call_plain = false;
    bool ok = false;
    if (moves) {
        moves_only = true;
        ok = simple_line();
        moves_only = false;
        partial = ok && plain;
        if (!ok) restart();
    }
    if (!ok) ok = simple_line();
    if (!ok) {
        // Start again with the general parser.
        restart();
        ok = parse_line();
    }
    word_pool.finish(out.words, words_used);
    expr_pool.finish(out.exprs, exprs_used);
    keep_call(ok);
    return ok;
}

void FastLineParser::Impl::restart() {
    b->sequence.reset();
    exprs_used = 0;
    words_used = 0;
    plain = false;
}

// The shape CAM post-processors write by the million: an optional
// sequence number, then glued words with literal values, separated by
// blanks or not at all (`N120 G1 Y-40. F2500`). The same Block as
// parse_line (prefix: sequence; items: glued_word), built in one pass;
// false on anything else, and parse_line starts again. Sets `plain` when
// the words are all X/Y/Z/F or G0..G3 (is_plain_move_block). With
// `moves_only`, false as soon as a word is not one of those, and each word
// gets only its address, range and number.
bool FastLineParser::Impl::simple_line() {
    return sentinel ? simple_line_in<true>() : simple_line_in<false>();
}

// With kSentinel, the byte at the end of the text is the line's terminator
// (LF or CR, in the same buffer): no class of the scans below includes
// it, so they stop there without comparing with the end.
template <bool kSentinel, bool kValues>
bool FastLineParser::Impl::simple_line_in() {
    const char* q = s;
    const char* const e = s + n;
    while ((kSentinel || q < e) && (kClass[static_cast<unsigned char>(*q)] & kBlankClass)) ++q;
    if (q == e) return false;
    if constexpr (kValues) values->sequence = {};
    if (*q == 'N' || *q == 'n') {
        const char* t = q + 1;
        if (t == e || !(kClass[static_cast<unsigned char>(*t)] & kDigitClass)) return false;
        while ((kSentinel || t < e) && (kClass[static_cast<unsigned char>(*t)] & kDigitClass)) ++t;
        if constexpr (kValues) {
            // The name as written is the Label's (upper-cased) name only with an upper-case N.
            if (*q != 'N') return false;
            values->sequence = std::string_view(q, static_cast<size_t>(t - q));
            values->sequence_range = abs(static_cast<uint32_t>(q - s), static_cast<uint32_t>(t - s));
        } else {
            set_label(b->sequence, static_cast<uint32_t>(q - s), static_cast<uint32_t>(t - s));
        }
        q = t;
    }
    bool all_plain = true;
    while (true) {
        while ((kSentinel || q < e) && (kClass[static_cast<unsigned char>(*q)] & kBlankClass)) ++q;
        if (q == e) break;
        if (!(kClass[static_cast<unsigned char>(*q)] & kWordClass) || q + 1 == e) return false;
        const char c = upper(*q);
        const char* t = q + 1;
        const char sign = (*t == '+' || *t == '-') ? *t : 0;
        if (sign) ++t;
        const char* const digits = t;
        double v = 0;
        t = scan_number<kSentinel>(t, e, v);
        if (t == digits) return false;
        if (t < e && !(kClass[static_cast<unsigned char>(*t)] & (kBlankClass | kLetterClass))) return false;
        const uint32_t p = static_cast<uint32_t>(q - s);
        const uint32_t j = static_cast<uint32_t>(t - s);
        if (c == 'G') all_plain = all_plain && (v == 0 || v == 1 || v == 2 || v == 3) && sign != '-';
        else if (c != 'X' && c != 'Y' && c != 'Z' && c != 'F') all_plain = false;
        if constexpr (kValues) {
            if (!all_plain || values->count == PlainMove::kMaxWords) return false;
            PlainMoveWord& w = values->words[values->count++];
            w.address = c;
            w.number = sign == '-' ? -v : v;
            w.range = abs(p, j);
            q = t;
            continue;
        }
        Word& w = new_word();
        set_char(w.address, c);
        w.range = abs(p, j);
        if (moves_only) {
            if (!all_plain) return false;
            w.number = sign == '-' ? -v : v;
            q = t;
            continue;
        }
        w.address_range = abs(p, p + 1);
        w.value_range = abs(p + 1, j);
        set_text(w.value_text, q + 1, j - p - 1);
        ExprNode& num = new_expr(ExprKind::Number, abs(static_cast<uint32_t>(digits - s), j));
        num.number = v;
        const ExprId num_id = last_expr();
        if (sign) {
            ExprNode& un = new_expr(ExprKind::Unary, abs(p + 1, j), sign);
            set_child(un.children, num_id);
            w.value = last_expr();
            w.number = sign == '-' ? -v : v;
        } else {
            w.value = num_id;
            w.number = v;
        }
        q = t;
    }
    if constexpr (kValues) return values->count > 0;
    plain = all_plain && words_used > 0;
    return true;
}

bool FastLineParser::Impl::parse_line() {
    uint32_t p = skip_extras(0);
    if (p == kFail) return false;
    if (p >= n) return true;
    const char c = s[p];
    if (c == '$') {  // tape header: the rest of the line (control characters end the token)
        for (uint32_t i = p + 1; i < n; ++i) {
            const auto ch = static_cast<unsigned char>(s[i]);
            if ((ch < 0x20 && ch != '\t') || ch == 0x7F) return false;
        }
        b->kind = LineKind::Header;
        return true;
    }
    if (c == '%') {
        uint32_t e = p + 1;
        if (e < n && s[e] == '%') ++e;
        e = skip_extras(e);
        if (e != n) return false;
        b->kind = LineKind::TapeMark;
        return true;
    }
    // Prefix: `/` [sequence], sequence [`/`], or a program name.
    if (c == '/') {
        b->block_delete = true;
        b->block_delete_range = abs(p, p + 1);
        p = skip_extras(p + 1);
        if (p == kFail) return false;
        if (p < n && (s[p] == 'N' || s[p] == 'n')) {
            p = sequence(p);
            if (p == kFail) return false;
        }
    } else if (c == 'N' || c == 'n') {
        const uint32_t e = sequence(p);
        if (e == kFail) return false;
        if (e != p) {
            p = skip_extras(e);
            if (p == kFail) return false;
            if (p < n && s[p] == '/') {
                b->block_delete = true;
                b->block_delete_range = abs(p, p + 1);
                ++p;
            }
        }
    } else if (c == 'O' || c == 'o') {
        p = program_name(p);
        if (p == kFail) return false;
    }
    // Items.
    while (true) {
        p = skip_blanks(p);
        if (p >= n) return true;
        if (s[p] == '(') {
            p = comment(p);
            if (p == kFail) return false;
            continue;
        }
        p = is_glued_word(s, p, n) ? glued_word(p) : is_letter(s[p]) ? item(p, Ctx::Block) : kFail;
        if (p == kFail) return false;
    }
}

FastLineParser::FastLineParser() : impl_(new Impl) {}
FastLineParser::~FastLineParser() { delete impl_; }

bool FastLineParser::parse_fast_only(const LineRef& line, Block& out) {
    const bool ok = impl_->run(line, out);
    last_plain_ = ok && impl_->plain;
    return ok;
}

bool FastLineParser::parse_moves(const LineRef& line, Block& out) {
    if (!impl_->run(line, out, true)) {
        last_plain_ = false;
        ++fallback_lines_;
        parse_line_tree_sitter(line, out);
        return false;
    }
    last_plain_ = impl_->plain;
    ++fast_lines_;
    return true;
}

bool FastLineParser::last_partial() const { return impl_->partial; }

uint64_t FastLineParser::again_lines() const { return impl_->again_lines; }
bool FastLineParser::last_again() const { return impl_->again_last; }
uint64_t FastLineParser::fills() const { return impl_->fills; }

bool FastLineParser::plain_move(const LineRef& line, PlainMove& out) {
    impl_->start(line);
    impl_->values = &out;
    out.count = 0;
    const bool ok = impl_->sentinel ? impl_->simple_line_in<true, true>() : impl_->simple_line_in<false, true>();
    impl_->values = nullptr;
    if (ok) ++fast_lines_;
    return ok;
}

bool FastLineParser::parse_outline(const LineRef& line, Block& out) {
    impl_->outline = true;
    const bool ok = parse(line, out);
    impl_->outline = false;
    return ok;
}

bool FastLineParser::plain_call(const LineRef& line) {
    impl_->start(line);
    return impl_->plain_call_line();
}

uint32_t FastLineParser::call_head_end(const LineRef& line) {
    // A posted program calls the same macro line after line: the same bytes
    // up to the name's end, and a blank after them, end there again.
    const std::string& last = impl_->last_head;
    const std::string_view text = line.text;
    if (!last.empty() && text.size() > last.size() && is_blank(text[last.size()]) &&
        std::memcmp(text.data(), last.data(), last.size()) == 0)
        return static_cast<uint32_t>(last.size());
    impl_->start(line);
    const uint32_t head = impl_->call_head();
    impl_->last_head.assign(text.data(), head);
    return head;
}

bool FastLineParser::parse(const LineRef& line, Block& out) {
    const bool ok = impl_->run(line, out);
    last_plain_ = ok && impl_->plain;
    if (ok) {
        ++fast_lines_;
        return true;
    }
    ++fallback_lines_;
    parse_line_tree_sitter(line, out);
    return false;
}

}  // namespace osplint
