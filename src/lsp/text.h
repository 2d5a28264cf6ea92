// Language server: documents, positions and incremental re-parsing.
//
// Internally every location is a byte offset (model.h). LSP positions are a
// 0-based line and a 0-based character counted in the negotiated encoding:
// UTF-8 code units (bytes) or UTF-16 code units. Conversion goes through
// SourceText in both directions, so a comment such as `(裏ザグリ)` or an emoji
// outside the BMP moves every later column by the right amount in either
// encoding.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "syntax/model.h"
#include "syntax/source.h"

namespace osplint::lsp {

using json = nlohmann::json;

enum class Encoding { Utf8, Utf16 };

std::string_view encoding_name(Encoding e);  // "utf-8" / "utf-16"
// "utf-8" when the client offers it (general.positionEncodings), else "utf-16".
Encoding negotiate_encoding(const json& client_capabilities);

// LSP position <-> byte offset. Characters past the end of a line clamp to the
// line end, lines past the end of the text clamp to the end of the text.
json to_lsp_position(const SourceText& text, uint32_t offset, Encoding enc);
json to_lsp_range(const SourceText& text, ByteRange range, Encoding enc);
json to_lsp_position(const Position& p, Encoding enc);  // a resolved Position (1-based line)
uint32_t from_lsp_position(const SourceText& text, const json& position, Encoding enc);  // throws on bad JSON
ByteRange from_lsp_range(const SourceText& text, const json& range, Encoding enc);

// Applies one TextDocumentContentChangeEvent (with a range: incremental;
// without: full replacement) to `text`. Throws std::invalid_argument on a
// malformed event.
void apply_change(std::string& text, const json& change, Encoding enc);

// The file path of a `file://` URI (percent-decoded), or nullopt.
std::optional<std::string> uri_to_path(std::string_view uri);
std::string path_to_uri(std::string_view path);

}  // namespace osplint::lsp
