// SARIF 2.1.0 for GitHub code scanning and other SARIF consumers.
//
// One run. `tool.driver.rules` holds every rule the run reports (ID order), with
// the short and full descriptions and the rule's documentation (the embedded
// docs/rules/OSPnnn.md) as help text and Markdown. Each result carries ruleId
// and ruleIndex, a level (error, warning; info -> note), the message with its
// notes, a location relative to %SRCROOT% (the directory osplint ran in, given
// in originalUriBaseIds), a region in UTF-16 code units (columnKind
// "utf16CodeUnits"), the line-independent fingerprint as partialFingerprints
// "osplintFingerprint/v1", notes with a range as relatedLocations, and fixes.
// Suppressed findings are listed too, with `suppressions` (kind "inSource" with
// the directive's reason, or "external" for a baseline), so that code
// scanning shows them as closed rather than forgetting them.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "osplint/osplint.h"

namespace osplint {

inline constexpr std::string_view kProjectUri = "https://github.com/osplint/osplint";
inline constexpr std::string_view kSarifSchema =
    "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json";
inline constexpr std::string_view kFingerprintKey = "osplintFingerprint/v1";

struct SarifOptions {
    // The directory paths are made relative to (%SRCROOT%): the current directory.
    std::filesystem::path root;
};

std::string render_sarif(const std::vector<FileResult>& results, const SarifOptions& options);

// The artifact URI of a checked path: relative to `root` when the file is
// under it (`relative` set), else an absolute file: URI. Percent-encoded.
std::string sarif_artifact_uri(const std::string& path, const std::filesystem::path& root, bool& relative);

}  // namespace osplint
