// The tree-sitter front end: parses a file with the OSP grammar (grammar/) and
// fills the program model (model.h). The node types and fields it reads are
// documented in grammar/NODES.md.
//
// The tree is walked with one TSTreeCursor. Structure (blocks, statements,
// words) is shallow; expressions can nest arbitrarily deep, so their conversion
// stops at kMaxExprDepth and everything below is only swept iteratively for
// comments and syntax errors.
#include "syntax/frontend.h"
#include "syntax/frontend_fast.h"

#include <tree_sitter/api.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <string_view>

extern "C" const TSLanguage* tree_sitter_osp(void);
extern "C" int tree_sitter_osp_keyword_class(const char* upper_name);

namespace osplint {

namespace {

constexpr int kMaxExprDepth = 200;

// Symbol and field ids of the grammar, looked up once.
struct Grammar {
    const TSLanguage* lang = nullptr;
    TSSymbol block, tape_header, tape_mark, comment, block_delete, program_name, program_ref,
        sequence_name, label, word, assignment, address, ncyl, noex, modout, rts, goto_, if_,
        while_, do_, end_, call, modin, coordinate, mnemonic, command, number, hex_constant,
        string, empty, variable, identifier, indexed_variable, hex_subscript, function_call,
        bracket, unary, binary, unexpected;
    TSFieldId f_address, f_value, f_left, f_right, f_name, f_argument, f_condition, f_target,
        f_loop, f_keyword, f_index, f_operator, f_operand, f_expression, f_delete, f_sequence,
        f_program, f_code;

    Grammar() {
        lang = tree_sitter_osp();
        auto sym = [&](const char* name, bool named = true) {
            return ts_language_symbol_for_name(lang, name, static_cast<uint32_t>(std::strlen(name)), named);
        };
        auto field = [&](const char* name) {
            return ts_language_field_id_for_name(lang, name, static_cast<uint32_t>(std::strlen(name)));
        };
        block = sym("block");
        tape_header = sym("tape_header");
        tape_mark = sym("tape_mark");
        comment = sym("comment");
        block_delete = sym("block_delete");
        program_name = sym("program_name");
        program_ref = sym("program_ref");
        sequence_name = sym("sequence_name");
        label = sym("label");
        word = sym("word");
        assignment = sym("assignment");
        address = sym("address");
        ncyl = sym("ncyl_statement");
        noex = sym("noex_statement");
        modout = sym("modout_statement");
        rts = sym("rts_statement");
        goto_ = sym("goto_statement");
        if_ = sym("if_statement");
        while_ = sym("while_statement");
        do_ = sym("do_statement");
        end_ = sym("end_statement");
        call = sym("call_statement");
        modin = sym("modin_statement");
        coordinate = sym("coordinate_statement");
        mnemonic = sym("mnemonic_statement");
        command = sym("command_statement");
        number = sym("number");
        hex_constant = sym("hex_constant");
        string = sym("string");
        empty = sym("empty");
        variable = sym("variable");
        identifier = sym("identifier");
        indexed_variable = sym("indexed_variable");
        hex_subscript = sym("hex_subscript");
        function_call = sym("function_call");
        bracket = sym("bracket_expression");
        unary = sym("unary_expression");
        binary = sym("binary_expression");
        unexpected = sym("unexpected");
        f_address = field("address");
        f_value = field("value");
        f_left = field("left");
        f_right = field("right");
        f_name = field("name");
        f_argument = field("argument");
        f_condition = field("condition");
        f_target = field("target");
        f_loop = field("loop");
        f_keyword = field("keyword");
        f_index = field("index");
        f_operator = field("operator");
        f_operand = field("operand");
        f_expression = field("expression");
        f_delete = field("delete");
        f_sequence = field("sequence");
        f_program = field("program");
        f_code = field("code");
    }
};

const Grammar& grammar() {
    static const Grammar g;
    return g;
}

// ERROR nodes carry the reserved symbol (TSSymbol)-1.
bool is_error(TSNode n) { return ts_node_symbol(n) == static_cast<TSSymbol>(-1); }

ByteRange range_of(TSNode n) { return {ts_node_start_byte(n), ts_node_end_byte(n)}; }

std::string upper(std::string_view s) {
    std::string out(s);
    for (char& c : out)
        if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
    return out;
}

bool is_alnum(unsigned char c) {
    return (c >= '0' && c <= '9') || (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}
bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }


// Value of hex digits (`81` of `#81H`, `002C`).
double hex_value(std::string_view digits) {
    double v = 0;
    for (char c : digits) {
        int d;
        if (c >= '0' && c <= '9') d = c - '0';
        else if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
        else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
        else continue;
        v = v * 16 + d;
    }
    return v;
}

// Where a line stops being valid. Tree-sitter tells whether a line has a
// syntax error; its recovery does not tell where the text stopped making sense.
// LineChecker reads the line again with the grammar's rules (grammar/grammar.js,
// grammar/src/scanner.c) and returns the first character that cannot continue
// the block as written: stray or unknown characters, the token where something
// else is required, the opening `'` of an unclosed string, or the end of the
// line when it ends while something is still required. Blanks never carry the
// error. It is used only to place the first error of a line that tree-sitter
// rejected.
enum class KeywordClass { None = 0, Control = 1, Function = 2, Coordinate = 3, Mnemonic = 4, Command = 5 };

KeywordClass keyword_class(const std::string& upper_name) {
    return static_cast<KeywordClass>(tree_sitter_osp_keyword_class(upper_name.c_str()));
}

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

private:
    std::string_view s_;
    size_t p_ = 0;
    size_t fail_ = npos;
    int depth_ = 0;         // expression nesting
    bool gave_up_ = false;  // nested too deeply to check

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

    void unary() {
        while (!at_end()) {
            const char c = s_[p_];
            if (c == '-' || c == '+') {
                ++p_;
            } else if (letter(c) && peek_name().text == "NOT") {
                p_ = peek_name().end;
            } else {
                break;
            }
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

// Walks the children of the cursor's node; `f(field_id)` is called with the
// cursor on each child and must leave it there.
template <class F>
void for_each_child(TSTreeCursor* c, F&& f) {
    if (!ts_tree_cursor_goto_first_child(c)) return;
    do {
        f(ts_tree_cursor_current_field_id(c));
    } while (ts_tree_cursor_goto_next_sibling(c));
    ts_tree_cursor_goto_parent(c);
}

class Converter {
public:
    Converter(const std::string& text, std::vector<Block>& blocks, const SourceText& source)
        : g_(grammar()), text_(text), blocks_(blocks), source_(source) {}

    // Converts the nodes of `root`. Nodes that start on a line marked in `skip`
    // are left out (those lines are parsed again on their own). When the whole
    // parse failed, `root` is an ERROR node: its complete lines are converted and
    // the loose tokens left over make one syntax error per line.
    void run(TSNode root, const std::vector<char>* skip = nullptr) {
        const bool root_error = is_error(root);
        Block* loose_block = nullptr;
        ByteRange loose{0, 0};
        uint32_t loose_offending = 0;
        bool loose_found_unexpected = false;
        auto flush = [&] {
            if (!loose_block) return;
            const uint32_t at = loose_found_unexpected ? loose_offending : loose.end;
            syntax_error(*loose_block, {at, loose.end}, explain(*loose_block, at));
            loose_block = nullptr;
        };
        TSTreeCursor c = ts_tree_cursor_new(root);
        for_each_child(&c, [&](TSFieldId) {
            TSNode n = ts_tree_cursor_current_node(&c);
            Block* b = block_at(ts_node_start_byte(n));
            if (!b || (skip && (*skip)[b->line - 1])) return;
            if (!root_error || is_line_node(n)) {
                flush();
                line_node(&c, n, *b);
                return;
            }
            // A loose token or unfinished construct of the failed parse.
            if (loose_block != b) {
                flush();
                loose_block = b;
                loose = range_of(n);
                loose_found_unexpected = false;
            }
            loose.end = std::max(loose.end, ts_node_end_byte(n));
            if (!loose_found_unexpected && ts_node_symbol(n) == g_.unexpected) {
                loose_found_unexpected = true;
                loose_offending = ts_node_start_byte(n);
            }
            if (ts_node_symbol(n) == g_.comment) comment(n, *b);
        });
        flush();
        ts_tree_cursor_delete(&c);
    }

    // Nodes that stand for (part of) a line on their own.
    bool is_line_node(TSNode n) const {
        const TSSymbol s = ts_node_symbol(n);
        return s == g_.block || s == g_.tape_header || s == g_.tape_mark || s == g_.comment || is_error(n);
    }

private:
    const Grammar& g_;
    const std::string& text_;
    std::vector<Block>& blocks_;
    const SourceText& source_;
    const Block* checked_block_ = nullptr;    // block whose line LineChecker has placed
    const Block* mergeable_block_ = nullptr;  // block and error count of the last
    size_t mergeable_count_ = 0;              // SyntaxError that may be extended

    std::string_view text(TSNode n) const {
        const uint32_t b = ts_node_start_byte(n);
        const uint32_t e = ts_node_end_byte(n);
        return std::string_view(text_).substr(b, e > b ? e - b : 0);
    }
    std::string_view text(ByteRange r) const {
        return std::string_view(text_).substr(r.begin, r.size());
    }

    Block* block_at(uint32_t offset) {
        if (blocks_.empty()) return nullptr;
        const uint32_t line = std::min<uint32_t>(source_.line_of(offset), static_cast<uint32_t>(blocks_.size()));
        return &blocks_[line - 1];
    }

    static void error(Block& b, ByteRange r, std::string message) {
        b.errors.push_back({r, std::move(message)});
    }

    // A syntax error found in the tree; extends the previous one when adjacent.
    //
    // An error starts at the first character that cannot continue the block,
    // never on a blank: a range that starts on blanks (a missing token) moves
    // to the next character, or to the end of the line.
    void syntax_error(Block& b, ByteRange r, std::string message) {
        uint32_t begin = std::min(r.begin, b.range.end);
        while (begin < b.range.end && is_blank(text_[begin])) ++begin;
        r = {begin, std::max(begin, std::min(r.end, b.range.end))};
        if (checked_block_ != &b) {
            // The line's first syntax error starts where the line stops being valid.
            checked_block_ = &b;
            const size_t at = LineChecker(text(b.range)).first_error();
            if (at != LineChecker::npos) {
                const uint32_t where = b.range.begin + static_cast<uint32_t>(at);
                if (where != r.begin) message = explain(b, where);
                r = {where, std::max(r.end, lexeme_end(where, b.range.end))};
            }
        }
        if (extend_error(b, r)) return;
        b.errors.push_back({r, std::move(message)});
        mark_mergeable(b);
    }

    // ------------------------------------------------------------------ lines

    void line_node(TSTreeCursor* c, TSNode n, Block& b) {
        const TSSymbol s = ts_node_symbol(n);
        if (is_error(n)) {
            error_node(c, n, b);
        } else if (s == g_.block) {
            block(c, b);
        } else if (s == g_.tape_header) {
            b.kind = LineKind::Header;
        } else if (s == g_.tape_mark) {
            b.kind = LineKind::TapeMark;
        } else if (s == g_.comment) {
            comment(n, b);
        } else {
            sweep(c, b);
        }
    }

    void comment(TSNode n, Block& b) {
        const ByteRange r = range_of(n);
        b.comments.push_back({r});
        if (r.size() < 2 || text_[r.end - 1] != ')')
            error(b, r, "unterminated comment: expected ')' before the end of the line");
    }

    void block(TSTreeCursor* c, Block& b) {
        // Most named children are words, each with one or two expression nodes.
        const uint32_t named = ts_node_named_child_count(ts_tree_cursor_current_node(c));
        b.words.reserve(b.words.size() + named);
        b.exprs.reserve(b.exprs.size() + named + named / 2);
        for_each_child(c, [&](TSFieldId field) {
            TSNode n = ts_tree_cursor_current_node(c);
            if (field == g_.f_delete) {
                if (ts_node_has_error(n)) return sweep(c, b);  // a `/` invented by recovery
                b.block_delete = true;
                b.block_delete_range = range_of(n);
            } else if (field == g_.f_sequence) {
                label(n, b.sequence, b, "a sequence name");
            } else if (field == g_.f_program) {
                label(n, b.program_name, b, "a program name");
            } else {
                item(c, n, b, Context::Block);
            }
        });
    }

    void label(TSNode n, std::optional<Label>& out, Block& b, const char* what) {
        if (ts_node_is_missing(n)) {
            syntax_error(b, range_of(n), std::string("expected ") + what);
            return;
        }
        out = Label{upper(text(n)), range_of(n)};
    }

    // -------------------------------------------------------------- block items

    enum class Context { Block, CallArgs };

    void item(TSTreeCursor* c, TSNode n, Block& b, Context ctx) {
        const TSSymbol s = ts_node_symbol(n);
        if (is_error(n)) return error_node(c, n, b);
        if (ts_node_is_missing(n)) return missing(n, b);
        if (s == g_.word) return word(c, n, b);
        if (s == g_.assignment) return assignment(c, n, b, ctx);
        if (s == g_.label) return label_word(n, b);
        if (s == g_.comment) return comment(n, b);
        if (s == g_.unexpected) return unexpected(n, b);
        if (s == g_.ncyl) return keyword_statement(n, b, StmtKind::Ncyl);
        if (s == g_.noex) return keyword_statement(n, b, StmtKind::Noex);
        if (s == g_.modout) return keyword_statement(n, b, StmtKind::Modout);
        if (s == g_.rts) return keyword_statement(n, b, StmtKind::Rts);
        if (s == g_.goto_ || s == g_.if_ || s == g_.while_ || s == g_.do_ || s == g_.end_)
            return control_statement(c, n, b, s);
        if (s == g_.call || s == g_.modin) return call_statement(c, n, b, s == g_.call ? StmtKind::Call : StmtKind::Modin);
        if (s == g_.coordinate || s == g_.mnemonic || s == g_.command)
            return mnemonic_statement(c, n, b, s == g_.coordinate ? StmtKind::CoordCalc : StmtKind::Mnemonic);
        if (ts_node_has_error(n)) sweep(c, b);
    }

    // `G00`, `X-.75`, `X=XPOS+8`.
    void word(TSTreeCursor* c, TSNode n, Block& b) {
        Word w;
        w.range = range_of(n);
        bool have_value = false;
        for_each_child(c, [&](TSFieldId field) {
            TSNode ch = ts_tree_cursor_current_node(c);
            if (field == g_.f_address) {
                w.address = upper(text(ch));
                w.address_range = range_of(ch);
            } else if (field == g_.f_code) {
                // `HA`: address H, value "A" (no number).
                const ByteRange r = range_of(ch);
                have_value = true;
                w.address = upper(text(ByteRange{r.begin, r.begin + 1}));
                w.address_range = {r.begin, r.begin + 1};
                w.value_range = {r.begin + 1, r.end};
                w.value_text = upper(text(w.value_range));
            } else if (field == g_.f_value) {
                have_value = true;
                if (ts_node_is_missing(ch)) {
                    w.value_range = range_of(ch);
                    syntax_error(b, w.value_range,
                                 w.equals ? "expected an expression after '" + w.address + "='"
                                          : "expected a number after '" + w.address + "'");
                    return;
                }
                w.value_range = range_of(ch);
                w.value_text = std::string(text(ch));
                if (w.equals) {
                    w.value = expr(c, b, 0);
                    w.number = literal_value(b, w.value);
                } else {
                    plain_number(ch, b, w);
                }
            } else if (!ts_node_is_named(ch) && text(ch) == "=") {
                w.equals = true;
            } else if (is_error(ch)) {
                error_node(c, ch, b);
            } else if (ts_node_symbol(ch) == g_.comment) {
                comment(ch, b);
            }
        });
        if (!have_value && !w.address.empty())
            syntax_error(b, {w.range.end, w.range.end}, "expected a number or '=' after '" + w.address + "'");
        b.words.push_back(std::move(w));
    }

    // The glued number of `X-.75`: value = Unary(-, Number(.75)), number = -0.75.
    void plain_number(TSNode n, Block& b, Word& w) {
        const ByteRange r = range_of(n);
        std::string_view t = text(n);
        char sign = 0;
        if (!t.empty() && (t[0] == '-' || t[0] == '+')) {
            sign = t[0];
            t.remove_prefix(1);
        }
        const double v = decimal_literal_value(t);
        ExprNode num;
        num.kind = ExprKind::Number;
        num.number = v;
        num.range = {sign ? r.begin + 1 : r.begin, r.end};
        const ExprId num_id = push(b, std::move(num));
        if (sign) {
            ExprNode un;
            un.kind = ExprKind::Unary;
            un.op = std::string(1, sign);
            un.children.push_back(num_id);
            un.range = r;
            w.value = push(b, std::move(un));
            w.number = sign == '-' ? -v : v;
        } else {
            w.value = num_id;
            w.number = v;
        }
    }

    // A numeric literal, possibly signed (`5`, `-.75`), as a number.
    std::optional<double> literal_value(const Block& b, ExprId id) const {
        const ExprNode* e = b.expr(id);
        if (!e) return std::nullopt;
        if (e->kind == ExprKind::Number) return e->number;
        if (e->kind == ExprKind::Unary && (e->op == "-" || e->op == "+") && e->children.size() == 1) {
            const ExprNode* inner = b.expr(e->children[0]);
            if (inner && inner->kind == ExprKind::Number) return e->op == "-" ? -inner->number : inner->number;
        }
        return std::nullopt;
    }

    // `N0207` / `NAT3` inside a block (`G85 N0207 D7`): a word with address N.
    void label_word(TSNode n, Block& b) {
        Word w;
        w.address = "N";
        w.range = range_of(n);
        w.address_range = {w.range.begin, w.range.begin + 1};
        w.value_range = {w.range.begin + 1, w.range.end};
        w.value_text = upper(text(w.value_range));
        const std::string_view v = text(w.value_range);
        if (!v.empty() && std::all_of(v.begin(), v.end(), [](char ch) { return ch >= '0' && ch <= '9'; })) {
            ExprNode num;
            num.kind = ExprKind::Number;
            num.number = decimal_literal_value(v);
            num.range = w.value_range;
            w.number = num.number;
            w.value = push(b, std::move(num));
            w.value_text = std::string(v);
        }
        b.words.push_back(std::move(w));
    }

    // `VC1=2`, `VTOFX[16]=...` become Assignments; `PX=0`, `FA=200` (and every
    // plain name in a call's arguments) become Words with equals=true.
    void assignment(TSTreeCursor* c, TSNode n, Block& b, Context ctx) {
        TSNode left = ts_node_child_by_field_id(n, g_.f_left);
        const bool indexed = !ts_node_is_null(left) && ts_node_symbol(left) == g_.indexed_variable;
        const std::string_view name = ts_node_is_null(left) ? std::string_view() : text(left);
        const bool system_or_common = name.size() >= 2 && (name[0] == 'V' || name[0] == 'v');
        const bool as_assignment = indexed || (ctx == Context::Block && system_or_common);

        if (as_assignment) {
            Assignment a;
            a.range = range_of(n);
            for_each_child(c, [&](TSFieldId field) {
                TSNode ch = ts_tree_cursor_current_node(c);
                if (field == g_.f_left) a.target = expr(c, b, 0);
                else if (field == g_.f_right) a.value = expr(c, b, 0);
                else other_child(c, ch, b);
            });
            b.assignments.push_back(std::move(a));
            return;
        }
        Word w;
        w.range = range_of(n);
        w.equals = true;
        for_each_child(c, [&](TSFieldId field) {
            TSNode ch = ts_tree_cursor_current_node(c);
            if (field == g_.f_left) {
                w.address = upper(text(ch));
                w.address_range = range_of(ch);
            } else if (field == g_.f_right) {
                w.value_range = range_of(ch);
                w.value_text = std::string(text(ch));
                w.value = expr(c, b, 0);
                w.number = literal_value(b, w.value);
            } else {
                other_child(c, ch, b);
            }
        });
        b.words.push_back(std::move(w));
    }

    // Children a converter does not model: comments, errors, missing tokens.
    void other_child(TSTreeCursor* c, TSNode n, Block& b) {
        if (is_error(n)) error_node(c, n, b);
        else if (ts_node_is_missing(n)) missing(n, b);
        else if (ts_node_symbol(n) == g_.comment) comment(n, b);
        else if (ts_node_symbol(n) == g_.unexpected) unexpected(n, b);
        else if (ts_node_has_error(n)) sweep(c, b);
    }

    // ------------------------------------------------------------- statements

    Statement& new_statement(TSNode n, Block& b, StmtKind kind) {
        Statement s;
        s.kind = kind;
        s.range = range_of(n);
        TSNode kw = ts_node_child(n, 0);
        s.keyword_range = ts_node_is_null(kw) ? s.range : range_of(kw);
        b.statements.push_back(std::move(s));
        return b.statements.back();
    }

    void keyword_statement(TSNode n, Block& b, StmtKind kind) { new_statement(n, b, kind); }

    // GOTO / IF / WHILE / DO / END.
    void control_statement(TSTreeCursor* c, TSNode n, Block& b, TSSymbol s) {
        StmtKind kind = s == g_.goto_ ? StmtKind::Goto
                        : s == g_.if_ ? StmtKind::If
                        : s == g_.while_ ? StmtKind::While
                        : s == g_.do_ ? StmtKind::Do
                                      : StmtKind::End;
        const size_t index = b.statements.size();
        new_statement(n, b, kind);
        const std::string keyword = upper(text(b.statements[index].keyword_range));
        ExprId cond = kNoExpr;
        int loop = -1;
        std::optional<Label> target;
        for_each_child(c, [&](TSFieldId field) {
            TSNode ch = ts_tree_cursor_current_node(c);
            if (field == g_.f_condition) {
                cond = ts_node_is_missing(ch) ? missing_expr(ch, b) : expr(c, b, 0);
            } else if (field == g_.f_target) {
                if (ts_node_is_missing(ch)) {
                    syntax_error(b, range_of(ch), "expected a sequence name after " + keyword);
                } else {
                    target = Label{upper(text(ch)), range_of(ch)};
                }
            } else if (field == g_.f_loop) {
                if (ts_node_is_missing(ch)) {
                    syntax_error(b, range_of(ch), "expected a loop number after " + std::string(kind == StmtKind::While ? "DO" : keyword));
                } else {
                    const double v = decimal_literal_value(text(ch));
                    loop = v >= 0 && v <= 1e9 && v == std::floor(v) ? static_cast<int>(v) : -1;
                    if (loop < 0) error(b, range_of(ch), "loop number must be a whole number");
                }
            } else {
                other_child(c, ch, b);
            }
        });
        Statement& st = b.statements[index];
        st.expr = cond;
        st.loop = loop;
        if (target) {
            st.name = std::move(target->name);
            st.name_range = target->range;
        }
    }

    // CALL / MODIN Oname [Q..] [args]: the arguments become words of the block.
    void call_statement(TSTreeCursor* c, TSNode n, Block& b, StmtKind kind) {
        const size_t index = b.statements.size();
        new_statement(n, b, kind);
        const std::string keyword = kind == StmtKind::Call ? "CALL" : "MODIN";
        std::optional<Label> name;
        for_each_child(c, [&](TSFieldId field) {
            TSNode ch = ts_tree_cursor_current_node(c);
            if (field == g_.f_name) {
                if (ts_node_is_missing(ch))
                    syntax_error(b, range_of(ch), "expected a program name (O...) after " + keyword);
                else
                    name = Label{upper(text(ch)), range_of(ch)};
            } else if (field == g_.f_argument) {
                item(c, ch, b, Context::CallArgs);
            } else {
                other_child(c, ch, b);
            }
        });
        if (name) {
            b.statements[index].name = std::move(name->name);
            b.statements[index].name_range = name->range;
        }
    }

    // Coordinate calculation, mnemonics and free-form commands: name = keyword.
    void mnemonic_statement(TSTreeCursor* c, TSNode n, Block& b, StmtKind kind) {
        const size_t index = b.statements.size();
        new_statement(n, b, kind);
        for_each_child(c, [&](TSFieldId field) {
            TSNode ch = ts_tree_cursor_current_node(c);
            if (field == g_.f_keyword) {
                b.statements[index].name = upper(text(ch));
                b.statements[index].name_range = range_of(ch);
            } else if (field == g_.f_argument) {
                item(c, ch, b, Context::Block);
            } else if (field == g_.f_operand) {
                if (ts_node_symbol(ch) == g_.unexpected) unexpected(ch, b);  // else free-form, not modelled
            } else {
                other_child(c, ch, b);
            }
        });
    }

    // ------------------------------------------------------------ expressions

    ExprId push(Block& b, ExprNode e) {
        b.exprs.push_back(std::move(e));
        return static_cast<ExprId>(b.exprs.size() - 1);
    }

    ExprId error_expr(Block& b, ByteRange r) {
        ExprNode e;
        e.kind = ExprKind::Error;
        e.range = r;
        return push(b, std::move(e));
    }

    ExprId missing_expr(TSNode n, Block& b) {
        missing(n, b);
        return error_expr(b, range_of(n));
    }

    // Converts the expression under the cursor.
    ExprId expr(TSTreeCursor* c, Block& b, int depth) {
        TSNode n = ts_tree_cursor_current_node(c);
        const ByteRange r = range_of(n);
        if (ts_node_is_missing(n)) return missing_expr(n, b);
        if (is_error(n)) {
            error_node(c, n, b);
            return error_expr(b, r);
        }
        if (depth > kMaxExprDepth) {
            bool reported = false;
            for (const auto& e : b.errors) reported |= e.message == "expression nested too deeply";
            if (!reported) error(b, r, "expression nested too deeply");
            sweep(c, b);
            return error_expr(b, r);
        }
        const TSSymbol s = ts_node_symbol(n);
        ExprNode e;
        e.range = r;
        if (s == g_.number) {
            e.kind = ExprKind::Number;
            e.number = decimal_literal_value(text(n));
        } else if (s == g_.hex_constant) {
            const std::string_view t = text(n);  // #81H
            e.kind = ExprKind::HexConst;
            e.text = std::string(t);
            e.number = hex_value(t.size() >= 2 ? t.substr(1, t.size() - 2) : std::string_view());
        } else if (s == g_.hex_subscript) {
            e.kind = ExprKind::HexConst;
            e.text = std::string(text(n));
            e.number = hex_value(e.text);
        } else if (s == g_.string) {
            std::string_view t = text(n);
            e.kind = ExprKind::String;
            t.remove_prefix(1);
            if (!t.empty() && t.back() == '\'') {
                t.remove_suffix(1);
            } else {
                error(b, r, "unterminated string: expected \"'\" before the end of the line");
            }
            e.text = std::string(t);
        } else if (s == g_.empty) {
            e.kind = ExprKind::Empty;
        } else if (s == g_.variable || s == g_.identifier) {
            e.kind = ExprKind::Variable;
            e.text = upper(text(n));
        } else if (s == g_.indexed_variable) {
            e.kind = ExprKind::Variable;
            for_each_child(c, [&](TSFieldId field) {
                TSNode ch = ts_tree_cursor_current_node(c);
                if (field == g_.f_name) e.text = upper(text(ch));
                else if (field == g_.f_index) e.children.push_back(expr(c, b, depth + 1));
                else other_child(c, ch, b);
            });
        } else if (s == g_.function_call) {
            e.kind = ExprKind::Function;
            for_each_child(c, [&](TSFieldId field) {
                TSNode ch = ts_tree_cursor_current_node(c);
                if (field == g_.f_name) e.text = upper(text(ch));
                else if (field == g_.f_argument) e.children.push_back(expr(c, b, depth + 1));
                else other_child(c, ch, b);
            });
        } else if (s == g_.bracket) {
            e.kind = ExprKind::Bracket;
            for_each_child(c, [&](TSFieldId field) {
                TSNode ch = ts_tree_cursor_current_node(c);
                if (field == g_.f_expression) e.children.push_back(expr(c, b, depth + 1));
                else other_child(c, ch, b);
            });
        } else if (s == g_.unary || s == g_.binary) {
            e.kind = s == g_.unary ? ExprKind::Unary : ExprKind::Binary;
            for_each_child(c, [&](TSFieldId field) {
                TSNode ch = ts_tree_cursor_current_node(c);
                if (field == g_.f_operator) e.op = upper(text(ch));
                else if (field == g_.f_operand || field == g_.f_left || field == g_.f_right)
                    e.children.push_back(expr(c, b, depth + 1));
                else other_child(c, ch, b);
            });
        } else {
            e.kind = ExprKind::Error;
            if (ts_node_has_error(n)) sweep(c, b);
        }
        return push(b, std::move(e));
    }

    // ------------------------------------------------------------------ errors

    // A token the parser inserted to recover (zero width).
    void missing(TSNode n, Block& b) {
        const ByteRange r = range_of(n);
        const std::string_view type = ts_node_type(n);
        const std::string prev = previous_lexeme(b, r.begin);
        std::string message;
        if (type == "label") message = "expected a sequence name after " + (prev == "]" ? std::string("IF [...]") : prev);
        else if (type == "program_ref") message = "expected a program name (O...) after " + prev;
        else if (prev == "=") message = "expected an expression after '='";
        else if (type == "number" && prev.size() == 1 && prev[0] >= 'A' && prev[0] <= 'Z')
            message = "expected a number after '" + prev + "'";
        else if (type == "number" && (prev == "DO" || prev == "END")) message = "expected a loop number after " + prev;
        else if (ts_node_is_named(n)) message = "expected an expression after '" + prev + "'";
        else if (type == "]" || type == "[" || type == "=") message = "expected '" + std::string(type) + "'";
        else message = explain(b, r.begin);  // a token recovery invented (like a `/`)
        syntax_error(b, r, std::move(message));
    }

    // An ERROR node: one SyntaxError for its whole range, plus whatever can be
    // salvaged from inside (comments, a sequence or program name that starts the
    // line). The walk is iterative: ERROR nodes can hold deep subtrees.
    void error_node(TSTreeCursor* c, TSNode n, Block& b) {
        const ByteRange r = range_of(n);
        if (!extend_error(b, r)) {
            auto [at, message] = describe_error(c, n, b);
            syntax_error(b, {at, r.end}, std::move(message));
        }
        sweep(c, b, /*inside_error=*/true);
    }

    // Text the scanner could not lex, accepted after a block's first item.
    void unexpected(TSNode n, Block& b) {
        const ByteRange r = range_of(n);
        if (extend_error(b, r)) return;
        syntax_error(b, r, explain(b, r.begin));
    }

    // Consecutive ERROR nodes and unexpected characters (separated by blanks at
    // most) form one SyntaxError: the last one is extended when `r` follows it.
    bool extend_error(Block& b, ByteRange r) {
        if (mergeable_block_ != &b || b.errors.size() != mergeable_count_) return false;
        SyntaxError& last = b.errors.back();
        if (r.begin < last.range.begin) return false;
        for (uint32_t i = last.range.end; i < r.begin; ++i)
            if (!is_blank(text_[i])) return false;
        last.range.end = std::max(last.range.end, r.end);
        return true;
    }
    void mark_mergeable(Block& b) {
        mergeable_block_ = &b;
        mergeable_count_ = b.errors.size();
    }

    // Iterative walk of the subtree under the cursor: records comments, ERROR
    // nodes (outermost only), missing tokens, and salvages labels inside errors.
    void sweep(TSTreeCursor* c, Block& b, bool inside_error = false) {
        TSTreeCursor w = ts_tree_cursor_copy(c);
        // Descend from the root of the subtree and stop when we climb back to it.
        uint32_t depth = 0;
        std::vector<bool> in_error;  // per depth: inside an ERROR node
        in_error.push_back(inside_error);
        bool descend = true;
        while (true) {
            if (descend && ts_tree_cursor_goto_first_child(&w)) {
                ++depth;
                in_error.push_back(in_error.back());
            } else {
                while (depth > 0 && !ts_tree_cursor_goto_next_sibling(&w)) {
                    ts_tree_cursor_goto_parent(&w);
                    --depth;
                    in_error.pop_back();
                }
                if (depth == 0) break;
                in_error.back() = in_error[in_error.size() - 2];
            }
            TSNode n = ts_tree_cursor_current_node(&w);
            descend = true;
            const TSSymbol s = ts_node_symbol(n);
            if (s == g_.comment) {
                comment(n, b);
                descend = false;
            } else if (is_error(n)) {
                if (!in_error.back() && !extend_error(b, range_of(n))) {
                    auto [at, message] = describe_error(&w, n, b);
                    syntax_error(b, {at, ts_node_end_byte(n)}, std::move(message));
                }
                in_error.back() = true;
            } else if (ts_node_is_missing(n)) {
                if (!in_error.back()) missing(n, b);
                descend = false;
            } else if (s == g_.unexpected) {
                if (!in_error.back()) unexpected(n, b);
            } else if (in_error.back() && (s == g_.sequence_name || s == g_.program_name)) {
                salvage_label(n, b, s);
                descend = false;
            }
        }
        ts_tree_cursor_delete(&w);
    }

    void salvage_label(TSNode n, Block& b, TSSymbol s) {
        const ByteRange r = range_of(n);
        // Only at the start of the line's content.
        for (uint32_t i = b.range.begin; i < r.begin; ++i) {
            const char ch = text_[i];
            if (!is_blank(ch) && ch != '/') return;
        }
        Label l{upper(text(n)), r};
        if (s == g_.sequence_name && !b.sequence) b.sequence = std::move(l);
        if (s == g_.program_name && !b.program_name) b.program_name = std::move(l);
    }

    // A message for an ERROR node: what was unexpected and, where the context
    // tells, what was expected instead.
    std::pair<uint32_t, std::string> describe_error(TSTreeCursor* c, TSNode n, const Block& b) {
        const ByteRange r = range_of(n);
        // The offending text is the first character skipped during recovery
        // (an `unexpected` token). Without one, the ERROR holds either a single
        // stray token (the culprit itself) or an unfinished construct, which the
        // text after it failed to continue.
        uint32_t offending = r.end;
        uint32_t last_leaf = r.begin;
        bool found = false;
        TSTreeCursor w = ts_tree_cursor_copy(c);
        if (!ts_node_eq(ts_tree_cursor_current_node(&w), n)) ts_tree_cursor_reset(&w, n);
        uint32_t depth = 0;
        bool descend = true;
        while (!found) {
            if (descend && ts_tree_cursor_goto_first_child(&w)) {
                ++depth;
            } else {
                while (depth > 0 && !ts_tree_cursor_goto_next_sibling(&w)) {
                    ts_tree_cursor_goto_parent(&w);
                    --depth;
                }
                if (depth == 0) break;
            }
            TSNode m = ts_tree_cursor_current_node(&w);
            descend = ts_node_symbol(m) != g_.comment;
            if (ts_node_symbol(m) == g_.unexpected) {
                offending = ts_node_start_byte(m);
                found = true;
            } else if (descend && ts_node_child_count(m) == 0 && ts_node_end_byte(m) > ts_node_start_byte(m)) {
                last_leaf = ts_node_start_byte(m);
            }
        }
        ts_tree_cursor_delete(&w);
        if (!found && !needs_continuation(previous_lexeme(b, r.end))) offending = last_leaf;
        return {offending, explain(b, offending)};
    }

    // Lexemes after which a block cannot end.
    static bool needs_continuation(const std::string& lexeme) {
        static const char* const kWords[] = {"GOTO", "CALL", "MODIN", "IF", "WHILE", "DO", "=", "[", ",",
                                             "+", "-", "*", "/", "EQ", "NE", "GT", "GE", "LT", "LE",
                                             "AND", "OR", "EOR", "NOT"};
        for (const char* w : kWords)
            if (lexeme == w) return true;
        return lexeme.size() == 1 && lexeme[0] >= 'A' && lexeme[0] <= 'Z';  // an address letter
    }

    uint32_t first_content(const Block& b) const {
        uint32_t i = b.range.begin;
        while (i < b.range.end && is_blank(text_[i])) ++i;
        return i;
    }

    // End of the lexeme at `at`: a run of letters/digits/dots, else one character.
    uint32_t lexeme_end(uint32_t at, uint32_t end) const {
        if (at >= end) return at;
        uint32_t e = at;
        while (e < end && (is_alnum(static_cast<unsigned char>(text_[e])) || text_[e] == '.')) ++e;
        if (e > at) return e;
        e = at + 1;
        if (static_cast<unsigned char>(text_[at]) >= 0xC0)  // a UTF-8 sequence
            while (e < end && (static_cast<unsigned char>(text_[e]) & 0xC0) == 0x80) ++e;
        return e;
    }

    // The lexeme at `at` for a message.
    std::string lexeme_at(uint32_t at, uint32_t end) const {
        if (at >= end) return {};
        const auto ch = static_cast<unsigned char>(text_[at]);
        if (is_alnum(ch) || ch == '.') {
            uint32_t e = at;
            while (e < end && e - at < 24 && (is_alnum(static_cast<unsigned char>(text_[e])) || text_[e] == '.')) ++e;
            return "'" + std::string(text_.substr(at, e - at)) + "'";
        }
        if (ch >= 0xC0) {  // a well-formed UTF-8 character is shown as such
            const std::string_view seq = std::string_view(text_).substr(at, lexeme_end(at, end) - at);
            if (seq.size() > 1 && is_valid_utf8(seq)) return "'" + std::string(seq) + "'";
        }
        if (ch >= 0x80 || ch < 0x20 || ch == 0x7F) {
            static const char* hex = "0123456789ABCDEF";
            std::string s = "byte 0x";
            s += hex[ch >> 4];
            s += hex[ch & 15];
            return s;
        }
        if (ch == '\'') return "\"'\"";
        return "'" + std::string(1, static_cast<char>(ch)) + "'";
    }

    // The lexeme that ends just before `at` on the line (skipping blanks and comments).
    std::string previous_lexeme(const Block& b, uint32_t at) const {
        uint32_t i = at;
        while (i > b.range.begin) {
            const char ch = text_[i - 1];
            if (is_blank(ch)) {
                --i;
            } else if (ch == ')') {  // skip a comment backwards
                uint32_t j = i - 1;
                while (j > b.range.begin && text_[j - 1] != '(') --j;
                if (j == b.range.begin) break;
                i = j - 1;
            } else {
                break;
            }
        }
        if (i == b.range.begin) return {};
        const auto last = static_cast<unsigned char>(text_[i - 1]);
        if (!is_alnum(last)) return std::string(1, static_cast<char>(last));
        uint32_t s = i;
        while (s > b.range.begin && is_alnum(static_cast<unsigned char>(text_[s - 1]))) --s;
        return upper(text_.substr(s, i - s));
    }

    // `[` minus `]` on the line before `at`, outside comments and strings.
    int open_brackets(const Block& b, uint32_t at) const {
        int depth = 0;
        for (uint32_t i = b.range.begin; i < at && i < b.range.end; ++i) {
            const char ch = text_[i];
            if (ch == '(') {
                while (i < at && text_[i] != ')') ++i;
            } else if (ch == '\'') {
                ++i;
                while (i < at && text_[i] != '\'') ++i;
            } else if (ch == '[') {
                ++depth;
            } else if (ch == ']') {
                --depth;
            }
        }
        return depth;
    }

    std::string explain(const Block& b, uint32_t offending) const {
        uint32_t at = offending;
        while (at < b.range.end && is_blank(text_[at])) ++at;
        const std::string what = at >= b.range.end ? "end of line" : lexeme_at(at, b.range.end);
        if (at < b.range.end && text_[at] == '\'')
            return "unterminated string: expected \"'\" before the end of the line";
        if (at < b.range.end && (text_[at] == '-' || text_[at] == '+') && at > b.range.begin &&
            std::isalpha(static_cast<unsigned char>(text_[at - 1])))
            return "expected a number after '" + upper(text_.substr(at - 1, 2)) + "'";
        const std::string prev = previous_lexeme(b, offending);
        const std::string found = ", found " + what;
        if (prev == "GOTO") return "expected a sequence name after GOTO" + found;
        if (prev == "CALL" || prev == "MODIN") return "expected a program name (O...) after " + prev + found;
        if (prev == "IF" || prev == "WHILE") return "expected '[' after " + prev + found;
        if (prev == "DO") return "expected a loop number after DO" + found;
        if (prev == "=") return "expected an expression after '='" + found;
        if (prev == "[" || prev == ",") return "expected an expression after '" + prev + "'" + found;
        if ((needs_continuation(prev) && prev.size() > 1) || prev == "+" || prev == "-" || prev == "*" || prev == "/")
            return "expected an operand after '" + prev + "'" + found;
        if (prev.size() == 1 && prev[0] >= 'A' && prev[0] <= 'Z')
            return "expected a number or '=' after '" + prev + "'" + found;
        if (open_brackets(b, offending) > 0) return "expected ']' before " + what;
        if (at + 1 < b.range.end && (text_[at] == 'O' || text_[at] == 'o') &&
            std::isdigit(static_cast<unsigned char>(text_[at + 1])))
            return "unexpected " + what + ": O is a program name only at the start of a line";
        if (at + 1 < b.range.end && std::isalpha(static_cast<unsigned char>(text_[at])) &&
            std::isalpha(static_cast<unsigned char>(text_[at + 1]))) {
            uint32_t e = lexeme_end(at, b.range.end);
            while (e < b.range.end && is_blank(text_[e])) ++e;
            if (e >= b.range.end || (text_[e] != '=' && text_[e] != '['))
                return "unknown command " + what + " (a variable or multi-letter address needs '=')";
        }
        // `IF [...]` must be followed by its jump target.
        if (prev == "]" && starts_with_if(b)) return "expected a sequence name after IF [...]" + found;
        return "unexpected " + what;
    }

    bool starts_with_if(const Block& b) const {
        // IF is the first keyword of the block content, after an optional sequence name.
        uint32_t i = first_content(b);
        auto word_at = [&](uint32_t p) {
            uint32_t e = p;
            while (e < b.range.end && is_alnum(static_cast<unsigned char>(text_[e]))) ++e;
            return std::pair<std::string, uint32_t>(upper(text_.substr(p, e - p)), e);
        };
        auto [w, e] = word_at(i);
        if (w == "IF") return true;
        if (!w.empty() && w[0] == 'N') {
            i = e;
            while (i < b.range.end && (is_blank(text_[i]) || text_[i] == '/')) ++i;
            return word_at(i).first == "IF";
        }
        return false;
    }

};

// Lines that become blocks: every terminated line, plus a non-empty last line.
uint32_t block_count(const SourceText& src) {
    const uint32_t lines = src.line_count();
    if (lines == 0) return 0;
    const uint32_t last_start = src.line_start(lines);
    return last_start < src.size() ? lines : lines - 1;
}

// Lines covered by a node that spans several lines. Only error recovery makes
// such nodes: tree-sitter sometimes merges a bad line with the next one (when
// both are bad). Those lines are parsed again one by one so that every error
// stays on its line.
std::vector<char> lines_to_reparse(TSNode root, const SourceText& src, size_t count) {
    const Grammar& g = grammar();
    std::vector<char> marks(count, 0);
    auto mark = [&](TSNode n) {
        const uint32_t b = ts_node_start_byte(n);
        const uint32_t e = ts_node_end_byte(n);
        const uint32_t first = src.line_of(b);
        const uint32_t last = src.line_of(e > b ? e - 1 : b);
        for (uint32_t l = first; l <= last && l <= count; ++l) marks[l - 1] = 1;
    };
    auto multi_line = [&](TSNode n) {
        const uint32_t b = ts_node_start_byte(n);
        const uint32_t e = ts_node_end_byte(n);
        return src.line_of(b) != src.line_of(e > b ? e - 1 : b);
    };
    const bool root_error = is_error(root);
    TSTreeCursor c = ts_tree_cursor_new(root);
    for_each_child(&c, [&](TSFieldId) {
        TSNode n = ts_tree_cursor_current_node(&c);
        if (!ts_node_has_error(n) && !root_error) return;
        const TSSymbol s = ts_node_symbol(n);
        const bool loose = root_error && s != g.block && s != g.tape_header && s != g.tape_mark &&
                           s != g.comment && !is_error(n);  // tokens of a failed parse
        if (loose || multi_line(n)) mark(n);
    });
    ts_tree_cursor_delete(&c);
    return marks;
}

// Marks the lines of every ERROR and MISSING node (hidden ones included, such
// as a missing line end), walking only the subtrees that hold one.
void mark_error_lines(TSNode root, const SourceText& src, std::vector<char>& marks) {
    if (!ts_node_has_error(root)) return;
    // A missing line end is a hidden node the tree does not show: two lines'
    // worth of nodes (block, tape header, tape mark) on one line.
    const Grammar& g = grammar();
    uint32_t last_line = 0;
    for (uint32_t i = 0, n = ts_node_child_count(root); i < n; ++i) {
        const TSNode ch = ts_node_child(root, i);
        const TSSymbol s = ts_node_symbol(ch);
        if (s != g.block && s != g.tape_header && s != g.tape_mark) continue;
        const uint32_t line = src.line_of(ts_node_start_byte(ch));
        if (line == last_line && line >= 1 && line <= marks.size()) marks[line - 1] = 1;
        last_line = line;
    }
    TSTreeCursor c = ts_tree_cursor_new(root);
    while (true) {
        const TSNode n = ts_tree_cursor_current_node(&c);
        const bool bad = is_error(n) || ts_node_is_missing(n);
        if (bad) {
            const uint32_t b = ts_node_start_byte(n);
            const uint32_t e = ts_node_end_byte(n);
            const uint32_t first = src.line_of(b);
            const uint32_t last = src.line_of(e > b ? e - 1 : b);
            for (uint32_t l = first; l <= last && l <= marks.size(); ++l)
                if (l >= 1) marks[l - 1] = 1;
        }
        // Into a subtree with an error (not into an ERROR node: its lines are marked).
        if (!bad && ts_node_has_error(n) && ts_tree_cursor_goto_first_child(&c)) continue;
        // Next sibling, or up until there is one.
        bool moved = false;
        while (!(moved = ts_tree_cursor_goto_next_sibling(&c)))
            if (!ts_tree_cursor_goto_parent(&c)) break;
        if (!moved) break;
    }
    ts_tree_cursor_delete(&c);
}

void parse_blocks(const SourceText& src, std::vector<Block>& blocks, std::vector<char>* error_lines) {
    const Grammar& g = grammar();
    std::unique_ptr<TSParser, decltype(&ts_parser_delete)> parser(ts_parser_new(), &ts_parser_delete);
    ts_parser_set_language(parser.get(), g.lang);
    using Tree = std::unique_ptr<TSTree, decltype(&ts_tree_delete)>;
    Tree tree(ts_parser_parse_string(parser.get(), nullptr, src.text().data(), src.size()), &ts_tree_delete);
    if (!tree) {
        blocks[0].errors.push_back({{0, 0}, "the parser could not process this file"});
        return;
    }
    Converter conv(src.text(), blocks, src);
    const TSNode root = ts_tree_root_node(tree.get());
    if (error_lines) {
        error_lines->assign(blocks.size(), 0);
        mark_error_lines(root, src, *error_lines);
    }
    std::vector<char> reparse;
    if (ts_node_has_error(root)) reparse = lines_to_reparse(root, src, blocks.size());
    const bool any = std::find(reparse.begin(), reparse.end(), 1) != reparse.end();
    conv.run(root, any ? &reparse : nullptr);
    if (!any) return;
    tree.reset();
    for (size_t i = 0; i < reparse.size(); ++i) {
        if (!reparse[i]) continue;
        const Block& b = blocks[i];
        if (b.range.empty()) continue;
        TSRange range;
        range.start_byte = b.range.begin;
        range.end_byte = b.range.end;
        range.start_point = {static_cast<uint32_t>(i), 0};
        range.end_point = {static_cast<uint32_t>(i), b.range.size()};
        ts_parser_set_included_ranges(parser.get(), &range, 1);
        Tree line_tree(ts_parser_parse_string(parser.get(), nullptr, src.text().data(), src.size()),
                       &ts_tree_delete);
        if (line_tree) conv.run(ts_tree_root_node(line_tree.get()));
    }
}

}  // namespace

namespace {
ProgramFile parse_file(std::string path, std::string text, std::vector<char>* error_lines);
}

ProgramFile parse_program_file(std::string path, std::string text) {
    std::vector<char> error_lines;
    ProgramFile file = parse_file(std::move(path), std::move(text), &error_lines);
    // Error lines again, each on its own.
    const SourceText& src = file.source;
    bool changed = false;
    for (Block& b : file.blocks) {
        const bool error_line = b.line >= 1 && b.line <= error_lines.size() && error_lines[b.line - 1];
        if ((b.errors.empty() && !error_line) || b.line == 0) continue;
        const std::string_view t = src.line_text(b.line);
        const uint32_t text_end = b.line_start + static_cast<uint32_t>(t.size());
        const uint32_t next = b.line < src.line_count() ? src.line_start(b.line + 1) : static_cast<uint32_t>(src.size());
        const LineRef l{t, std::string_view(src.text()).substr(text_end, next - text_end), b.line, b.line_start};
        Block alone;
        parse_line_tree_sitter(l, alone);
        b = std::move(alone);
        changed = true;
    }
    if (changed) file.programs = split_programs(file.blocks);
    return file;
}

ProgramFile parse_program_file_once(std::string path, std::string text) {
    return parse_file(std::move(path), std::move(text), nullptr);
}

namespace {

ProgramFile parse_file(std::string path, std::string text, std::vector<char>* error_lines) {
    ProgramFile file;
    file.path = std::move(path);
    const bool too_large = text.size() > std::numeric_limits<uint32_t>::max() - 1;
    if (too_large) text.clear();
    file.source = SourceText(std::move(text));
    const SourceText& src = file.source;

    const uint32_t count = block_count(src);
    file.blocks.resize(count);
    for (uint32_t i = 0; i < count; ++i) {
        Block& b = file.blocks[i];
        b.line = i + 1;
        b.line_start = src.line_start(i + 1);
        b.range = {b.line_start, b.line_start + static_cast<uint32_t>(src.line_text(i + 1).size())};
    }
    if (too_large) {
        file.blocks.resize(1);
        file.blocks[0].line = 1;
        file.blocks[0].errors.push_back({{0, 0}, "file is larger than 4 GiB and was not parsed"});
        file.programs = split_programs(file.blocks);
        return file;
    }

    if (count > 0) parse_blocks(src, file.blocks, error_lines);
    file.programs = split_programs(file.blocks);
    return file;
}

}  // namespace

std::vector<Program> split_programs(const std::vector<Block>& blocks) {
    std::vector<Program> programs;
    if (blocks.empty()) return programs;
    // Lines before the first program name that hold nothing executable (tape
    // header, comments, blank lines) belong to the first program.
    size_t first = 0;
    while (first < blocks.size() && !blocks[first].program_name &&
           (blocks[first].is_empty() || blocks[first].kind != LineKind::Block))
        ++first;
    auto start = [&](size_t at, const Block& named) {
        Program p;
        if (named.program_name) {
            p.name = named.program_name->name;
            p.name_range = named.program_name->range;
        }
        p.first_block = static_cast<uint32_t>(at);
        programs.push_back(std::move(p));
    };
    if (first < blocks.size() && blocks[first].program_name)
        start(0, blocks[first]);
    else
        start(0, Block{});
    for (size_t i = first + 1; i < blocks.size(); ++i) {
        if (!blocks[i].program_name) continue;
        programs.back().end_block = static_cast<uint32_t>(i);
        start(i, blocks[i]);
    }
    programs.back().end_block = static_cast<uint32_t>(blocks.size());
    return programs;
}

double decimal_literal_value(std::string_view digits) {
    double v = 0;
    const char* first = digits.data();
    const char* last = first + digits.size();
    const auto res = std::from_chars(first, last, v, std::chars_format::fixed);
    if (res.ec == std::errc::result_out_of_range) {
        // Too many digits for a double: either huge or (all zeros after a
        // leading dot) tiny.
        const bool fraction_only = !digits.empty() && digits.front() == '.';
        return fraction_only ? 0.0 : std::numeric_limits<double>::infinity();
    }
    return v;
}

}  // namespace osplint
