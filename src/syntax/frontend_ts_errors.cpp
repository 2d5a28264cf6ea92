// The syntax errors of the tree-sitter front end (see frontend_ts_convert.h):
// every ERROR node, missing token and unexpected character becomes a
// SyntaxError on its block, starting where the line stops being valid,
// adjacent ones merged, with a message that says what was found and, where
// the context tells, what was expected instead.
#include <cctype>

#include "syntax/frontend_ts_convert.h"
#include "syntax/frontend_ts_linecheck.h"

namespace osplint::ts_detail {

namespace {

// A lexeme as messages show it: in single quotes.
std::string quoted(std::string_view s) {
    std::string q;
    q.reserve(s.size() + 2);
    q += '\'';
    q += s;
    q += '\'';
    return q;
}

}  // namespace

// A syntax error found in the tree; extends the previous one when adjacent.
//
// An error starts at the first character that cannot continue the block,
// never on a blank: a range that starts on blanks (a missing token) moves
// to the next character, or to the end of the line.
void Converter::syntax_error(Block& b, ByteRange r, std::string message) {
    uint32_t begin = std::min(r.begin, b.range.end);
    while (begin < b.range.end && is_blank(text_[begin])) ++begin;
    r = {begin, std::max(begin, std::min(r.end, b.range.end))};
    if (checked_block_ != &b) {
        // The line's first syntax error starts where the line stops being valid.
        checked_block_ = &b;
        const size_t at = first_line_error(text(b.range));
        if (at != std::string_view::npos) {
            const uint32_t where = b.range.begin + static_cast<uint32_t>(at);
            if (where != r.begin) message = explain(b, where);
            r = {where, std::max(r.end, lexeme_end(where, b.range.end))};
        }
    }
    if (extend_error(b, r)) return;
    b.errors.push_back({r, std::move(message)});
    mark_mergeable(b);
}

// A token the parser inserted to recover (zero width).
void Converter::missing(TSNode n, Block& b) {
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
void Converter::error_node(TSTreeCursor* c, TSNode n, Block& b) {
    const ByteRange r = range_of(n);
    if (!extend_error(b, r)) {
        auto [at, message] = describe_error(c, n, b);
        syntax_error(b, {at, r.end}, std::move(message));
    }
    sweep(c, b, /*inside_error=*/true);
}

// Text the scanner could not lex, accepted after a block's first item.
void Converter::unexpected(TSNode n, Block& b) {
    const ByteRange r = range_of(n);
    if (extend_error(b, r)) return;
    syntax_error(b, r, explain(b, r.begin));
}

// Consecutive ERROR nodes and unexpected characters (separated by blanks at
// most) form one SyntaxError: the last one is extended when `r` follows it.
bool Converter::extend_error(Block& b, ByteRange r) {
    if (mergeable_block_ != &b || b.errors.size() != mergeable_count_) return false;
    SyntaxError& last = b.errors.back();
    if (r.begin < last.range.begin) return false;
    for (uint32_t i = last.range.end; i < r.begin; ++i)
        if (!is_blank(text_[i])) return false;
    last.range.end = std::max(last.range.end, r.end);
    return true;
}

void Converter::mark_mergeable(Block& b) {
    mergeable_block_ = &b;
    mergeable_count_ = b.errors.size();
}

// Iterative walk of the subtree under the cursor: records comments, ERROR
// nodes (outermost only), missing tokens, and salvages labels inside errors.
void Converter::sweep(TSTreeCursor* c, Block& b, bool inside_error) {
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

void Converter::salvage_label(TSNode n, Block& b, TSSymbol s) {
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
std::pair<uint32_t, std::string> Converter::describe_error(TSTreeCursor* c, TSNode n, const Block& b) {
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

// --- The text around an error, for its message ------------------------------------

// Lexemes after which a block cannot end.
bool Converter::needs_continuation(const std::string& lexeme) {
    static const char* const kWords[] = {"GOTO", "CALL", "MODIN", "IF", "WHILE", "DO", "=", "[", ",",
                                         "+", "-", "*", "/", "EQ", "NE", "GT", "GE", "LT", "LE",
                                         "AND", "OR", "EOR", "NOT"};
    for (const char* w : kWords)
        if (lexeme == w) return true;
    return lexeme.size() == 1 && lexeme[0] >= 'A' && lexeme[0] <= 'Z';  // an address letter
}

uint32_t Converter::first_content(const Block& b) const {
    uint32_t i = b.range.begin;
    while (i < b.range.end && is_blank(text_[i])) ++i;
    return i;
}

// End of the lexeme at `at`: a run of letters/digits/dots, else one character.
uint32_t Converter::lexeme_end(uint32_t at, uint32_t end) const {
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
std::string Converter::lexeme_at(uint32_t at, uint32_t end) const {
    if (at >= end) return {};
    const auto ch = static_cast<unsigned char>(text_[at]);
    if (is_alnum(ch) || ch == '.') {
        uint32_t e = at;
        while (e < end && e - at < 24 && (is_alnum(static_cast<unsigned char>(text_[e])) || text_[e] == '.')) ++e;
        return quoted(std::string_view(text_).substr(at, e - at));
    }
    if (ch >= 0xC0) {  // a well-formed UTF-8 character is shown as such
        const std::string_view seq = std::string_view(text_).substr(at, lexeme_end(at, end) - at);
        if (seq.size() > 1 && is_valid_utf8(seq)) return quoted(seq);
    }
    if (ch >= 0x80 || ch < 0x20 || ch == 0x7F) {
        static const char* hex = "0123456789ABCDEF";
        std::string s = "byte 0x";
        s += hex[ch >> 4];
        s += hex[ch & 15];
        return s;
    }
    if (ch == '\'') return "\"'\"";
    return quoted(std::string(1, static_cast<char>(ch)));
}

// The lexeme that ends just before `at` on the line (skipping blanks and comments).
std::string Converter::previous_lexeme(const Block& b, uint32_t at) const {
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
int Converter::open_brackets(const Block& b, uint32_t at) const {
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

std::string Converter::explain(const Block& b, uint32_t offending) const {
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

bool Converter::starts_with_if(const Block& b) const {
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

}  // namespace osplint::ts_detail
