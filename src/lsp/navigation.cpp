#include "lsp/navigation.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "engine/workspace.h"
#include "support/text.h"

namespace fs = std::filesystem;

namespace osplint::lsp {

namespace {

// The token at the offset, or ending at it (the cursor just after a name).
bool hits(ByteRange r, uint32_t off) { return r.contains(off) || (!r.empty() && r.end == off); }

json location(const std::string& uri, const SourceText& src, ByteRange r, Encoding enc) {
    return json{{"uri", uri}, {"range", to_lsp_range(src, r, enc)}};
}

bool is_jump(const Statement& st) { return (st.kind == StmtKind::Goto || st.kind == StmtKind::If) && !st.name.empty(); }
bool is_call(const Statement& st) { return (st.kind == StmtKind::Call || st.kind == StmtKind::Modin) && !st.name.empty(); }

}  // namespace

// --- lines and programs -------------------------------------------------------

void parse_source_line(const SourceText& src, uint32_t line, FastLineParser& parser, Block& out) {
    const uint32_t start = src.line_start(line);
    const std::string_view text = src.line_text(line);
    const uint32_t text_end = start + static_cast<uint32_t>(text.size());
    const uint32_t next = line < src.line_count() ? src.line_start(line + 1) : src.size();
    parser.parse(LineRef{text, std::string_view(src.text()).substr(text_end, next - text_end), line, start}, out);
}

size_t program_of_line(const FileOutline& outline, uint32_t line) {
    const auto& ps = outline.programs;
    auto it = std::upper_bound(ps.begin(), ps.end(), line,
                               [](uint32_t l, const ProgramOutline& p) { return l < p.line; });
    return it == ps.begin() ? 0 : static_cast<size_t>(it - ps.begin() - 1);
}

std::pair<uint32_t, uint32_t> program_lines(const DocumentModel& doc, size_t i) {
    const auto& ps = doc.outline.programs;
    const uint32_t first = ps[i].line;
    const uint32_t last = i + 1 < ps.size() ? ps[i + 1].line - 1 : std::max(doc.outline.lines, first);
    return {first, last};
}

std::vector<uint32_t> lines_holding(const SourceText& src, uint32_t first, uint32_t last, std::string_view word) {
    std::vector<uint32_t> out;
    if (first == 0 || first > src.line_count() || first > last) return out;
    last = std::min(last, src.line_count());
    const std::string& t = src.text();
    auto it = t.begin() + src.line_start(first);
    const auto end = t.begin() + src.line_start(last) + static_cast<long>(src.line_text(last).size());
    auto same = [](char a, char b) { return ascii_upper(a) == b; };
    while (it < end) {
        it = std::search(it, end, word.begin(), word.end(), same);
        if (it == end) break;
        const uint32_t line = src.line_of(static_cast<uint32_t>(it - t.begin()));
        out.push_back(line);
        it = t.begin() + src.line_start(line) + static_cast<long>(src.line_text(line).size());
    }
    return out;
}

std::vector<SequenceDefinition> sequence_definitions(const DocumentModel& doc, size_t program, size_t limit) {
    std::vector<SequenceDefinition> out;
    if (program >= doc.outline.programs.size()) return out;
    const SourceText& src = doc.source();
    const auto [first, last] = program_lines(doc, program);
    FastLineParser parser;
    Block b;
    for (uint32_t line = first; line <= last && line <= src.line_count() && out.size() < limit; ++line) {
        const std::string_view text = src.line_text(line);
        // A sequence name starts its block (after blanks or a block delete).
        const size_t k = text.find_first_not_of(" \t/");
        if (k == std::string_view::npos || (text[k] != 'N' && text[k] != 'n')) continue;
        parse_source_line(src, line, parser, b);
        if (b.sequence) out.push_back({b.sequence->name, b.sequence->range, b.range});
    }
    return out;
}

std::vector<NameSite> sequence_sites(const DocumentModel& doc, size_t program, std::string_view name) {
    std::vector<NameSite> out;
    if (program >= doc.outline.programs.size()) return out;
    for (const auto& d : sequence_definitions(doc, program))
        if (d.name == name) out.push_back({d.range, true});
    // The jumps: the outline's flow sites of the program that name it.
    const SourceText& src = doc.source();
    FastLineParser parser;
    Block b;
    for (const FlowSite& site : doc.outline.programs[program].flow) {
        if (std::none_of(site.statements.begin(), site.statements.end(), [&](const FlowStatement& st) {
                return (st.kind == StmtKind::Goto || st.kind == StmtKind::If) && st.name == name;
            }))
            continue;
        parse_source_line(src, site.line, parser, b);
        for (const auto& st : b.statements)
            if (is_jump(st) && st.name == name) out.push_back({st.name_range, false});
    }
    std::sort(out.begin(), out.end(), [](const NameSite& a, const NameSite& b) { return a.range.begin < b.range.begin; });
    return out;
}

std::vector<NameSite> program_sites(const DocumentModel& doc, std::string_view name) {
    std::vector<NameSite> out;
    for (const auto& p : doc.outline.programs)
        if (!p.name.empty() && p.name == name) out.push_back({p.name_range, true});
    const SourceText& src = doc.source();
    if (src.line_count() == 0) return out;
    std::vector<uint32_t> lines = lines_holding(src, 1, src.line_count(), "CALL");
    std::vector<uint32_t> modin = lines_holding(src, 1, src.line_count(), "MODIN");
    std::vector<uint32_t> all;
    std::set_union(lines.begin(), lines.end(), modin.begin(), modin.end(), std::back_inserter(all));
    FastLineParser parser;
    Block b;
    for (uint32_t line : all) {
        parse_source_line(src, line, parser, b);
        for (const auto& st : b.statements)
            if (is_call(st) && st.name == name) out.push_back({st.name_range, false});
    }
    std::sort(out.begin(), out.end(), [](const NameSite& a, const NameSite& b) { return a.range.begin < b.range.begin; });
    return out;
}

std::vector<DiskDocument> sibling_documents(const fs::path& dir, const std::set<std::string>& skip) {
    std::vector<DiskDocument> out;
    std::error_code ec;
    std::vector<fs::path> files;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const fs::path& p = it->path();
        std::error_code ec2;
        if (!it->is_regular_file(ec2) || !is_subprogram_file(p.filename().string())) continue;
        if (skip.count(p.lexically_normal().string())) continue;
        if (it->file_size(ec2) > SubprogramDirectories::max_file_size || ec2) continue;
        files.push_back(p);
    }
    std::sort(files.begin(), files.end());
    for (const auto& p : files)
        if (auto d = read_outlined_document(p)) out.push_back(std::move(*d));
    return out;
}

std::optional<DiskDocument> read_outlined_document(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    if (!in) return std::nullopt;
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) return std::nullopt;
    return outlined_document(path_to_uri(p.string()), p.string(), std::move(text));
}

DiskDocument outlined_document(std::string uri, std::string path, std::string text) {
    DiskDocument d;
    d.uri = std::move(uri);
    d.doc.path = std::move(path);
    MemorySource src(text);
    OutlineOptions options;
    options.names_only = true;
    d.doc.outline = outline_file(src, options);
    d.doc.set_text(std::move(text));
    return d;
}

// --- what the position names ----------------------------------------------------

NameAt name_at(const DocumentModel& doc, uint32_t offset) {
    NameAt at;
    const SourceText& src = doc.source();
    if (doc.outline.programs.empty() || src.line_count() == 0) return at;
    const uint32_t line = src.line_of(offset);
    FastLineParser parser;
    Block b;
    parse_source_line(src, line, parser, b);
    auto set = [&](NameAt::Kind kind, const std::string& name, ByteRange r, bool def) {
        at.kind = kind;
        at.name = name;
        at.range = r;
        at.definition = def;
        at.program = program_of_line(doc.outline, line);
    };
    if (b.sequence && hits(b.sequence->range, offset)) {
        set(NameAt::Sequence, b.sequence->name, b.sequence->range, true);
        return at;
    }
    if (b.program_name && hits(b.program_name->range, offset)) {
        set(NameAt::Program, b.program_name->name, b.program_name->range, true);
        return at;
    }
    for (const auto& st : b.statements) {
        if (is_jump(st) && hits(st.name_range, offset)) {
            set(NameAt::Sequence, st.name, st.name_range, false);
            return at;
        }
        if (is_call(st) && hits(st.name_range, offset)) {
            set(NameAt::Program, st.name, st.name_range, false);
            return at;
        }
    }
    return at;
}

bool valid_sequence_name(std::string_view name) {
    if (name.size() < 2 || name.size() > 64 || ascii_upper(name[0]) != 'N') return false;
    if (!std::all_of(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)); }))
        return false;
    const std::string want = upper(name);
    FastLineParser parser;
    Block b;
    const std::string label = std::string(name) + " G0";
    parser.parse(LineRef{label, {}, 1, 0}, b);
    if (!b.errors.empty() || !b.sequence || b.sequence->name != want) return false;
    const std::string jump = "GOTO " + std::string(name);
    parser.parse(LineRef{jump, {}, 1, 0}, b);
    if (!b.errors.empty() || b.statements.size() != 1) return false;
    return b.statements[0].kind == StmtKind::Goto && b.statements[0].name == want;
}

// --- requests -----------------------------------------------------------------------

json definition(const DocumentModel& doc, const std::string& uri, uint32_t offset,
                const std::vector<OtherDocument>& others, Encoding enc) {
    json out = json::array();
    const NameAt at = name_at(doc, offset);
    const SourceText& src = doc.source();
    if (at.kind == NameAt::Sequence) {
        for (const auto& d : sequence_definitions(doc, at.program))
            if (d.name == at.name) out.push_back(location(uri, src, d.range, enc));
        return out;
    }
    if (at.kind != NameAt::Program) return out;
    // A program of the document first (the control looks there first), then
    // the other documents.
    for (const auto& p : doc.outline.programs)
        if (p.name == at.name) out.push_back(location(uri, src, p.name_range, enc));
    if (!out.empty()) return out;
    for (const auto& o : others)
        for (const auto& p : o.doc->outline.programs)
            if (p.name == at.name) out.push_back(location(o.uri, o.doc->source(), p.name_range, enc));
    return out;
}

json references(const DocumentModel& doc, const std::string& uri, uint32_t offset, bool include_declaration,
                const std::vector<OtherDocument>& others, Encoding enc) {
    json out = json::array();
    const NameAt at = name_at(doc, offset);
    auto add = [&](const std::string& u, const DocumentModel& d, const std::vector<NameSite>& sites) {
        for (const auto& s : sites)
            if (include_declaration || !s.definition) out.push_back(location(u, d.source(), s.range, enc));
    };
    if (at.kind == NameAt::Sequence) {
        add(uri, doc, sequence_sites(doc, at.program, at.name));
    } else if (at.kind == NameAt::Program) {
        add(uri, doc, program_sites(doc, at.name));
        for (const auto& o : others) add(o.uri, *o.doc, program_sites(*o.doc, at.name));
    }
    return out;
}

json document_highlight(const DocumentModel& doc, uint32_t offset, Encoding enc) {
    json out = json::array();
    const NameAt at = name_at(doc, offset);
    if (at.kind == NameAt::None) return out;
    const auto sites = at.kind == NameAt::Sequence ? sequence_sites(doc, at.program, at.name)
                                                   : program_sites(doc, at.name);
    for (const auto& s : sites)
        out.push_back({{"range", to_lsp_range(doc.source(), s.range, enc)}, {"kind", s.definition ? 3 : 2}});
    return out;
}

json prepare_rename(const DocumentModel& doc, uint32_t offset, Encoding enc) {
    const NameAt at = name_at(doc, offset);
    if (at.kind != NameAt::Sequence) return nullptr;
    const SourceText& src = doc.source();
    return json{{"range", to_lsp_range(src, at.range, enc)},
                {"placeholder", std::string(std::string_view(src.text()).substr(at.range.begin, at.range.size()))}};
}

json rename(const DocumentModel& doc, const std::string& uri, uint32_t offset, std::string_view new_name,
            Encoding enc) {
    const NameAt at = name_at(doc, offset);
    if (at.kind != NameAt::Sequence) throw std::invalid_argument("only a sequence name can be renamed");
    if (!valid_sequence_name(new_name))
        throw std::invalid_argument("'" + std::string(new_name) +
                                    "' is not a sequence name (N followed by letters or digits, not a keyword)");
    const std::string wanted = upper(new_name);
    if (wanted != at.name)
        for (const auto& d : sequence_definitions(doc, at.program))
            if (d.name == wanted)
                throw std::invalid_argument(wanted + " is already a sequence name of this program");
    json edits = json::array();
    for (const auto& s : sequence_sites(doc, at.program, at.name))
        edits.push_back({{"range", to_lsp_range(doc.source(), s.range, enc)}, {"newText", std::string(new_name)}});
    return json{{"changes", {{uri, std::move(edits)}}}};
}

}  // namespace osplint::lsp
