// Converter: a tree of the OSP grammar into the program model (model.h), and
// the syntax errors of the tree into SyntaxErrors on their blocks. The node
// types and fields it reads are documented in grammar/NODES.md.
//
// The tree is walked with one TSTreeCursor. Structure (blocks, statements,
// words) is shallow; expressions can nest arbitrarily deep, so their
// conversion stops at kMaxExprDepth and everything below is only swept
// iteratively for comments and syntax errors.
//
// The conversion is in frontend_ts_convert.cpp, the syntax errors (where they
// start, how adjacent ones merge, what their messages say) in
// frontend_ts_errors.cpp.
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "syntax/frontend_ts_grammar.h"
#include "syntax/model.h"
#include "syntax/source.h"

namespace osplint::ts_detail {

class Converter {
public:
    Converter(const std::string& text, std::vector<Block>& blocks, const SourceText& source)
        : g_(grammar()), text_(text), blocks_(blocks), source_(source) {}

    // Converts the nodes of `root` into the blocks of their lines. Nodes that
    // start on a line marked in `skip` are left out.
    void run(TSNode root, const std::vector<char>* skip = nullptr);

    // Nodes that stand for (part of) a line on their own.
    bool is_line_node(TSNode n) const;

private:
    const Grammar& g_;
    const std::string& text_;
    std::vector<Block>& blocks_;
    const SourceText& source_;
    const Block* checked_block_ = nullptr;    // block whose line first_line_error has placed
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

    // --- Lines (frontend_ts_convert.cpp) -----------------------------------------

    void line_node(TSTreeCursor* c, TSNode n, Block& b);
    void comment(TSNode n, Block& b);
    void block(TSTreeCursor* c, Block& b);
    void label(TSNode n, std::optional<Label>& out, Block& b, const char* what);

    // --- Block items ------------------------------------------------------------------

    enum class Context { Block, CallArgs };

    void item(TSTreeCursor* c, TSNode n, Block& b, Context ctx);
    void word(TSTreeCursor* c, TSNode n, Block& b);
    void plain_number(TSNode n, Block& b, Word& w);
    std::optional<double> number_value(Block& b, ExprNode& e, std::string_view digits);
    void unusable_if_infinite(Block& b, ExprNode& e);
    std::optional<double> literal_value(const Block& b, ExprId id) const;
    void label_word(TSNode n, Block& b);
    void assignment(TSTreeCursor* c, TSNode n, Block& b, Context ctx);
    void other_child(TSTreeCursor* c, TSNode n, Block& b);

    // --- Statements -------------------------------------------------------------------

    Statement& new_statement(TSNode n, Block& b, StmtKind kind);
    void keyword_statement(TSNode n, Block& b, StmtKind kind);
    void control_statement(TSTreeCursor* c, TSNode n, Block& b, TSSymbol s);
    void call_statement(TSTreeCursor* c, TSNode n, Block& b, StmtKind kind);
    void mnemonic_statement(TSTreeCursor* c, TSNode n, Block& b, StmtKind kind);

    // --- Expressions ------------------------------------------------------------------

    ExprId push(Block& b, ExprNode e) {
        b.exprs.push_back(std::move(e));
        return static_cast<ExprId>(b.exprs.size() - 1);
    }
    ExprId error_expr(Block& b, ByteRange r);
    ExprId missing_expr(TSNode n, Block& b);
    ExprId expr(TSTreeCursor* c, Block& b, int depth);
    bool leaf_expr(TSNode n, TSSymbol s, Block& b, ExprNode& e);
    bool compound_expr(TSTreeCursor* c, TSSymbol s, Block& b, int depth, ExprNode& e);

    // --- Syntax errors (frontend_ts_errors.cpp) ------------------------------------

    void syntax_error(Block& b, ByteRange r, std::string message);
    void missing(TSNode n, Block& b);
    void error_node(TSTreeCursor* c, TSNode n, Block& b);
    void unexpected(TSNode n, Block& b);
    bool extend_error(Block& b, ByteRange r);
    void mark_mergeable(Block& b);
    void sweep(TSTreeCursor* c, Block& b, bool inside_error = false);
    void salvage_label(TSNode n, Block& b, TSSymbol s);
    std::pair<uint32_t, std::string> describe_error(TSTreeCursor* c, TSNode n, const Block& b);

    // --- The text around an error, for its message -------------------------------------

    static bool needs_continuation(const std::string& lexeme);
    uint32_t first_content(const Block& b) const;
    uint32_t lexeme_end(uint32_t at, uint32_t end) const;
    std::string lexeme_at(uint32_t at, uint32_t end) const;
    std::string previous_lexeme(const Block& b, uint32_t at) const;
    int open_brackets(const Block& b, uint32_t at) const;
    std::string explain(const Block& b, uint32_t offending) const;
    bool starts_with_if(const Block& b) const;
};

}  // namespace osplint::ts_detail
