// The tree-sitter front end (frontend.h) in several files; this header is
// what they share: the grammar's symbol and field ids, looked up once, and
// small helpers on nodes and text.
//
//   frontend_ts.cpp            the file-level parse: the tree, and the lines
//                              parsed again on their own
//   frontend_ts_grammar.cpp    the grammar handle (this header)
//   frontend_ts_convert.h      the conversion of a tree into Blocks (Converter):
//     frontend_ts_convert.cpp    lines, block items, statements, expressions
//     frontend_ts_errors.cpp     syntax errors: where they start, what they say
//   frontend_ts_linecheck.cpp  where a line stops being valid (LineChecker)
//   frontend_shared.cpp        split_programs and decimal_literal_value, shared
//                              with the fast front end
#pragma once

#include <tree_sitter/api.h>

#include <string>
#include <string_view>

#include "support/text.h"
#include "syntax/model.h"

namespace osplint::ts_detail {

// Expressions can nest arbitrarily deep: their conversion (and LineChecker)
// stops at this depth, and everything below is only swept iteratively for
// comments and syntax errors.
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

    Grammar();
};

const Grammar& grammar();

// ERROR nodes carry the reserved symbol (TSSymbol)-1.
inline bool is_error(TSNode n) { return ts_node_symbol(n) == static_cast<TSSymbol>(-1); }

inline ByteRange range_of(TSNode n) { return {ts_node_start_byte(n), ts_node_end_byte(n)}; }

using osplint::upper;  // support/text.h

inline bool is_alnum(unsigned char c) {
    return (c >= '0' && c <= '9') || (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

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

}  // namespace osplint::ts_detail
