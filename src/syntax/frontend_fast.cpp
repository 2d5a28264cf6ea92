// The hand-written lexer and block parser (see frontend_fast.h).
//
// Every decision below mirrors the grammar (grammar/grammar.js), its external
// scanner (grammar/src/scanner.c) and the tree-sitter converter
// (analyzer/frontend_ts.cpp): which token a run of letters becomes, which
// ranges a node covers, in which order expression nodes enter the block's
// arena. Wherever the outcome would depend on something this parser does not
// model, it gives up and the line goes to the tree-sitter front end.
#include "syntax/frontend_fast.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstring>
#include <limits>
#include <utility>

#include "syntax/frontend.h"

namespace osplint {

namespace {

constexpr uint32_t kNameMax = 32;  // NAME_MAX_LEN of the scanner

#if defined(__GNUC__)
#define OSPLINT_HOT inline __attribute__((always_inline))
#else
#define OSPLINT_HOT inline
#endif

inline bool is_letter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
inline bool is_digit(char c) { return c >= '0' && c <= '9'; }
inline bool is_alnum(char c) { return is_letter(c) || is_digit(c); }
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }
inline char upper(char c) { return c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c; }

// Character classes of simple_line.
constexpr uint8_t kBlankClass = 1;   // blank: space, tab, form feed, vertical tab (is_blank)
constexpr uint8_t kDigitClass = 2;   // 0-9
constexpr uint8_t kLetterClass = 4;  // A-Z, a-z
constexpr uint8_t kWordClass = 8;    // a letter that starts a glued word: not N, O or V (is_glued_word)
constexpr auto kClass = [] {
    std::array<uint8_t, 256> t{};
    for (int c : {' ', '\t', '\f', '\v'}) t[static_cast<unsigned char>(c)] = kBlankClass;
    for (int c = '0'; c <= '9'; ++c) t[static_cast<unsigned char>(c)] = kDigitClass;
    for (int c = 'A'; c <= 'Z'; ++c) {
        const bool word = c != 'N' && c != 'O' && c != 'V';
        t[static_cast<unsigned char>(c)] = t[static_cast<unsigned char>(c - 'A' + 'a')] =
            static_cast<uint8_t>(kLetterClass | (word ? kWordClass : 0));
    }
    return t;
}();

constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                             1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// Scans an unsigned number at t (`12`, `3.`, `.5`, `0404`), ending at e at the
// latest, and computes its value in the same pass: at most 15 digits take
// the exact path (the digits as an integer and the power of ten are exact
// doubles, so their quotient is the correctly rounded value), longer ones
// decimal_literal_value. Returns the end, or t when there is no number. With
// kSentinel the byte at e is neither a digit nor a point (the line's
// terminator), so the scans need not compare with e.
template <bool kSentinel>
OSPLINT_HOT const char* scan_number(const char* t, const char* e, double& value) {
    const char* const start = t;
    uint64_t m = 0;
    while ((kSentinel || t < e) && static_cast<unsigned char>(*t - '0') < 10) m = m * 10 + static_cast<uint64_t>(*t++ - '0');
    size_t count = static_cast<size_t>(t - start);
    size_t fraction = 0;
    if ((kSentinel || t < e) && *t == '.') {
        const char* const f = t + 1;
        const char* u = f;
        while ((kSentinel || u < e) && static_cast<unsigned char>(*u - '0') < 10)
            m = m * 10 + static_cast<uint64_t>(*u++ - '0');
        fraction = static_cast<size_t>(u - f);
        if (count == 0 && fraction == 0) return start;  // a point alone
        count += fraction;
        t = u;
    } else if (count == 0) {
        return start;
    }
    value = count <= 15 ? (fraction ? static_cast<double>(m) / kPow10[fraction] : static_cast<double>(m))
                        : decimal_literal_value(std::string_view(start, static_cast<size_t>(t - start)));
    return t;
}
// The same on s[p..n): returns the end offset, or p when there is no number.
OSPLINT_HOT uint32_t scan_number_at(const char* s, uint32_t p, uint32_t n, double& value) {
    return static_cast<uint32_t>(scan_number<false>(s + p, s + n, value) - s);
}

// Keyword classes of the scanner, for a name in upper case.
enum class Keyword : uint8_t { None, Call, Modin, Modout, Rts, Ncyl, Noex, Control, Function, Other };

bool equals(const char* name, uint32_t len, const char* kw) {
    return std::strlen(kw) == len && std::memcmp(name, kw, len) == 0;
}

// Names the scanner turns into keyword tokens whatever follows them (when the
// grammar expects them): the control keywords and the function names.
Keyword control_keyword(const char* name, uint32_t len) {
    static const std::pair<const char*, Keyword> kControl[] = {
        {"CALL", Keyword::Call},    {"MODIN", Keyword::Modin},  {"MODOUT", Keyword::Modout},
        {"RTS", Keyword::Rts},      {"NCYL", Keyword::Ncyl},    {"NOEX", Keyword::Noex},
        {"GOTO", Keyword::Control}, {"IF", Keyword::Control},   {"WHILE", Keyword::Control},
        {"DO", Keyword::Control},   {"END", Keyword::Control},  {"EMPTY", Keyword::Control},
        {"NOT", Keyword::Control},  {"EQ", Keyword::Control},   {"NE", Keyword::Control},
        {"GT", Keyword::Control},   {"GE", Keyword::Control},   {"LT", Keyword::Control},
        {"LE", Keyword::Control},   {"AND", Keyword::Control},  {"OR", Keyword::Control},
        {"EOR", Keyword::Control},
    };
    static const char* const kFunctions[] = {"SIN",   "COS", "TAN", "ATAN",   "ATAN2", "SQRT", "ABS",  "BIN",
                                             "BCD",   "ROUND", "FIX", "FUP", "DROUND", "DFIX", "DFUP", "MOD"};
    for (const auto& [kw, k] : kControl)
        if (equals(name, len, kw)) return k;
    for (const char* kw : kFunctions)
        if (equals(name, len, kw)) return Keyword::Function;
    return Keyword::None;
}

// The binary operators spelled with letters.
bool operator_keyword(const char* name, uint32_t len) {
    static const char* const kOps[] = {"EQ", "NE", "GT", "GE", "LT", "LE", "AND", "OR", "EOR"};
    for (const char* kw : kOps)
        if (equals(name, len, kw)) return true;
    return false;
}

// Names the scanner turns into command keywords unless `=` or `[` follows.
bool command_keyword(const char* name, uint32_t len) {
    static const char* const kWords[] = {
        // coordinate calculation
        "BHC", "LAA", "ARC", "GRDX", "GRDY", "DGRDX", "DGRDY", "SQRX", "SQRY", "OMIT", "RSTRT",
        // mnemonics
        "MSG", "NMSG", "COPY", "COPYE", "CHFC", "CHFR", "RTMCR", "RTMDI", "FMILR", "FMILF", "PMIL", "PMILR",
        "RMILO", "RMILI", "TLFON", "TLFOFF", "TLID", "CLEAR", "LCLEAR", "DRAW",
        // commands with free-form operands
        "DEF", "PT", "PUT", "FWRITC", "FOPENA", "FOPENB", "WRITE", "READ", "CLOSE", "PRNT", "SAVE", "EIN", "DIN",
        "RTI", "CYLNDR", "DIREC"};
    for (const char* kw : kWords)
        if (equals(name, len, kw)) return true;
    return false;
}

// Assignments to the strings of recycled model objects: most blocks of a
// program repeat the previous block's shape, so the text often has the same
// length (or is the same) and the generic assign can be skipped.
OSPLINT_HOT void set_text(std::string& dst, const char* p, size_t n) {
    // A length change within the capacity by the inline members (erase to
    // shorten, push_back to lengthen): assign() is an out-of-line call.
    if (dst.size() > n) {
        dst.erase(n);
    } else if (dst.size() < n && n <= dst.capacity() && n - dst.size() <= 4) {
        while (dst.size() < n) dst.push_back('\0');
    }
    if (dst.size() == n) {
        char* d = dst.data();
        if (n >= 4 && n <= 8) {  // two overlapping 4-byte moves
            uint32_t a, z;
            std::memcpy(&a, p, 4);
            std::memcpy(&z, p + n - 4, 4);
            std::memcpy(d, &a, 4);
            std::memcpy(d + n - 4, &z, 4);
        } else {
            for (size_t i = 0; i < n; ++i) d[i] = p[i];
        }
    } else {
        dst.assign(p, n);
    }
}
// Sets a node's only child.
inline void set_child(std::vector<ExprId>& children, ExprId id) {
    if (children.size() == 1) {
        children[0] = id;
    } else {
        children.clear();
        children.push_back(id);
    }
}
OSPLINT_HOT void set_char(std::string& dst, char c) {
    if (dst.size() == 1) dst[0] = c;
    else dst.assign(1, c);
}

// Storage reuse: elements beyond what a block needs are parked here (moved, so
// their strings and vectors keep their capacity) and taken back later.
template <class T>
class Recycler {
public:
    T& take(std::vector<T>& v, size_t& used) {
        if (used == v.size()) {
            if (!spare_.empty()) {
                v.push_back(std::move(spare_.back()));
                spare_.pop_back();
            } else {
                v.emplace_back();
            }
        }
        return v[used++];
    }
    void finish(std::vector<T>& v, size_t used) {
        while (v.size() > used) {
            spare_.push_back(std::move(v.back()));
            v.pop_back();
        }
    }

private:
    std::vector<T> spare_;
};

constexpr uint32_t kFail = std::numeric_limits<uint32_t>::max();

}  // namespace

struct FastLineParser::Impl {
    Recycler<ExprNode> expr_pool;
    Recycler<Word> word_pool;
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
    // Deeper lines are left to the tree-sitter front end (bounded recursion here).
    static constexpr int kMaxDepth = 64;

    enum class Ctx { Block, CallArgs };

    // ------------------------------------------------------------ utilities

    uint32_t skip_blanks(uint32_t p) const {
        while (p < n && is_blank(s[p])) ++p;
        return p;
    }

    ByteRange abs(uint32_t b0, uint32_t e0) const { return {base + b0, base + e0}; }

    // A comment at p (s[p] == '('): its end, or kFail when it is not closed on
    // the line or holds a control character.
    uint32_t comment(uint32_t p) {
        uint32_t q = p + 1;
        while (q < n && s[q] != ')') {
            const auto c = static_cast<unsigned char>(s[q]);
            if ((c < 0x20 && c != '\t') || c == 0x7F) return kFail;
            ++q;
        }
        if (q >= n) return kFail;
        b->comments.push_back(Comment{abs(p, q + 1)});
        return q + 1;
    }

    // Skips blanks and comments (recording the comments).
    uint32_t skip_extras(uint32_t p) {
        while (true) {
            p = skip_blanks(p);
            if (p < n && s[p] == '(') {
                p = comment(p);
                if (p == kFail) return kFail;
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
        if (op) set_char(e.op, op);
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
        while (p < n && is_alnum(s[p])) ++p;
        return p;
    }

    // Upper-case copy of a name (at most kNameMax characters).
    struct Name {
        char text[kNameMax + 1];
        uint32_t len = 0;
        std::string_view view() const { return {text, len}; }
    };
    bool read_name(uint32_t p, uint32_t e, Name& out) const {
        if (e - p > kNameMax) return false;
        out.len = e - p;
        for (uint32_t i = 0; i < out.len; ++i) out.text[i] = upper(s[p + i]);
        out.text[out.len] = '\0';
        // `DO1`, `END1`: the scanner may split a loop number off these.
        if (out.len >= 3 && out.text[0] == 'D' && out.text[1] == 'O' && is_digit(out.text[2])) return false;
        if (out.len >= 4 && out.text[0] == 'E' && out.text[1] == 'N' && out.text[2] == 'D' && is_digit(out.text[3]))
            return false;
        return true;
    }

    // ------------------------------------------------------------ expressions

    // Number literal at p (unsigned): pushes a Number node, returns its end.
    uint32_t number(uint32_t p) {
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
    uint32_t subscripts(uint32_t name_begin, const Name& name, uint32_t open) {
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
    uint32_t unary(uint32_t p) {
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

    static int precedence(char c) {
        if (c == '+' || c == '-') return 4;
        if (c == '*' || c == '/') return 5;
        return 0;
    }

    // Whether the expression may end at p (s[p] is not an operator): anything
    // after a comment that could continue the expression makes the line too
    // subtle for this parser.
    bool may_end_here(uint32_t p) const {
        if (p >= n) return true;
        if (is_letter(s[p])) {
            // A keyword operator (EQ, AND, ...) continues the expression.
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

    // Precedence climbing over + - * /; the nodes enter the arena in the order
    // the tree-sitter converter pushes them (children first).
    uint32_t expr(uint32_t p, int min_prec) {
        p = unary(p);
        if (p == kFail) return kFail;
        while (true) {
            const uint32_t q = skip_blanks(p);
            const int prec = q < n ? precedence(s[q]) : 0;
            if (!prec) {
                if (!may_end_here(q)) return kFail;
                return p;
            }
            if (prec < min_prec) return p;
            const ExprId left = last_expr();
            const uint32_t r = expr(q + 1, prec + 1);
            if (r == kFail) return kFail;
            const ExprId right = last_expr();
            const uint32_t begin = b->exprs[static_cast<size_t>(left)].range.begin;
            const uint32_t end = b->exprs[static_cast<size_t>(right)].range.end;
            ExprNode& e = new_expr(ExprKind::Binary, {begin, end}, s[q]);
            e.children.push_back(left);
            e.children.push_back(right);
            p = r;
        }
    }

    // ------------------------------------------------------------------ items

    // The glued number of `X-.75` at p: a Number (signed: Unary over it).
    OSPLINT_HOT uint32_t word_number(Word& w, uint32_t p) {
        uint32_t j = p;
        const char sign = (j < n && (s[j] == '+' || s[j] == '-')) ? s[j] : 0;
        if (sign) ++j;
        const uint32_t digits = j;
        double v = 0;
        j = scan_number_at(s, digits, n, v);
        if (j == digits || (j < n && s[j] == '.')) return kFail;
        ExprNode& num = new_expr(ExprKind::Number, abs(digits, j));
        num.number = v;
        const ExprId num_id = last_expr();
        if (sign) {
            ExprNode& un = new_expr(ExprKind::Unary, abs(p, j), sign);
            set_child(un.children, num_id);
            w.value = last_expr();
            w.number = sign == '-' ? -v : v;
        } else {
            w.value = num_id;
            w.number = v;
        }
        w.value_range = abs(p, j);
        set_text(w.value_text, s + p, j - p);
        return j;
    }

    // `NAME = expr` or `NAME[..] = expr` with the name at [p, e).
    uint32_t assignment(uint32_t p, uint32_t e, const Name& name, Ctx ctx) {
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
        Word& w = b->words[wi];
        const ExprId value = last_expr();
        const ByteRange vr = b->exprs[static_cast<size_t>(value)].range;
        set_text(w.address, name.text, name.len);
        w.range = {base + p, vr.end};
        w.address_range = abs(p, e);
        w.equals = true;
        w.value = value;
        w.value_range = vr;
        set_text(w.value_text, s + (vr.begin - base), vr.size());
        w.number = literal_value(value);
        return q;
    }

    // `N0207` / `NAT3` inside a block: a word with address N, value = the rest.
    uint32_t label_word(uint32_t p, uint32_t e) {
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
            const size_t wi = words_used - 1;
            ExprNode& num = new_expr(ExprKind::Number, abs(p + 1, e));
            num.number = decimal_literal_value(std::string_view(s + p + 1, e - p - 1));
            Word& ww = b->words[wi];
            ww.number = num.number;
            ww.value = last_expr();
        }
        return e;
    }

    uint32_t keyword_statement(StmtKind kind, uint32_t p, uint32_t e) {
        Statement st;
        st.kind = kind;
        st.range = abs(p, e);
        st.keyword_range = st.range;
        b->statements.push_back(std::move(st));
        return e;
    }

    // CALL / MODIN Oname args...: takes the rest of the line.
    uint32_t call_statement(StmtKind kind, uint32_t p, uint32_t e) {
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
        while (true) {
            pos = skip_blanks(pos);
            if (pos >= n) break;
            if (s[pos] == '(') {
                pos = comment(pos);
                if (pos == kFail) return kFail;
                continue;
            }
            if (!is_letter(s[pos])) return kFail;
            pos = item(pos, Ctx::CallArgs);
            if (pos == kFail) return kFail;
            end = pos;
        }
        b->statements[index].range = abs(p, end);
        return n;
    }

    // `X-.75`: a letter other than N, O and V directly followed by a number
    // (the most common item by far).
    static bool is_glued_word(const char* s, uint32_t p, uint32_t n) {
        if (p + 1 >= n) return false;
        const char c = upper(s[p]);
        const char nx = s[p + 1];
        return c >= 'A' && c <= 'Z' && c != 'N' && c != 'O' && c != 'V' &&
               (is_digit(nx) || nx == '-' || nx == '+' || nx == '.');
    }
    OSPLINT_HOT uint32_t glued_word(uint32_t p) {
        Word& w = new_word();
        set_char(w.address, upper(s[p]));
        w.address_range = abs(p, p + 1);
        const uint32_t e = word_number(w, p + 1);
        if (e == kFail) return kFail;
        w.range = abs(p, e);
        return e;
    }

    // One item at p (a letter).
    uint32_t item(uint32_t p, Ctx ctx) {
        if (is_glued_word(s, p, n)) return glued_word(p);
        const char c = upper(s[p]);
        const uint32_t q = p + 1;
        if (q < n && is_letter(s[q])) {
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
        if (nx == '=' || is_blank(nx)) {
            const uint32_t r = skip_blanks(q);
            if (r >= n || s[r] != '=') return kFail;
            const size_t wi = words_used;
            new_word();
            const uint32_t e = expr(r + 1, 0);
            if (e == kFail) return kFail;
            Word& w = b->words[wi];
            const ExprId value = last_expr();
            const ByteRange vr = b->exprs[static_cast<size_t>(value)].range;
            set_char(w.address, c);
            w.range = {base + p, vr.end};
            w.address_range = abs(p, q);
            w.equals = true;
            w.value = value;
            w.value_range = vr;
            set_text(w.value_text, s + (vr.begin - base), vr.size());
            w.number = literal_value(value);
            return e;
        }
        return kFail;
    }

    // ---------------------------------------------------------------- prefix

    // A sequence name at p (s[p] is N/n), or p when there is none.
    uint32_t sequence(uint32_t p) {
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
    uint32_t program_name(uint32_t p) {
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

    void set_label(std::optional<Label>& out, uint32_t p, uint32_t e) {
        if (!out) out.emplace();
        out->name.resize(e - p);
        for (uint32_t i = p; i < e; ++i) out->name[i - p] = upper(s[i]);
        out->range = abs(p, e);
    }

    // ------------------------------------------------------------------ line

    bool run(const LineRef& line, Block& out) {
        s = line.text.data();
        n = static_cast<uint32_t>(line.text.size());
        base = line.start;
        sentinel = !line.terminator.empty() && line.terminator.data() == line.text.data() + line.text.size();
        b = &out;
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
        bool ok = simple_line();
        if (!ok) {
            // Start again with the general parser.
            out.sequence.reset();
            exprs_used = 0;
            words_used = 0;
            plain = false;
            ok = parse_line();
        }
        word_pool.finish(out.words, words_used);
        expr_pool.finish(out.exprs, exprs_used);
        return ok;
    }

    // The shape CAM post-processors write by the million: an optional
    // sequence number, then glued words with literal values, separated by
    // blanks or not at all (`N120 G1 Y-40. F2500`). The same Block as
    // parse_line (prefix: sequence; items: glued_word), built in one pass;
    // false on anything else, and parse_line starts again. Sets `plain` when
    // the words are all X/Y/Z/F or G0..G3 (is_plain_move_block).
    bool simple_line() {
        return sentinel ? simple_line_in<true>() : simple_line_in<false>();
    }

    // With kSentinel, the byte at the end of the text is the line's terminator
    // (LF or CR, in the same buffer): no class of the scans below includes
    // it, so they stop there without comparing with the end.
    template <bool kSentinel>
    bool simple_line_in() {
        const char* q = s;
        const char* const e = s + n;
        while ((kSentinel || q < e) && (kClass[static_cast<unsigned char>(*q)] & kBlankClass)) ++q;
        if (q == e) return false;
        if (*q == 'N' || *q == 'n') {
            const char* t = q + 1;
            if (t == e || !(kClass[static_cast<unsigned char>(*t)] & kDigitClass)) return false;
            while ((kSentinel || t < e) && (kClass[static_cast<unsigned char>(*t)] & kDigitClass)) ++t;
            set_label(b->sequence, static_cast<uint32_t>(q - s), static_cast<uint32_t>(t - s));
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
            Word& w = new_word();
            set_char(w.address, c);
            w.address_range = abs(p, p + 1);
            w.range = abs(p, j);
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
            if (c == 'G') all_plain = all_plain && (v == 0 || v == 1 || v == 2 || v == 3) && sign != '-';
            else if (c != 'X' && c != 'Y' && c != 'Z' && c != 'F') all_plain = false;
            q = t;
        }
        plain = all_plain && words_used > 0;
        return true;
    }

    bool parse_line() {
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
};

FastLineParser::FastLineParser() : impl_(new Impl) {}
FastLineParser::~FastLineParser() { delete impl_; }

bool FastLineParser::parse_fast_only(const LineRef& line, Block& out) {
    const bool ok = impl_->run(line, out);
    last_plain_ = ok && impl_->plain;
    return ok;
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

namespace {

// Applies `f` to every byte range of a block that is set. Unset ranges stay
// {0, 0}: the block-delete range without a `/`, the name range of a statement
// without a name, and the word ranges the converter never filled.
template <class F>
void for_each_range(Block& b, F&& f) {
    auto maybe = [&](ByteRange& r) {
        if (r.begin != 0 || r.end != 0) f(r);
    };
    f(b.range);
    if (b.program_name) f(b.program_name->range);
    if (b.sequence) f(b.sequence->range);
    if (b.block_delete) f(b.block_delete_range);
    for (auto& w : b.words) {
        f(w.range);
        maybe(w.address_range);
        maybe(w.value_range);
    }
    for (auto& a : b.assignments) f(a.range);
    for (auto& s : b.statements) {
        f(s.range);
        f(s.keyword_range);
        if (!s.name.empty()) f(s.name_range);
        else maybe(s.name_range);
    }
    for (auto& c : b.comments) f(c.range);
    for (auto& e : b.exprs) f(e.range);
    for (auto& e : b.errors) f(e.range);
}

}  // namespace

void shift_block(Block& b, int64_t delta) {
    for_each_range(b, [&](ByteRange& r) {
        r.begin = static_cast<uint32_t>(r.begin + delta);
        r.end = static_cast<uint32_t>(r.end + delta);
    });
}

void parse_line_tree_sitter(const LineRef& line, Block& out) {
    // The line is parsed after one blank, so that every offset of its own text
    // is above zero and an unset range ({0, 0}) is never taken for a set one.
    // A blank is padding to the grammar and changes no node; a node error
    // recovery inserts before it (a missing token at offset 0) belongs at the
    // line start, where it is in the file.
    std::string text;
    text.reserve(line.text.size() + line.terminator.size() + 1);
    text.push_back(' ');
    text.append(line.text);
    text.append(line.terminator);
    ProgramFile f = parse_program_file_once(std::string(), std::move(text));
    Block b = f.blocks.empty() ? Block{} : std::move(f.blocks[0]);
    const uint32_t start = line.start;
    for_each_range(b, [&](ByteRange& r) {
        r.begin = (r.begin ? r.begin - 1 : 0) + start;
        r.end = (r.end ? r.end - 1 : 0) + start;
    });
    b.line = line.line;
    b.line_start = line.start;
    b.range = {line.start, line.start + static_cast<uint32_t>(line.text.size())};
    out = std::move(b);
}

namespace {

std::string dump_range(ByteRange r) { return "[" + std::to_string(r.begin) + "," + std::to_string(r.end) + ")"; }

std::string dump_number(double v) {
    char buf[64];
    const auto res = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, res.ptr);
}

}  // namespace

std::string dump_block(const Block& b) {
    std::string o;
    o += "line " + std::to_string(b.line) + " start " + std::to_string(b.line_start) + " range " +
         dump_range(b.range) + " kind " + std::to_string(static_cast<int>(b.kind)) + "\n";
    if (b.program_name) o += "program " + b.program_name->name + " " + dump_range(b.program_name->range) + "\n";
    if (b.sequence) o += "sequence " + b.sequence->name + " " + dump_range(b.sequence->range) + "\n";
    o += "delete " + std::to_string(b.block_delete) + " " + dump_range(b.block_delete_range) + "\n";
    for (const auto& w : b.words) {
        o += "word " + w.address + " " + dump_range(w.range) + " addr " + dump_range(w.address_range) + " value " +
             dump_range(w.value_range) + " eq " + std::to_string(w.equals) + " expr " + std::to_string(w.value) +
             " num " + (w.number ? dump_number(*w.number) : std::string("-")) + " text '" + w.value_text + "'\n";
    }
    for (const auto& a : b.assignments)
        o += "assign " + std::to_string(a.target) + " = " + std::to_string(a.value) + " " + dump_range(a.range) + "\n";
    for (const auto& s : b.statements)
        o += "stmt " + std::to_string(static_cast<int>(s.kind)) + " " + dump_range(s.range) + " kw " +
             dump_range(s.keyword_range) + " name '" + s.name + "' " + dump_range(s.name_range) + " expr " +
             std::to_string(s.expr) + " loop " + std::to_string(s.loop) + "\n";
    for (const auto& c : b.comments) o += "comment " + dump_range(c.range) + "\n";
    for (size_t i = 0; i < b.exprs.size(); ++i) {
        const auto& e = b.exprs[i];
        o += "expr " + std::to_string(i) + " kind " + std::to_string(static_cast<int>(e.kind)) + " op '" + e.op +
             "' text '" + e.text + "' num " + dump_number(e.number) + " " + dump_range(e.range) + " children";
        for (auto c : e.children) o += " " + std::to_string(c);
        o += "\n";
    }
    for (const auto& e : b.errors) o += "error " + dump_range(e.range) + " " + e.message + "\n";
    return o;
}

ProgramFile parse_program_file_fast(std::string path, std::string text, uint64_t* fallback_lines) {
    if (text.size() > std::numeric_limits<uint32_t>::max() - 1)
        return parse_program_file(std::move(path), std::move(text));
    ProgramFile file;
    file.path = std::move(path);
    file.source = SourceText(std::move(text));
    FastLineParser parser;
    Block scratch;
    for_each_line(file.source.text(), [&](const LineRef& l) {
        parser.parse(l, scratch);
        file.blocks.push_back(scratch);
    });
    if (fallback_lines) *fallback_lines = parser.fallback_lines();
    file.programs = split_programs(file.blocks);
    return file;
}

}  // namespace osplint
