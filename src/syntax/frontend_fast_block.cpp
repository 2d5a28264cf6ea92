// What the fast front end offers around its parser (frontend_fast.h): the
// byte ranges of a block shifted, one line parsed by the tree-sitter front
// end in place, a readable dump of a block, and a whole file parsed line by
// line.
#include <algorithm>
#include <charconv>
#include <limits>
#include <string>

#include "syntax/frontend.h"
#include "syntax/frontend_fast.h"
#include "syntax/frontend_ts_linecheck.h"

namespace osplint {

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
    const uint32_t start = line.start;
    const uint32_t size = static_cast<uint32_t>(line.text.size());
    // Bounds on tree-sitter's work (frontend_ts_linecheck.h): an expression
    // nested too deeply is not parsed at all, and a line is read only a
    // little past its first error.
    const ts_detail::LineBound bound = ts_detail::bound_line(line.text);
    if (bound.too_deep != std::string_view::npos) {
        Block b;
        b.line = line.line;
        b.line_start = start;
        b.range = {start, start + size};
        const uint32_t at = start + static_cast<uint32_t>(bound.too_deep);
        b.errors.push_back({{at, std::min(at + 1, start + size)}, "expression nested too deeply"});
        out = std::move(b);
        return;
    }
    // The line is parsed after one blank, so that every offset of its own text
    // is above zero and an unset range ({0, 0}) is never taken for a set one.
    // A blank is padding to the grammar and changes no node; a node error
    // recovery inserts before it (a missing token at offset 0) belongs at the
    // line start, where it is in the file.
    std::string text;
    text.reserve(line.text.size() + line.terminator.size() + 1);
    text.push_back(' ');
    text.append(line.text);
    const bool cut = bound.cut != std::string_view::npos;
    if (cut) std::fill(text.begin() + 1 + static_cast<std::ptrdiff_t>(bound.cut), text.end(), ' ');
    text.append(line.terminator);
    ProgramFile f = parse_program_file_once(std::string(), std::move(text));
    Block b = f.blocks.empty() ? Block{} : std::move(f.blocks[0]);
    for_each_range(b, [&](ByteRange& r) {
        r.begin = (r.begin ? r.begin - 1 : 0) + start;
        r.end = (r.end ? r.end - 1 : 0) + start;
    });
    b.line = line.line;
    b.line_start = line.start;
    b.range = {start, start + size};
    if (cut) {
        const uint32_t at = start + static_cast<uint32_t>(bound.cut);
        b.errors.push_back({{at, start + size}, "the line is not read further: " + std::to_string(start + size - at) +
                                                    " more characters after a syntax error"});
    }
    out = std::move(b);
}

namespace {

std::string dump_range(ByteRange r) {
    std::string s = "[";
    s += std::to_string(r.begin);
    s += ',';
    s += std::to_string(r.end);
    s += ')';
    return s;
}

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
