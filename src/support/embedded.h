// Files compiled into the binary: rule docs (docs/rules/*.md) and the shipped
// macro catalog (data/*.toml). One source serves `osplint explain`, hover in
// the language server and SARIF help text.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>

namespace osplint::embedded {

struct File {
    std::string_view path;     // relative to the source tree, e.g. "docs/rules/OSP104.md"
    std::string_view content;
};
extern const File kFiles[];
extern const std::size_t kFileCount;

inline std::optional<std::string_view> find(std::string_view path) {
    for (std::size_t i = 0; i < kFileCount; ++i)
        if (kFiles[i].path == path) return kFiles[i].content;
    return std::nullopt;
}

}  // namespace osplint::embedded
