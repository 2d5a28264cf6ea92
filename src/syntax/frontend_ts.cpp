// The tree-sitter front end (frontend.h): parses a file with the OSP grammar
// (grammar/) and fills the program model (model.h). This file is the
// file-level parse: the tree of the whole file, converted block by block
// (frontend_ts_convert.h), and the lines whose error recovery spans several
// lines, parsed again one by one. frontend_ts_grammar.h lists the files of
// the front end.
#include "syntax/frontend.h"
#include "syntax/frontend_fast.h"

#include <tree_sitter/api.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <string_view>

#include "syntax/frontend_ts_convert.h"
#include "syntax/frontend_ts_grammar.h"
#include "syntax/frontend_ts_linecheck.h"

namespace osplint {

namespace {

using ts_detail::Converter;
using ts_detail::for_each_child;
using ts_detail::grammar;
using ts_detail::Grammar;
using ts_detail::is_error;

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

// `ts_text` is what tree-sitter reads: the source, or a copy of it with the
// lines it must not be given blanked (see parse_file).
void parse_blocks(const SourceText& src, std::string_view ts_text, std::vector<Block>& blocks,
                  std::vector<char>* error_lines) {
    const Grammar& g = grammar();
    std::unique_ptr<TSParser, decltype(&ts_parser_delete)> parser(ts_parser_new(), &ts_parser_delete);
    ts_parser_set_language(parser.get(), g.lang);
    using Tree = std::unique_ptr<TSTree, decltype(&ts_tree_delete)>;
    Tree tree(ts_parser_parse_string(parser.get(), nullptr, ts_text.data(), static_cast<uint32_t>(ts_text.size())),
              &ts_tree_delete);
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
        Tree line_tree(
            ts_parser_parse_string(parser.get(), nullptr, ts_text.data(), static_cast<uint32_t>(ts_text.size())),
            &ts_tree_delete);
        if (line_tree) conv.run(ts_tree_root_node(line_tree.get()));
    }
}

// With `bound`, the lines tree-sitter must not be given whole (bound_line in
// frontend_ts_linecheck.h) are blanked in what it reads and marked as error
// lines: parse_program_file parses them again on their own, with the bound.
ProgramFile parse_file(std::string path, std::string text, std::vector<char>* error_lines, bool bound) {
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

    std::string masked;
    std::vector<uint32_t> masked_lines;
    if (bound) {
        for (uint32_t i = 1; i <= count; ++i) {
            const std::string_view t = src.line_text(i);
            const ts_detail::LineBound b = ts_detail::bound_line(t);
            if (b.too_deep == std::string_view::npos && b.cut == std::string_view::npos) continue;
            if (masked.empty()) masked = src.text();
            const uint32_t at = src.line_start(i);
            std::fill(masked.begin() + at, masked.begin() + at + static_cast<std::ptrdiff_t>(t.size()), ' ');
            masked_lines.push_back(i);
        }
    }
    if (count > 0) parse_blocks(src, masked.empty() ? std::string_view(src.text()) : masked, file.blocks, error_lines);
    if (error_lines && !masked_lines.empty()) {
        error_lines->resize(count, 0);
        for (uint32_t l : masked_lines) (*error_lines)[l - 1] = 1;
    }
    file.programs = split_programs(file.blocks);
    return file;
}

}  // namespace

ProgramFile parse_program_file(std::string path, std::string text) {
    std::vector<char> error_lines;
    ProgramFile file = parse_file(std::move(path), std::move(text), &error_lines, true);
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
    return parse_file(std::move(path), std::move(text), nullptr, false);
}

}  // namespace osplint
