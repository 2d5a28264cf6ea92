// Report writers: the one diagnostic model rendered as text, JSON, SARIF,
// gcc lines, GitHub workflow commands or an HTML page (output/html.h),
// written as the findings arrive.
//
// A writer is a DiagnosticSink: it writes each finding when it gets it, so
// memory does not grow with their number (the JSON report's suppressed
// findings, which follow a file's findings, wait in a spool that goes to a
// temporary file past a few megabytes). `finish` writes the end of the report:
// the summary line, or the closing brackets and the counts.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "osplint/diagnostic.h"

namespace osplint {

enum class Format { Text, Json, Sarif, Gcc, Github, Html };
std::optional<Format> parse_format(std::string_view name);

// What a run found, over every finding (folded and omitted ones included).
struct Counts {
    uint64_t files = 0;
    uint64_t error = 0, warning = 0, info = 0;
    uint64_t suppressed = 0;
    uint64_t folded = 0;        // findings shown only as a count (--fold, --max-findings)
    uint64_t unreadable = 0;    // files that could not be read
    uint64_t fixable = 0;       // findings shown with a safe fix (`--fix` applies it)
    uint64_t unsafe_fixable = 0;  // findings shown with an unsafe fix only (`--unsafe-fixes`)
    void add(Severity s, uint64_t n = 1) {
        if (s == Severity::Error) error += n;
        else if (s == Severity::Warning) warning += n;
        else info += n;
    }
    uint64_t at_least(Severity s) const {
        return error + (s <= Severity::Warning ? warning : 0) + (s <= Severity::Info ? info : 0);
    }
};

class SideViews;

struct WriterOptions {
    bool color = false;                 // text: ANSI colours
    std::filesystem::path sarif_root;   // SARIF: paths relative to it (%SRCROOT%)
    // HTML: where the side views of the files are taken from (output/sideview.h;
    // none when null), and the path standard input is reported under (its
    // lines cannot be read again: its findings show their own line only).
    SideViews* side_views = nullptr;
    std::string stdin_path;
};

class ReportWriter : public DiagnosticSink {
public:
    // Writes what ends the report; `counts` are the run's totals.
    virtual void finish(const Counts& counts) = 0;
};

std::unique_ptr<ReportWriter> make_writer(Format format, std::ostream& out, const WriterOptions& options = {});

// One finding as the text report shows it: `path:line:col: severity[ID]:
// message`, the source line with a caret under the range, notes and fixes;
// with `explain_hint`, a last line pointing at `osplint explain ID` (the text
// report gives it with the first finding of each rule only).
std::string render_text_diagnostic(const std::string& path, const Diagnostic& d, bool color,
                                   bool explain_hint = false);
// The part of a finding's line (made printable) the text report shows, and
// where its carets go (code points): a line longer than kShownColumns is cut
// to that many code points around the range start, "..." marking each cut;
// the carets end at the text shown. A range starting past the text (beyond
// what was kept of a very long line) gets no caret (carets 0).
struct ShownLine {
    std::string text;
    uint32_t caret = 0;   // columns before the first caret
    uint32_t carets = 0;  // how many
};
inline constexpr uint32_t kShownColumns = 120;
inline constexpr uint32_t kShownBefore = 40;  // columns kept before the range when the line is cut
ShownLine shown_line(std::string_view line, uint32_t start, uint32_t end);

// The text report's last line: "2 errors, 1 warning, 0 infos in 3 files".
std::string render_summary(const Counts& counts);

// The escaping of GitHub workflow commands: the message ("data") escapes
// % CR LF; property values also escape ':' and ','.
std::string github_escape_data(std::string_view s);
std::string github_escape_property(std::string_view s);

// SARIF constants and the artifact URI of a checked path: relative to `root`
// when the file is under it (`relative` set), else an absolute file: URI.
inline constexpr std::string_view kProjectUri = "https://github.com/osplint/osplint";
inline constexpr std::string_view kSarifSchema =
    "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json";
inline constexpr std::string_view kFingerprintKey = "osplintFingerprint/v1";
std::string sarif_artifact_uri(const std::string& path, const std::filesystem::path& root, bool& relative);

}  // namespace osplint
