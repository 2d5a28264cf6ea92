// The grammar handle of the tree-sitter front end (frontend_ts_grammar.h):
// the ids of the node kinds and fields it reads (grammar/NODES.md).
#include "syntax/frontend_ts_grammar.h"

#include <cstring>

extern "C" const TSLanguage* tree_sitter_osp(void);

namespace osplint::ts_detail {

Grammar::Grammar() {
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

const Grammar& grammar() {
    static const Grammar g;
    return g;
}

}  // namespace osplint::ts_detail
