#include "lsp/text.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <stdexcept>

#include "syntax/frontend.h"

namespace osplint::lsp {

std::string_view encoding_name(Encoding e) { return e == Encoding::Utf8 ? "utf-8" : "utf-16"; }

Encoding negotiate_encoding(const json& caps) {
    if (!caps.is_object()) return Encoding::Utf16;
    auto general = caps.find("general");
    if (general == caps.end() || !general->is_object()) return Encoding::Utf16;
    auto encs = general->find("positionEncodings");
    if (encs == general->end() || !encs->is_array()) return Encoding::Utf16;
    for (const auto& e : *encs)
        if (e.is_string() && e.get<std::string>() == "utf-8") return Encoding::Utf8;
    return Encoding::Utf16;
}

namespace {

ColumnUnit unit_of(Encoding enc) { return enc == Encoding::Utf8 ? ColumnUnit::Byte : ColumnUnit::Utf16; }

uint32_t get_u32(const json& obj, const char* key) {
    if (!obj.is_object()) throw std::invalid_argument("a position must be an object");
    auto it = obj.find(key);
    if (it == obj.end() || !it->is_number())
        throw std::invalid_argument(std::string("position.") + key + " must be a number");
    if (it->is_number_unsigned()) return static_cast<uint32_t>(std::min<uint64_t>(it->get<uint64_t>(), UINT32_MAX));
    if (it->is_number_integer()) {
        const int64_t v = it->get<int64_t>();
        return v < 0 ? 0 : static_cast<uint32_t>(std::min<int64_t>(v, UINT32_MAX));
    }
    const double d = it->get<double>();
    return d <= 0 ? 0 : d >= 4294967295.0 ? UINT32_MAX : static_cast<uint32_t>(d);
}

// Byte offset of (line, character) in `text` without building a line index.
uint32_t offset_in(std::string_view text, uint32_t line, uint32_t character, Encoding enc) {
    std::size_t start = 0;
    for (uint32_t l = 0; l < line; ++l) {
        std::size_t i = start;
        while (i < text.size() && text[i] != '\n' && text[i] != '\r') ++i;
        if (i >= text.size()) return static_cast<uint32_t>(text.size());  // past the last line
        i += (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ? 2 : 1;
        start = i;
    }
    std::size_t end = start;
    while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
    return static_cast<uint32_t>(start) + bytes_for_columns(text.substr(start, end - start), character, unit_of(enc));
}

}  // namespace

json to_lsp_position(const Position& p, Encoding enc) {
    return json{{"line", p.line > 0 ? p.line - 1 : 0}, {"character", enc == Encoding::Utf8 ? p.byte_col : p.utf16_col}};
}

json to_lsp_position(const SourceText& text, uint32_t offset, Encoding enc) {
    return to_lsp_position(text.position(offset), enc);
}

json to_lsp_range(const SourceText& text, ByteRange range, Encoding enc) {
    return json{{"start", to_lsp_position(text, range.begin, enc)},
                {"end", to_lsp_position(text, std::max(range.begin, range.end), enc)}};
}

uint32_t from_lsp_position(const SourceText& text, const json& position, Encoding enc) {
    const uint32_t line = get_u32(position, "line");
    const uint32_t character = get_u32(position, "character");
    if (line >= text.line_count()) return text.size();
    return text.offset_of(line + 1, character, unit_of(enc));
}

ByteRange from_lsp_range(const SourceText& text, const json& range, Encoding enc) {
    if (!range.is_object() || !range.contains("start") || !range.contains("end"))
        throw std::invalid_argument("a range needs start and end");
    uint32_t a = from_lsp_position(text, range["start"], enc);
    uint32_t b = from_lsp_position(text, range["end"], enc);
    if (b < a) std::swap(a, b);
    return {a, b};
}

void apply_change(std::string& text, const json& change, Encoding enc) {
    if (!change.is_object()) throw std::invalid_argument("a content change must be an object");
    auto t = change.find("text");
    if (t == change.end() || !t->is_string()) throw std::invalid_argument("a content change needs a text");
    const std::string& replacement = t->get_ref<const std::string&>();
    auto r = change.find("range");
    if (r == change.end() || r->is_null()) {
        text = replacement;
        return;
    }
    if (!r->is_object() || !r->contains("start") || !r->contains("end"))
        throw std::invalid_argument("a range needs start and end");
    const json& s = (*r)["start"];
    const json& e = (*r)["end"];
    uint32_t a = offset_in(text, get_u32(s, "line"), get_u32(s, "character"), enc);
    uint32_t b = offset_in(text, get_u32(e, "line"), get_u32(e, "character"), enc);
    if (b < a) std::swap(a, b);
    text.replace(a, b - a, replacement);
}

std::optional<std::string> uri_to_path(std::string_view uri) {
    constexpr std::string_view kScheme = "file://";
    if (uri.size() < kScheme.size()) return std::nullopt;
    for (std::size_t i = 0; i < kScheme.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(uri[i])) != kScheme[i]) return std::nullopt;
    std::string_view rest = uri.substr(kScheme.size());
    // file://host/path: only an empty host or localhost is local.
    const std::size_t slash = rest.find('/');
    if (slash == std::string_view::npos) return std::nullopt;
    const std::string_view host = rest.substr(0, slash);
    if (!host.empty() && host != "localhost") return std::nullopt;
    rest = rest.substr(slash);
    std::string out;
    for (std::size_t i = 0; i < rest.size(); ++i) {
        const char c = rest[i];
        if (c == '%' && i + 2 < rest.size() + 0 && std::isxdigit(static_cast<unsigned char>(rest[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(rest[i + 2]))) {
            out += static_cast<char>(std::stoi(std::string(rest.substr(i + 1, 2)), nullptr, 16));
            i += 2;
        } else if (c == '?' || c == '#') {
            break;
        } else {
            out += c;
        }
    }
    if (out.find('\0') != std::string::npos) return std::nullopt;
    return out;
}

std::string path_to_uri(std::string_view path) {
    static constexpr char kHex[] = "0123456789ABCDEF";
    std::string out = "file://";
    for (char c : path) {
        const auto u = static_cast<unsigned char>(c);
        if (std::isalnum(u) || c == '/' || c == '-' || c == '.' || c == '_' || c == '~') {
            out += c;
        } else {
            out += '%';
            out += kHex[u >> 4];
            out += kHex[u & 15];
        }
    }
    return out;
}

namespace {

// Ranges the front end did not set stay {0, 0}. (A real range is never
// {0, 0} here: tail blocks start after the first line, and the changed lines
// are parsed after a padding line, see reparse.)
void shift(ByteRange& r, int64_t d) {
    if (r.begin == 0 && r.end == 0) return;
    r.begin = static_cast<uint32_t>(r.begin + d);
    r.end = static_cast<uint32_t>(r.end + d);
}

// Moves a block by `dbytes` bytes and `dlines` lines. Every byte range of the
// model (model.h) is listed here.
void shift_block(Block& b, int64_t dbytes, int64_t dlines) {
    b.line = static_cast<uint32_t>(b.line + dlines);
    if (dbytes == 0) return;
    b.line_start = static_cast<uint32_t>(b.line_start + dbytes);
    b.range.begin = static_cast<uint32_t>(b.range.begin + dbytes);
    b.range.end = static_cast<uint32_t>(b.range.end + dbytes);
    if (b.program_name) shift(b.program_name->range, dbytes);
    if (b.sequence) shift(b.sequence->range, dbytes);
    shift(b.block_delete_range, dbytes);
    for (auto& w : b.words) {
        shift(w.range, dbytes);
        shift(w.address_range, dbytes);
        shift(w.value_range, dbytes);
    }
    for (auto& a : b.assignments) shift(a.range, dbytes);
    for (auto& s : b.statements) {
        shift(s.range, dbytes);
        shift(s.keyword_range, dbytes);
        shift(s.name_range, dbytes);
    }
    for (auto& c : b.comments) shift(c.range, dbytes);
    for (auto& e : b.exprs) shift(e.range, dbytes);
    for (auto& e : b.errors) shift(e.range, dbytes);
}

// Lines around an edit that must be free of syntax errors for the edit to be
// parsed on its own.
constexpr uint32_t kErrorContext = 2;

// Blocks of a text: one per line, except an empty last line (frontend.h).
uint32_t blocks_of(const SourceText& s) {
    const uint32_t lines = s.line_count();
    if (lines == 0) return 0;
    return s.line_start(lines) < s.size() ? lines : lines - 1;
}

}  // namespace

ReparseStats reparse(ProgramFile& file, std::string new_text) {
    ReparseStats stats;
    const std::string& old_text = file.source.text();
    auto full = [&](std::string text) {
        stats.full = true;
        ProgramFile fresh = parse_program_file(file.path, std::move(text));
        stats.lines_parsed = fresh.source.line_count();
        file = std::move(fresh);
        return stats;
    };
    if (new_text.size() > UINT32_MAX - 1 || old_text.size() > UINT32_MAX - 1) return full(std::move(new_text));
    // Not parsed from this text (or never parsed): parse everything.
    if (file.source.line_count() == 0 || file.blocks.size() != blocks_of(file.source)) return full(std::move(new_text));

    // The common prefix and suffix of the old and the new text.
    const std::size_t old_len = old_text.size(), new_len = new_text.size();
    const std::size_t min_len = std::min(old_len, new_len);
    std::size_t p = 0;
    while (p < min_len && old_text[p] == new_text[p]) ++p;
    if (p == old_len && p == new_len) return stats;  // unchanged
    std::size_t s = 0;
    while (s < min_len - p && old_text[old_len - 1 - s] == new_text[new_len - 1 - s]) ++s;

    SourceText ns(std::move(new_text));
    const SourceText& os = file.source;
    // Lines before `first` lie wholly in the common prefix, in both texts.
    const uint32_t first = std::min(os.line_of(static_cast<uint32_t>(p)), ns.line_of(static_cast<uint32_t>(p)));
    // Lines that start inside the common suffix are the same in both texts.
    const uint32_t tail_old = os.line_count() - os.line_of(static_cast<uint32_t>(old_len - s));
    const uint32_t tail_new = ns.line_count() - ns.line_of(static_cast<uint32_t>(new_len - s));
    if (tail_old != tail_new) {
        return full(ns.text());
    }
    const uint32_t tail = tail_old;
    const uint32_t last_new = ns.line_count() - tail;  // last line (1-based) to parse again
    const uint32_t last_old = os.line_count() - tail;

    // Parse the changed lines, with the terminator of the last one.
    std::vector<Block> middle;
    if (last_new >= first) {
        const uint32_t from = ns.line_start(first);
        const uint32_t to = tail > 0 ? ns.line_start(last_new + 1) : ns.size();
        // A padding line first: then no real range of the piece is {0, 0}.
        std::string slice = "\n";
        slice.append(ns.text(), from, to - from);
        ProgramFile piece = parse_program_file(file.path, std::move(slice));
        if (piece.blocks.empty()) return full(ns.text());
        middle.assign(std::make_move_iterator(piece.blocks.begin() + 1), std::make_move_iterator(piece.blocks.end()));
        for (auto& b : middle) shift_block(b, static_cast<int64_t>(from) - 1, static_cast<int64_t>(first) - 2);
        stats.lines_parsed = last_new - first + 1;
    }
    // Tree-sitter's error recovery is not line-local: a line with a syntax
    // error may parse differently inside the file than alone, and may change
    // how its neighbours parse. Near syntax errors, parse everything.
    for (const auto& b : middle)
        if (!b.errors.empty()) return full(ns.text());
    {
        const uint32_t lo = first > 1 + kErrorContext ? first - 1 - kErrorContext : 0;
        const uint32_t hi = std::min<uint32_t>(static_cast<uint32_t>(file.blocks.size()), last_old + kErrorContext);
        for (uint32_t i = lo; i < hi; ++i)
            if (!file.blocks[i].errors.empty()) return full(ns.text());
    }

    // Old blocks [first-1, old_mid_end) are replaced; the ones after are shifted.
    const uint32_t old_blocks = static_cast<uint32_t>(file.blocks.size());
    const uint32_t old_mid_end = std::min(old_blocks, last_old);
    const uint32_t old_mid_begin = std::min(first - 1, old_mid_end);
    const uint32_t expected = blocks_of(ns);
    if (old_mid_begin + middle.size() + (old_blocks - old_mid_end) != expected) {
        return full(ns.text());
    }
    const int64_t dbytes = static_cast<int64_t>(new_len) - static_cast<int64_t>(old_len);
    const int64_t dlines = static_cast<int64_t>(ns.line_count()) - static_cast<int64_t>(os.line_count());
    for (uint32_t i = old_mid_end; i < old_blocks; ++i) shift_block(file.blocks[i], dbytes, dlines);
    auto& blocks = file.blocks;
    const std::size_t replaced = old_mid_end - old_mid_begin;
    const std::size_t common = std::min(replaced, middle.size());
    std::move(middle.begin(), middle.begin() + static_cast<std::ptrdiff_t>(common), blocks.begin() + old_mid_begin);
    if (middle.size() > replaced) {
        blocks.insert(blocks.begin() + old_mid_begin + static_cast<std::ptrdiff_t>(common),
                      std::make_move_iterator(middle.begin() + static_cast<std::ptrdiff_t>(common)),
                      std::make_move_iterator(middle.end()));
    } else if (replaced > middle.size()) {
        blocks.erase(blocks.begin() + old_mid_begin + static_cast<std::ptrdiff_t>(common),
                     blocks.begin() + old_mid_begin + static_cast<std::ptrdiff_t>(replaced));
    }
    file.source = std::move(ns);
    file.programs = split_programs(file.blocks);
    return stats;
}

}  // namespace osplint::lsp
