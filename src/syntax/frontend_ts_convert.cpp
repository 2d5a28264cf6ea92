// The conversion of a tree-sitter tree into blocks (see
// frontend_ts_convert.h): lines, block items, statements and expressions.
#include "syntax/frontend_ts_convert.h"

#include <algorithm>
#include <cmath>

#include "syntax/frontend.h"

namespace osplint::ts_detail {

namespace {

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

}  // namespace

void Converter::run(TSNode root, const std::vector<char>* skip) {
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

bool Converter::is_line_node(TSNode n) const {
    const TSSymbol s = ts_node_symbol(n);
    return s == g_.block || s == g_.tape_header || s == g_.tape_mark || s == g_.comment || is_error(n);
}

// --- Lines ------------------------------------------------------------------------

void Converter::line_node(TSTreeCursor* c, TSNode n, Block& b) {
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

void Converter::comment(TSNode n, Block& b) {
    const ByteRange r = range_of(n);
    b.comments.push_back({r});
    if (r.size() < 2 || text_[r.end - 1] != ')')
        error(b, r, "unterminated comment: expected ')' before the end of the line");
}

void Converter::block(TSTreeCursor* c, Block& b) {
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

void Converter::label(TSNode n, std::optional<Label>& out, Block& b, const char* what) {
    if (ts_node_is_missing(n)) {
        syntax_error(b, range_of(n), std::string("expected ") + what);
        return;
    }
    out = Label{upper(text(n)), range_of(n)};
}

// --- Block items ------------------------------------------------------------------

void Converter::item(TSTreeCursor* c, TSNode n, Block& b, Context ctx) {
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
void Converter::word(TSTreeCursor* c, TSNode n, Block& b) {
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

// The literal `digits` as the Number node `e` (its range set). One too large
// for a double is an error on the block and an Error node, without a value:
// no infinity reaches the analysis.
std::optional<double> Converter::number_value(Block& b, ExprNode& e, std::string_view digits) {
    const std::optional<double> v = decimal_literal_value(digits);
    if (!v) {
        e.kind = ExprKind::Error;
        e.number = 0;
        error(b, e.range, number_too_large_message(digits));
        return std::nullopt;
    }
    e.kind = ExprKind::Number;
    e.number = *v;
    return v;
}

// The same for a hex constant whose value `e` holds (hex_value).
void Converter::unusable_if_infinite(Block& b, ExprNode& e) {
    if (std::isfinite(e.number)) return;
    e.kind = ExprKind::Error;
    e.number = 0;
    error(b, e.range, number_too_large_message(text(e.range)));
}

// The glued number of `X-.75`: value = Unary(-, Number(.75)), number = -0.75.
void Converter::plain_number(TSNode n, Block& b, Word& w) {
    const ByteRange r = range_of(n);
    std::string_view t = text(n);
    char sign = 0;
    if (!t.empty() && (t[0] == '-' || t[0] == '+')) {
        sign = t[0];
        t.remove_prefix(1);
    }
    ExprNode num;
    num.range = {sign ? r.begin + 1 : r.begin, r.end};
    const std::optional<double> v = number_value(b, num, t);
    const ExprId num_id = push(b, std::move(num));
    if (sign) {
        ExprNode un;
        un.kind = ExprKind::Unary;
        un.op = std::string(1, sign);
        un.children.push_back(num_id);
        un.range = r;
        w.value = push(b, std::move(un));
        if (v) w.number = sign == '-' ? -*v : *v;
    } else {
        w.value = num_id;
        w.number = v;
    }
}

// A numeric literal, possibly signed (`5`, `-.75`), as a number.
std::optional<double> Converter::literal_value(const Block& b, ExprId id) const {
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
void Converter::label_word(TSNode n, Block& b) {
    Word w;
    w.address = "N";
    w.range = range_of(n);
    w.address_range = {w.range.begin, w.range.begin + 1};
    w.value_range = {w.range.begin + 1, w.range.end};
    w.value_text = upper(text(w.value_range));
    const std::string_view v = text(w.value_range);
    if (!v.empty() && std::all_of(v.begin(), v.end(), [](char ch) { return ch >= '0' && ch <= '9'; })) {
        ExprNode num;
        num.range = w.value_range;
        w.number = number_value(b, num, v);
        w.value = push(b, std::move(num));
        w.value_text = std::string(v);
    }
    b.words.push_back(std::move(w));
}

// `VC1=2`, `VTOFX[16]=...` become Assignments; `PX=0`, `FA=200` (and every
// plain name in a call's arguments) become Words with equals=true.
void Converter::assignment(TSTreeCursor* c, TSNode n, Block& b, Context ctx) {
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
void Converter::other_child(TSTreeCursor* c, TSNode n, Block& b) {
    if (is_error(n)) error_node(c, n, b);
    else if (ts_node_is_missing(n)) missing(n, b);
    else if (ts_node_symbol(n) == g_.comment) comment(n, b);
    else if (ts_node_symbol(n) == g_.unexpected) unexpected(n, b);
    else if (ts_node_has_error(n)) sweep(c, b);
}

// --- Statements -------------------------------------------------------------------

Statement& Converter::new_statement(TSNode n, Block& b, StmtKind kind) {
    Statement s;
    s.kind = kind;
    s.range = range_of(n);
    TSNode kw = ts_node_child(n, 0);
    s.keyword_range = ts_node_is_null(kw) ? s.range : range_of(kw);
    b.statements.push_back(std::move(s));
    return b.statements.back();
}

void Converter::keyword_statement(TSNode n, Block& b, StmtKind kind) { new_statement(n, b, kind); }

// GOTO / IF / WHILE / DO / END.
void Converter::control_statement(TSTreeCursor* c, TSNode n, Block& b, TSSymbol s) {
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
                const std::optional<double> v = decimal_literal_value(text(ch));
                loop = v && *v >= 0 && *v <= 1e9 && *v == std::floor(*v) ? static_cast<int>(*v) : -1;
                if (!v) error(b, range_of(ch), number_too_large_message(text(ch)));
                else if (loop < 0) error(b, range_of(ch), "loop number must be a whole number");
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
void Converter::call_statement(TSTreeCursor* c, TSNode n, Block& b, StmtKind kind) {
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
void Converter::mnemonic_statement(TSTreeCursor* c, TSNode n, Block& b, StmtKind kind) {
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

// --- Expressions ------------------------------------------------------------------

ExprId Converter::error_expr(Block& b, ByteRange r) {
    ExprNode e;
    e.kind = ExprKind::Error;
    e.range = r;
    return push(b, std::move(e));
}

ExprId Converter::missing_expr(TSNode n, Block& b) {
    missing(n, b);
    return error_expr(b, range_of(n));
}

// Converts the expression under the cursor.
ExprId Converter::expr(TSTreeCursor* c, Block& b, int depth) {
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
    if (!leaf_expr(n, s, b, e) && !compound_expr(c, s, b, depth, e)) {
        e.kind = ExprKind::Error;
        if (ts_node_has_error(n)) sweep(c, b);
    }
    return push(b, std::move(e));
}

// An expression without sub-expressions: a number, a hex constant, a string,
// EMPTY, a variable. False when `s` is none of them.
bool Converter::leaf_expr(TSNode n, TSSymbol s, Block& b, ExprNode& e) {
    if (s == g_.number) {
        number_value(b, e, text(n));
    } else if (s == g_.hex_constant) {
        const std::string_view t = text(n);  // #81H
        e.kind = ExprKind::HexConst;
        e.text = std::string(t);
        e.number = hex_value(t.size() >= 2 ? t.substr(1, t.size() - 2) : std::string_view());
        unusable_if_infinite(b, e);
    } else if (s == g_.hex_subscript) {
        e.kind = ExprKind::HexConst;
        e.text = std::string(text(n));
        e.number = hex_value(e.text);
        unusable_if_infinite(b, e);
    } else if (s == g_.string) {
        std::string_view t = text(n);
        e.kind = ExprKind::String;
        t.remove_prefix(1);
        if (!t.empty() && t.back() == '\'') {
            t.remove_suffix(1);
        } else {
            error(b, e.range, "unterminated string: expected \"'\" before the end of the line");
        }
        e.text = std::string(t);
    } else if (s == g_.empty) {
        e.kind = ExprKind::Empty;
    } else if (s == g_.variable || s == g_.identifier) {
        e.kind = ExprKind::Variable;
        e.text = upper(text(n));
    } else {
        return false;
    }
    return true;
}

// An expression with sub-expressions (converted at depth + 1): an indexed
// variable, a function call, a bracket, a unary or binary operation. False
// when `s` is none of them.
bool Converter::compound_expr(TSTreeCursor* c, TSSymbol s, Block& b, int depth, ExprNode& e) {
    if (s == g_.indexed_variable) {
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
        return false;
    }
    return true;
}

}  // namespace osplint::ts_detail
