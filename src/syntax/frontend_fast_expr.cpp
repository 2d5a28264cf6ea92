// The expressions of the fast front end (frontend_fast_parser.h): operands,
// indexed variables and brackets, and precedence climbing over + - * / and
// the keyword operators (EQ ... LE, AND, OR, EOR). The nodes enter the
// block's arena in the order the tree-sitter converter pushes them (children
// first); wherever the outcome would depend on something this parser does
// not model, it gives up (kFail) and the line goes to the tree-sitter front
// end.
#include "syntax/frontend_fast_parser.h"

namespace osplint {

using namespace fast_detail;

// Number literal at p (unsigned): pushes a Number node, returns its end.
uint32_t FastLineParser::Impl::number(uint32_t p) {
    double v = 0;
    const uint32_t j = scan_number_at(s, p, n, v);
    if (j == p) return kFail;
    // A letter right after the digits may make them a hex subscript token
    // (`002C`, also outside brackets: `X=5A1` does not parse); a second
    // point is never part of a number.
    if (j < n && (s[j] == '.' || is_alnum(s[j]))) return kFail;
    ExprNode& e = new_expr(ExprKind::Number, abs(p, j));
    e.number = v;
    return j;
}

// `[ sub (, sub)? ]` after the name of an indexed variable; pushes the
// subscripts and then the Variable node.
uint32_t FastLineParser::Impl::subscripts(uint32_t name_begin, const Name& name, uint32_t open) {
    ExprId subs[2];
    int count = 0;
    uint32_t p = open + 1;
    if (++depth > kMaxDepth) return kFail;  // deep nesting: the tree-sitter front end reports it
    while (true) {
        p = expr(p, 0);
        if (p == kFail) return kFail;
        subs[count++] = last_expr();
        p = skip_blanks(p);
        if (p < n && s[p] == ',' && count == 1) {
            ++p;
            continue;
        }
        if (p < n && s[p] == ']') break;
        return kFail;
    }
    --depth;
    ExprNode& v = new_expr(ExprKind::Variable, abs(name_begin, p + 1));
    set_text(v.text, name.text, name.len);
    for (int i = 0; i < count; ++i) v.children.push_back(subs[i]);
    return p + 1;
}

// An operand: number, variable, indexed variable, bracket, unary.
uint32_t FastLineParser::Impl::unary(uint32_t p) {
    p = skip_blanks(p);
    if (p >= n) return kFail;
    const char c = s[p];
    if (c == '-' || c == '+') {
        if (++depth > kMaxDepth) return kFail;
        const uint32_t q = unary(p + 1);
        --depth;
        if (q == kFail) return kFail;
        const ExprId operand = last_expr();
        const uint32_t end = b->exprs[static_cast<size_t>(operand)].range.end;
        ExprNode& e = new_expr(ExprKind::Unary, {base + p, end}, c);
        set_child(e.children, operand);
        return q;
    }
    if (is_digit(c) || c == '.') return number(p);
    if (c == '[') {
        if (++depth > kMaxDepth) return kFail;  // deep nesting: the tree-sitter front end reports it
        uint32_t q = expr(p + 1, 0);
        if (q == kFail) return kFail;
        const ExprId inner = last_expr();
        q = skip_blanks(q);
        if (q >= n || s[q] != ']') return kFail;
        --depth;
        ExprNode& e = new_expr(ExprKind::Bracket, abs(p, q + 1));
        set_child(e.children, inner);
        return q + 1;
    }
    if (is_letter(c)) {
        uint32_t e;
        Name name;
        if (p + 1 < n && is_letter(s[p + 1])) {
            e = alnum_end(p);
            if (!read_name(p, e, name)) return kFail;
            if (control_keyword(name.text, name.len) != Keyword::None) return kFail;
            if (command_keyword(name.text, name.len)) return kFail;
            if (name.text[0] == 'N' || name.text[0] == 'O') return kFail;
            if (name.len == 2 && (name.text[0] == 'H' || name.text[0] == 'D') &&
                (name.text[1] == 'A' || name.text[1] == 'C'))
                return kFail;
        } else if ((c == 'V' || c == 'v') && p + 1 < n && is_digit(s[p + 1])) {
            e = p + 1;
            while (e < n && is_digit(s[e])) ++e;
            if (e < n && is_alnum(s[e])) return kFail;
            name.len = e - p;
            if (name.len > kNameMax) return kFail;
            for (uint32_t i = 0; i < name.len; ++i) name.text[i] = upper(s[p + i]);
        } else {
            return kFail;  // a single letter is no operand
        }
        const uint32_t after = skip_blanks(e);
        if (after < n && s[after] == '[') return subscripts(p, name, after);
        ExprNode& v = new_expr(ExprKind::Variable, abs(p, e));
        set_text(v.text, name.text, name.len);
        return e;
    }
    return kFail;
}

int FastLineParser::Impl::precedence(char c) {
    if (c == '+' || c == '-') return 4;
    if (c == '*' || c == '/') return 5;
    return 0;
}

// Whether the expression may end at p (s[p] is not an operator): anything
// after a comment that could continue the expression makes the line too
// subtle for this parser.
bool FastLineParser::Impl::may_end_here(uint32_t p) const {
    if (p >= n) return true;
    if (is_letter(s[p])) {
        // A keyword operator (EQ, AND, ...) continues the expression.
        if (!may_be_operator(s[p])) return true;
        const uint32_t e = alnum_end(p);
        Name name;
        if (!read_name(p, e, name)) return false;
        return !operator_keyword(name.text, name.len);
    }
    if (s[p] != '(') return true;  // `]`, `,` and the like are for the caller
    // A comment: look at what follows it.
    uint32_t q = p;
    while (q < n) {
        q = skip_blanks(q);
        if (q < n && s[q] == '(') {
            while (q < n && s[q] != ')') ++q;
            if (q < n) ++q;
            continue;
        }
        break;
    }
    if (q >= n) return true;
    const char c = s[q];
    if (precedence(c) || c == '[' || c == ']' || c == ',' || c == '=' || c == '.' || is_digit(c)) return false;
    if (is_letter(c)) {
        const uint32_t e = alnum_end(q);
        Name name;
        if (!read_name(q, e, name)) return false;
        return !operator_keyword(name.text, name.len);
    }
    return true;
}

// Precedence climbing over + - * / and the keyword operators; the nodes enter the arena in the order
// the tree-sitter converter pushes them (children first).
uint32_t FastLineParser::Impl::expr(uint32_t p, int min_prec) {
    p = unary(p);
    if (p == kFail) return kFail;
    while (true) {
        const uint32_t q = skip_blanks(p);
        int prec = q < n ? precedence(s[q]) : 0;
        uint32_t operand = q + 1;  // where the right operand starts
        Name keyword;              // a keyword operator (EQ, AND ...), when len > 0
        if (!prec && q > p && q < n && may_be_operator(s[q])) {
            // Only between blanks (`VC1 LT 10`): glued to a bracket or a
            // name, the scanner's reading is not this parser's to guess.
            const uint32_t e = alnum_end(q);
            if (e < n && is_blank(s[e]) && read_name(q, e, keyword) && (prec = keyword_precedence(keyword)) != 0)
                operand = e;
            else
                keyword.len = 0;
        }
        if (!prec) {
            if (!may_end_here(q)) return kFail;
            return p;
        }
        if (prec < min_prec) return p;
        const ExprId left = last_expr();
        const uint32_t r = expr(operand, prec + 1);
        if (r == kFail) return kFail;
        const ExprId right = last_expr();
        const uint32_t begin = b->exprs[static_cast<size_t>(left)].range.begin;
        const uint32_t end = b->exprs[static_cast<size_t>(right)].range.end;
        ExprNode& e = new_expr(ExprKind::Binary, {begin, end}, keyword.len ? '\0' : s[q]);
        if (keyword.len) set_text(e.op, keyword.text, keyword.len);
        e.children.push_back(left);
        e.children.push_back(right);
        p = r;
    }
}

// The grammar's precedence of a keyword operator (0: none).
int FastLineParser::Impl::keyword_precedence(const Name& name) {
    if (!operator_keyword(name.text, name.len)) return 0;
    const std::string_view k = name.view();
    if (k == "AND") return 2;
    if (k == "OR" || k == "EOR") return 1;
    return 3;  // EQ NE GT GE LT LE
}

}  // namespace osplint
