#include "lsp/structure.h"

#include <algorithm>

#include "engine/flow.h"
#include "engine/workspace.h"
#include "lsp/navigation.h"
#include "support/text.h"
#include "syntax/frontend_fast.h"

namespace fs = std::filesystem;

namespace osplint::lsp {

// --- folding ----------------------------------------------------------------

namespace {

json fold(uint32_t first, uint32_t last, const char* kind) {
    json r = {{"startLine", first - 1}, {"endLine", last - 1}};
    if (kind) r["kind"] = kind;
    return r;
}

bool blank_line(std::string_view text) { return text.find_first_not_of(" \t\f\v") == std::string_view::npos; }

}  // namespace

json folding_ranges(const DocumentModel& doc) {
    json out = json::array();
    const SourceText& src = doc.source();
    const auto& programs = doc.outline.programs;
    FastLineParser parser;
    Block b;
    for (size_t i = 0; i < programs.size(); ++i) {
        auto [first, last] = program_lines(doc, i);
        last = std::min(last, src.line_count());
        while (last > first && blank_line(src.line_text(last))) --last;
        if (last > first) out.push_back(fold(first, last, nullptr));
        // WHILE / DO ... END: the loops as the engine pairs them.
        const ProgramFlow flow(programs[i], doc.outline.program_end(i));
        for (const LoopPair& loop : flow.loops()) {
            const uint32_t head = src.line_of(loop.head);
            const uint32_t end = src.line_of(loop.end);
            if (end > head) out.push_back(fold(head, end, nullptr));
        }
        // MODIN ... MODOUT (the MODOUT closes the MODIN before it).
        std::vector<uint32_t> lines = lines_holding(src, first, last, "MODIN");
        std::vector<uint32_t> outs = lines_holding(src, first, last, "MODOUT");
        std::vector<std::pair<uint32_t, bool>> marks;  // line, is MODIN
        for (uint32_t l : lines) {
            parse_source_line(src, l, parser, b);
            if (b.statement(StmtKind::Modin)) marks.push_back({l, true});
        }
        for (uint32_t l : outs) {
            parse_source_line(src, l, parser, b);
            if (b.statement(StmtKind::Modout)) marks.push_back({l, false});
        }
        std::sort(marks.begin(), marks.end());
        std::optional<uint32_t> open;
        for (const auto& [l, is_modin] : marks) {
            if (is_modin) {
                open = l;
            } else if (open) {
                if (l > *open) out.push_back(fold(*open, l, nullptr));
                open.reset();
            }
        }
    }
    // Runs of lines holding nothing but comments.
    uint32_t run_start = 0, run_end = 0;
    auto close_run = [&] {
        if (run_start && run_end > run_start) out.push_back(fold(run_start, run_end, "comment"));
        run_start = run_end = 0;
    };
    for (uint32_t line = 1; line <= src.line_count(); ++line) {
        const std::string_view text = src.line_text(line);
        const size_t k = text.find_first_not_of(" \t");
        bool comment_only = false;
        if (k != std::string_view::npos && text[k] == '(') {
            parse_source_line(src, line, parser, b);
            comment_only = b.is_empty() && !b.comments.empty();
        }
        if (comment_only) {
            if (!run_start) run_start = line;
            run_end = line;
        } else {
            close_run();
        }
    }
    close_run();
    std::stable_sort(out.begin(), out.end(), [](const json& a, const json& c) {
        return a["startLine"].get<uint32_t>() < c["startLine"].get<uint32_t>();
    });
    return out;
}

// --- semantic tokens -----------------------------------------------------------

namespace {

enum TokenType : uint32_t { Function, Parameter, Label, Variable, CommentToken, Keyword, Macro };
constexpr uint32_t kDeclaration = 1;

struct Token {
    ByteRange range;
    uint32_t type = 0;
    uint32_t modifiers = 0;
};

void block_tokens(const Block& b, std::string_view text, std::vector<Token>& out) {
    auto add = [&](ByteRange r, uint32_t type, uint32_t mods = 0) {
        if (!r.empty()) out.push_back({r, type, mods});
    };
    if (b.program_name) add(b.program_name->range, Function, kDeclaration);
    if (b.sequence) add(b.sequence->range, Label, kDeclaration);
    uint32_t args_from = UINT32_MAX;
    for (const auto& st : b.statements) {
        add(st.keyword_range, Keyword);
        if ((st.kind == StmtKind::Call || st.kind == StmtKind::Modin) && !st.name.empty()) {
            add(st.name_range, Function);
            args_from = std::min(args_from, st.name_range.end);
        }
        if ((st.kind == StmtKind::Goto || st.kind == StmtKind::If) && !st.name.empty()) add(st.name_range, Label);
    }
    for (const auto& w : b.words) {
        if (w.address == "G" || w.address == "M") add(w.range, Macro);
        else if (w.equals && w.range.begin >= args_from) add(w.address_range, Parameter);
    }
    for (const auto& c : b.comments) add(c.range, CommentToken);
    // Variables: the name as written (a subscript's own variables are tokens of their own).
    const uint32_t base = b.range.begin;
    for (const auto& e : b.exprs) {
        if (e.kind != ExprKind::Variable || e.text.empty() || e.range.begin < base) continue;
        const ByteRange r{e.range.begin, e.range.begin + static_cast<uint32_t>(e.text.size())};
        if (r.end - base > text.size() || !iequals(text.substr(r.begin - base, r.size()), e.text)) continue;
        add(r, Variable);
    }
}

}  // namespace

json semantic_tokens_legend() {
    json types = json::array(), mods = json::array();
    for (auto t : kTokenTypes) types.push_back(std::string(t));
    for (auto m : kTokenModifiers) mods.push_back(std::string(m));
    return json{{"tokenTypes", std::move(types)}, {"tokenModifiers", std::move(mods)}};
}

json semantic_tokens(const DocumentModel& doc, Encoding enc, uint32_t first, uint32_t last) {
    const SourceText& src = doc.source();
    std::vector<uint32_t> data;
    if (last == 0 || last > src.line_count()) last = src.line_count();
    FastLineParser parser;
    Block b;
    std::vector<Token> tokens;
    uint32_t prev_line = 0, prev_col = 0;
    auto units = [&](std::string_view bytes) {
        return enc == Encoding::Utf8 ? static_cast<uint32_t>(bytes.size()) : count_columns(bytes).utf16;
    };
    for (uint32_t line = std::max<uint32_t>(first, 1); line <= last; ++line) {
        const std::string_view text = src.line_text(line);
        if (blank_line(text)) continue;
        parse_source_line(src, line, parser, b);
        tokens.clear();
        block_tokens(b, text, tokens);
        std::sort(tokens.begin(), tokens.end(),
                  [](const Token& x, const Token& y) { return x.range.begin < y.range.begin; });
        const uint32_t start = src.line_start(line);
        uint32_t covered = start;  // tokens never overlap
        for (const Token& t : tokens) {
            if (t.range.begin < covered || t.range.end > start + text.size()) continue;
            const uint32_t col = units(text.substr(0, t.range.begin - start));
            const uint32_t len = units(text.substr(t.range.begin - start, t.range.size()));
            const uint32_t l = line - 1;
            data.push_back(l - prev_line);
            data.push_back(l == prev_line ? col - prev_col : col);
            data.push_back(len);
            data.push_back(t.type);
            data.push_back(t.modifiers);
            prev_line = l;
            prev_col = col;
            covered = t.range.end;
        }
    }
    return json{{"data", std::move(data)}};
}

// --- workspace symbols ------------------------------------------------------------

std::vector<SymbolSource> folder_documents(const fs::path& dir, const std::vector<std::string>& skip, size_t max_files) {
    std::vector<SymbolSource> out;
    std::vector<fs::path> files;
    std::error_code ec;
    const auto opts = fs::directory_options::skip_permission_denied;
    for (fs::recursive_directory_iterator it(dir, opts, ec), end; !ec && it != end; it.increment(ec)) {
        if (files.size() >= max_files) break;
        std::error_code ec2;
        const fs::path& p = it->path();
        if (it->is_directory(ec2) && !p.filename().empty() && p.filename().string()[0] == '.') {
            it.disable_recursion_pending();  // .git and the like
            continue;
        }
        if (!it->is_regular_file(ec2) || !is_program_file(p.filename().string())) continue;
        if (std::find(skip.begin(), skip.end(), p.lexically_normal().string()) != skip.end()) continue;
        if (it->file_size(ec2) > SubprogramDirectories::max_file_size || ec2) continue;
        files.push_back(p);
    }
    std::sort(files.begin(), files.end());
    for (const auto& p : files)
        if (auto d = read_outlined_document(p)) {
            auto doc = std::make_shared<DiskDocument>(std::move(*d));
            out.push_back({doc->uri, std::shared_ptr<const DocumentModel>(doc, &doc->doc)});
        }
    return out;
}

json workspace_symbols(const std::vector<SymbolSource>& sources, std::string_view query, Encoding enc) {
    json out = json::array();
    const std::string q = upper(query);
    for (const auto& s : sources) {
        const std::string file = fs::path(s.doc->path).filename().string();
        for (const auto& p : s.doc->outline.programs) {
            if (p.name.empty() || p.name.find(q) == std::string::npos) continue;
            if (out.size() >= kMaxWorkspaceSymbols) return out;
            out.push_back({{"name", p.name},
                           {"kind", 12},  // Function
                           {"location", {{"uri", s.uri}, {"range", to_lsp_range(s.doc->source(), p.name_range, enc)}}},
                           {"containerName", file}});
        }
    }
    return out;
}

// --- document symbols ----------------------------------------------------

json document_symbols(const DocumentModel& doc, Encoding enc) {
    json out = json::array();
    const SourceText& src = doc.source();
    const auto& programs = doc.outline.programs;
    for (size_t pi = 0; pi < programs.size(); ++pi) {
        const ProgramOutline& p = programs[pi];
        const auto [first_line, last_line] = program_lines(doc, pi);
        if (first_line > last_line) continue;
        json children = json::array();
        for (const auto& d : sequence_definitions(doc, pi, kMaxSequenceSymbols)) {
            std::string detail(std::string_view(src.text()).substr(d.range.end, d.block.end - d.range.end));
            detail = std::string(trim_blanks(detail)).substr(0, 60);
            json sym = {{"name", d.name},
                        {"kind", 20},  // Key
                        {"range", to_lsp_range(src, d.block, enc)},
                        {"selectionRange", to_lsp_range(src, d.range, enc)}};
            if (!detail.empty()) sym["detail"] = detail;
            children.push_back(std::move(sym));
        }
        if (p.name.empty() && children.empty()) continue;
        const uint32_t begin = src.line_start(first_line);
        const ByteRange whole{begin, begin + static_cast<uint32_t>(src.line_text(last_line).size()) +
                                         (src.line_start(last_line) - begin)};
        const ByteRange first_range{begin, begin + static_cast<uint32_t>(src.line_text(first_line).size())};
        json sym = {{"name", p.name.empty() ? std::string("(unnamed program)") : p.name},
                    {"kind", 12},  // Function
                    {"range", to_lsp_range(src, whole, enc)},
                    {"selectionRange", to_lsp_range(src, p.name.empty() ? first_range : p.name_range, enc)},
                    {"children", std::move(children)}};
        out.push_back(std::move(sym));
    }
    return out;
}

}  // namespace osplint::lsp
