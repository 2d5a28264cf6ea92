#include "lsp/text.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <stdexcept>

#include "support/io.h"


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
    const char* const b = text.data();
    const char* const e = b + text.size();
    const char* const start = skip_lines(b, e, line);
    if (!start) return static_cast<uint32_t>(text.size());  // past the last line
    const char* end = find_line_break(start, e);
    if (!end) end = e;
    return static_cast<uint32_t>(start - b) +
           bytes_for_columns(std::string_view(start, static_cast<size_t>(end - start)), character, unit_of(enc));
}

}  // namespace

// Built member by member: an initializer list copies every element it is
// given, and a document's diagnostics hold thousands of positions.
json to_lsp_position(const Position& p, Encoding enc) {
    json out(json::value_t::object);
    out["line"] = p.line > 0 ? p.line - 1 : 0;
    out["character"] = enc == Encoding::Utf8 ? p.byte_col : p.utf16_col;
    return out;
}

json to_lsp_position(const SourceText& text, uint32_t offset, Encoding enc) {
    return to_lsp_position(text.position(offset), enc);
}

json to_lsp_range(const SourceText& text, ByteRange range, Encoding enc) {
    json out(json::value_t::object);
    out["start"] = to_lsp_position(text, range.begin, enc);
    out["end"] = to_lsp_position(text, std::max(range.begin, range.end), enc);
    return out;
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

}  // namespace osplint::lsp
