// LineChecker: where a line stops being valid (see frontend_ts_linecheck.h).
// It follows the grammar (grammar/grammar.js) and its external scanner
// (grammar/src/scanner.c) token by token.
#include "syntax/frontend_ts_linecheck.h"

#include <algorithm>
#include <string>

#include "syntax/frontend_ts_grammar.h"

extern "C" int tree_sitter_osp_keyword_class(const char* upper_name);

namespace osplint::ts_detail {

namespace {

// The scanner's classes of keywords (tree_sitter_osp_keyword_class).
enum class KeywordClass { None = 0, Control = 1, Function = 2, Coordinate = 3, Mnemonic = 4, Command = 5 };

KeywordClass keyword_class(const std::string& upper_name) {
    return static_cast<KeywordClass>(tree_sitter_osp_keyword_class(upper_name.c_str()));
}

// Reads a line with the grammar's rules; first_error() is where it stops
// being valid.
class LineChecker {
public:
    explicit LineChecker(std::string_view line) : s_(line) {}

    // Offset in the line of the first character that cannot continue it, or
    // npos when the whole line is valid.
    size_t first_error() {
        if (at_end()) return npos;
        const char c = s_[p_];
        if (c == '$') return npos;  // tape header
        if (c == '%') {
            p_ += p_ + 1 < s_.size() && s_[p_ + 1] == '%' ? 2 : 1;
            if (!at_end()) fail(p_);
            return fail_;
        }
        block();
        return fail_;
    }

    static constexpr size_t npos = std::string_view::npos;

    // Where an expression nested deeper than kMaxExprDepth starts (the line
    // was not read past it), or npos.
    size_t too_deep_at() const { return gave_up_ ? deep_at_ : npos; }

private:
    std::string_view s_;
    size_t p_ = 0;
    size_t fail_ = npos;
    int depth_ = 0;         // expression nesting
    bool gave_up_ = false;  // nested too deeply to check
    size_t deep_at_ = npos; // where the expression too deep starts

    // A run of letters and digits that starts with a letter, as the scanner sees it.
    struct Name {
        size_t begin = 0, end = 0;
        std::string text;       // upper case
        bool single = false;    // one letter not followed by a letter
        bool operand_follows = false;  // `=` or `[` after blanks
    };

    static bool letter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
    static bool digit(char c) { return c >= '0' && c <= '9'; }
    static bool hex(char c) { return digit(c) || (c >= 'A' && c <= 'F') || (c >= 'a' && c <= 'f'); }
    char at(size_t i) const { return i < s_.size() ? s_[i] : '\0'; }
    bool failed() const { return fail_ != npos || gave_up_; }
    void fail(size_t where) {
        if (fail_ == npos && !gave_up_) fail_ = std::min(where, s_.size());
    }

    // Skips blanks, a BOM and comments (an unclosed comment is reported on its own).
    void skip() {
        while (p_ < s_.size()) {
            const char c = s_[p_];
            if (c == ' ' || c == '\t' || c == '\f' || c == '\v') {
                ++p_;
            } else if (s_.compare(p_, 3, "\xEF\xBB\xBF") == 0) {
                p_ += 3;
            } else if (c == '(') {
                const size_t close = s_.find(')', p_);
                p_ = close == npos ? s_.size() : close + 1;
            } else {
                break;
            }
        }
    }
    bool at_end() {
        skip();
        return p_ >= s_.size();
    }
    bool accept(char c) {
        if (at_end() || s_[p_] != c) return false;
        ++p_;
        return true;
    }
    void expect(char c) {
        if (!failed() && !accept(c)) fail(at_end() ? s_.size() : p_);
    }

    // The name at p_ (a letter must be there). The DO / END keyword may have
    // its loop number glued to it.
    Name peek_name() const {
        Name n;
        n.begin = p_;
        size_t e = p_ + 1;
        if (!letter(at(e))) {
            n.single = true;
        } else {
            while (letter(at(e)) || digit(at(e))) {
                ++e;
                const size_t len = e - p_;
                if (digit(at(e)) && ((len == 2 && upper(s_.substr(p_, 2)) == "DO") ||
                                     (len == 3 && upper(s_.substr(p_, 3)) == "END")))
                    break;
            }
        }
        n.end = e;
        n.text = upper(s_.substr(p_, e - p_));
        size_t f = e;
        while (f < s_.size() && (s_[f] == ' ' || s_[f] == '\t')) ++f;
        n.operand_follows = at(f) == '=' || at(f) == '[';
        return n;
    }

    // `N` + digits, or `N` + letters/digits when no `=` / `[` follows.
    bool n_name(Name& n) {
        if (n.text[0] != 'N') return false;
        if (n.single) {
            if (!digit(at(n.end))) return false;
            size_t e = n.end;
            while (digit(at(e))) ++e;
            n.end = e;
            return true;
        }
        return !n.operand_follows;
    }

    // `O` + letters/digits.
    bool o_name(Name& n) {
        if (n.text[0] != 'O') return false;
        if (n.single) {
            if (!digit(at(n.end))) return false;
            size_t e = n.end;
            while (letter(at(e)) || digit(at(e))) ++e;
            n.end = e;
        }
        return true;
    }

    void block() {
        bool started = false;
        if (accept('/')) {
            started = true;
            if (!at_end() && letter(s_[p_])) {
                Name n = peek_name();
                if (!is_keyword_prefix(n) && n_name(n)) p_ = n.end;
            }
        } else if (!at_end() && letter(s_[p_])) {
            Name n = peek_name();
            if (!is_keyword_prefix(n) && n_name(n)) {
                p_ = n.end;
                started = true;
                accept('/');
            } else if (!is_keyword_prefix(n) && !n.operand_follows && o_name(n)) {
                p_ = n.end;
                started = true;
            }
        }
        (void)started;
        while (!failed() && !at_end()) item();
    }

    // Names that are commands rather than program or sequence names at a block start.
    static bool is_keyword_prefix(const Name& n) {
        if (n.single) return false;
        const KeywordClass k = keyword_class(n.text);
        if (k == KeywordClass::Control) return n.text != "EMPTY" && n.text != "NOT" && !is_operator(n.text);
        if (k == KeywordClass::Coordinate || k == KeywordClass::Mnemonic || k == KeywordClass::Command)
            return !n.operand_follows;
        return false;
    }

    static bool is_operator(const std::string& t) {
        return t == "EQ" || t == "NE" || t == "GT" || t == "GE" || t == "LT" || t == "LE" || t == "AND" ||
               t == "OR" || t == "EOR";
    }

    // One item of a block; statements that take the rest of the line consume it.
    void item() {
        const size_t q = p_;
        const char c = s_[q];
        if (!letter(c)) return fail(q);
        Name n = peek_name();
        if (n.single) {
            const char l = n.text[0];
            if (l == 'N' && digit(at(n.end))) {
                n_name(n);
                p_ = n.end;
                return;
            }
            if (l == 'V' && digit(at(n.end))) {  // lathe common variable
                size_t e = n.end;
                while (digit(at(e))) ++e;
                p_ = e;
                return assignment_rest();
            }
            if (l == 'O') return fail(q);
            return word(n);
        }
        const KeywordClass k = keyword_class(n.text);
        if (k == KeywordClass::Control && n.text != "EMPTY" && n.text != "NOT" && !is_operator(n.text))
            return statement(n);
        if (!n.operand_follows) {
            if (k == KeywordClass::Coordinate || k == KeywordClass::Mnemonic) {
                p_ = n.end;
                return arguments(k == KeywordClass::Mnemonic);
            }
            if (k == KeywordClass::Command) {
                p_ = n.end;
                return operands();
            }
            if (n.text.size() == 2 && (n.text[0] == 'H' || n.text[0] == 'D') &&
                (n.text[1] == 'A' || n.text[1] == 'C')) {
                p_ = n.end;
                return;
            }
            if (n_name(n)) {  // `G85 NAT3`
                p_ = n.end;
                return;
            }
            return fail(q);  // unknown command; a variable needs `=`
        }
        p_ = n.end;
        return assignment_rest();
    }

    // `X10.`, `X-.75`, `X=expr`.
    void word(const Name& n) {
        p_ = n.end;
        const char c = at(p_);
        if (digit(c) || c == '.' || c == '+' || c == '-') {
            size_t e = p_;
            if (at(e) == '+' || at(e) == '-') ++e;
            const size_t digits = e;
            while (digit(at(e))) ++e;
            if (at(e) == '.') {
                ++e;
                while (digit(at(e))) ++e;
            }
            const bool has_digit = e > digits && !(e == digits + 1 && at(digits) == '.');
            if (!has_digit) return fail(p_);
            p_ = e;
            return;
        }
        if (accept('=')) return expression();
        fail(at_end() ? s_.size() : p_);
    }

    void assignment_rest() {
        if (accept('[')) subscripts();
        expect('=');
        if (!failed()) expression();
    }

    void statement(const Name& n) {
        p_ = n.end;
        const std::string& t = n.text;
        if (t == "NCYL" || t == "NOEX" || t == "MODOUT" || t == "RTS") return;
        if (t == "GOTO") return label();
        if (t == "IF" || t == "WHILE") {
            expect('[');
            if (!failed()) expression();
            expect(']');
            if (failed()) return;
            if (t == "IF") {
                if (!at_end() && letter(s_[p_])) {
                    Name g = peek_name();
                    if (g.text == "GOTO") p_ = g.end;
                }
                return label();
            }
            if (at_end() || !letter(s_[p_]) || peek_name().text != "DO") return fail(at_end() ? s_.size() : p_);
            p_ = peek_name().end;
            return loop_number(true);
        }
        if (t == "DO") return loop_number(true);
        if (t == "END") return loop_number(false);
        if (t == "CALL" || t == "MODIN") {
            if (at_end() || !letter(s_[p_])) return fail(at_end() ? s_.size() : p_);
            Name o = peek_name();
            if (!o_name(o)) return fail(p_);
            p_ = o.end;
            return arguments(false);
        }
        fail(n.begin);
    }

    void label() {
        if (at_end() || !letter(s_[p_])) return fail(at_end() ? s_.size() : p_);
        Name n = peek_name();
        if (!n_name(n)) return fail(p_);
        p_ = n.end;
    }

    void loop_number(bool required) {
        if (at_end() || !digit(s_[p_])) {
            if (required) fail(at_end() ? s_.size() : p_);
            return;
        }
        number();
    }

    // Words, assignments (and labels for mnemonics) up to the end of the line.
    void arguments(bool labels) {
        while (!failed() && !at_end()) {
            const size_t q = p_;
            if (!letter(s_[q])) return fail(q);
            Name n = peek_name();
            if (n.single) {
                if (n.text[0] == 'V' && digit(at(n.end))) {
                    size_t e = n.end;
                    while (digit(at(e))) ++e;
                    p_ = e;
                    assignment_rest();
                } else if (labels && n_name(n)) {
                    p_ = n.end;
                } else if (n.text[0] == 'O') {
                    return fail(q);
                } else {
                    word(n);
                }
            } else if (n.operand_follows) {
                p_ = n.end;
                assignment_rest();
            } else if (n.text.size() == 2 && (n.text[0] == 'H' || n.text[0] == 'D') &&
                       (n.text[1] == 'A' || n.text[1] == 'C')) {
                p_ = n.end;
            } else if (labels && n_name(n)) {
                p_ = n.end;
            } else {
                return fail(q);
            }
        }
    }

    // Free-form operands: anything but blanks and comments; quotes must close.
    void operands() {
        while (!failed() && !at_end()) {
            if (s_[p_] == '\'') {
                const size_t close = s_.find('\'', p_ + 1);
                if (close == npos) return fail(p_);
                p_ = close + 1;
            } else {
                ++p_;
            }
        }
    }

    void number() {
        size_t e = p_;
        while (digit(at(e))) ++e;
        if (at(e) == '.') {
            ++e;
            while (digit(at(e))) ++e;
        }
        if (e == p_ || (e == p_ + 1 && s_[p_] == '.')) return fail(p_);
        p_ = e;
    }

    void subscripts() {
        subscript();
        if (accept(',')) subscript();
        expect(']');
    }

    void subscript() {
        if (!at_end() && digit(s_[p_])) {
            size_t e = p_;
            bool letters = false;
            while (hex(at(e))) letters |= !digit(at(e++));
            if (letters) {
                p_ = e;
                return;
            }
        }
        expression();
    }

    // expression := unary (operator unary)*
    void expression() {
        if (depth_ >= kMaxExprDepth) {
            if (!gave_up_) deep_at_ = std::min(p_, s_.size());
            gave_up_ = true;
            p_ = s_.size();
            return;
        }
        ++depth_;
        expression_items();
        --depth_;
    }

    void expression_items() {
        unary();
        while (!failed() && !at_end()) {
            const char c = s_[p_];
            if (c == '+' || c == '-' || c == '*' || c == '/') {
                ++p_;
            } else if (letter(c) && is_operator(peek_name().text)) {
                p_ = peek_name().end;
            } else {
                return;
            }
            unary();
        }
    }

    // Each operator nests the operand one level deeper.
    void unary() {
        int operators = 0;
        while (!at_end()) {
            const char c = s_[p_];
            if (c != '-' && c != '+' && !(letter(c) && peek_name().text == "NOT")) break;
            if (depth_ + ++operators > kMaxExprDepth) {
                if (!gave_up_) deep_at_ = p_;
                gave_up_ = true;
                p_ = s_.size();
                return;
            }
            p_ = (c == '-' || c == '+') ? p_ + 1 : peek_name().end;
        }
        primary();
    }

    void primary() {
        if (failed()) return;
        if (at_end()) return fail(s_.size());
        const size_t q = p_;
        const char c = s_[q];
        if (digit(c) || c == '.') return number();
        if (c == '#') {
            size_t e = q + 1;
            while (hex(at(e))) ++e;
            if (e == q + 1 || (at(e) != 'H' && at(e) != 'h')) return fail(q);
            p_ = e + 1;
            return;
        }
        if (c == '\'') {
            const size_t close = s_.find('\'', q + 1);
            if (close == npos) return fail(q);
            p_ = close + 1;
            return;
        }
        if (c == '[') {
            ++p_;
            expression();
            return expect(']');
        }
        if (!letter(c)) return fail(q);
        Name n = peek_name();
        if (n.single) {
            if (n.text[0] != 'V' || !digit(at(n.end))) return fail(q);
            size_t e = n.end;
            while (digit(at(e))) ++e;
            p_ = e;
            return;
        }
        p_ = n.end;
        if (n.text == "EMPTY") return;
        if (keyword_class(n.text) == KeywordClass::Function) {
            expect('[');
            if (failed()) return;
            expression();
            while (!failed() && accept(',')) expression();
            return expect(']');
        }
        if (accept('[')) subscripts();
    }
};

}  // namespace

std::size_t first_line_error(std::string_view line) { return LineChecker(line).first_error(); }

LineBound bound_line(std::string_view line) {
    LineBound b;
    // Too short to nest that deep or to have a tail to cut.
    if (line.size() <= kMaxErrorTail && line.size() < static_cast<size_t>(kMaxExprDepth)) return b;
    LineChecker c(line);
    const size_t error = c.first_error();
    b.too_deep = c.too_deep_at();
    if (b.too_deep == LineChecker::npos && error != LineChecker::npos && line.size() - error > kMaxErrorTail)
        b.cut = error + kMaxErrorTail;
    return b;
}

}  // namespace osplint::ts_detail
