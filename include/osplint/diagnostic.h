// osplint's diagnostic model: what a check reports, and the sink it reports to.
//
// Self-contained (standard library only): every layer of osplint and every
// program that links the library uses these types. One model, many
// renderers: text, JSON, SARIF, gcc, GitHub annotations and the language
// server all read these fields and nothing else.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

// OSPLINT_API marks what the shared library (libosplint.so) exports; the rest
// of the library is built with hidden visibility.
#ifndef OSPLINT_API
#if defined(__GNUC__) || defined(__clang__)
#define OSPLINT_API __attribute__((visibility("default")))
#else
#define OSPLINT_API
#endif
#endif

namespace osplint {

// Half-open byte range [begin, end) into a file's text.
struct ByteRange {
    uint32_t begin = 0;
    uint32_t end = 0;
    bool empty() const { return begin >= end; }
    uint32_t size() const { return end > begin ? end - begin : 0; }
    bool contains(uint32_t off) const { return off >= begin && off < end; }
    friend bool operator==(const ByteRange&, const ByteRange&) = default;
};

// A resolved position: a 1-based line and 0-based columns counted in bytes,
// Unicode code points and UTF-16 code units (an invalid UTF-8 byte counts as
// one of each). Renderers add 1 where their format is 1-based.
struct Position {
    uint32_t line = 1;
    uint32_t byte_col = 0;
    uint32_t cp_col = 0;
    uint32_t utf16_col = 0;
    friend bool operator==(const Position&, const Position&) = default;
};

enum class Severity { Info = 0, Warning = 1, Error = 2 };

OSPLINT_API std::string_view severity_name(Severity s);                 // "info", "warning", "error"
OSPLINT_API std::optional<Severity> parse_severity(std::string_view s);  // inverse of severity_name

// A resolved source range: byte offsets plus display positions of both ends.
struct SourceRange {
    ByteRange bytes;
    Position start;
    Position end;
};

// One text edit: replace `range` by `replacement` (an insertion has an empty range).
struct TextEdit {
    SourceRange range;
    std::string replacement;
};

struct Fix {
    std::string title;  // "Replace M52 by PM=52"
    std::vector<TextEdit> edits;
    // A safe fix keeps what the program means and only makes it what the
    // manual asks for; `check --fix` applies it. An unsafe fix changes what
    // the machine does (another cancel code, another mode) and is applied
    // only with `--unsafe-fixes`; editors offer both.
    bool safe = false;
};

struct Note {
    std::string message;
    std::optional<SourceRange> range;  // where the note points, if anywhere
};

struct Diagnostic {
    std::string rule;  // "OSP104"
    std::string name;  // "m52-on-call-line"
    Severity severity = Severity::Error;
    std::string message;
    SourceRange range;
    std::vector<Note> notes;
    std::vector<Fix> fixes;
    // The text of the line the range starts on (for renderers that show it;
    // capped in length), so output never needs the whole file again.
    std::string line_text;
    // Stable identity of the finding for baselines and SARIF partialFingerprints:
    // rule, program name, normalised block text and occurrence, never the line
    // number. Empty when the consumer did not ask for fingerprints.
    std::string fingerprint;
    // The finding's kind: findings of one kind differ only in their numbers
    // (a hash of the rule and of the message with its numbers left out, or of
    // a key the rule gives). Used to fold long runs of one kind.
    uint64_t kind = 0;
    // Set on a finding that stands for others of its kind that are not
    // reported one by one (folded): how many, and the range of the last.
    uint64_t folded = 0;
    std::optional<SourceRange> folded_last;
};

// Order of findings inside one file: position, then rule, then message.
OSPLINT_API bool diagnostic_less(const Diagnostic& a, const Diagnostic& b);

// A finding that is not reported because a directive or a baseline covers it.
struct SuppressedDiagnostic {
    enum class Kind { InSource, Baseline };
    Diagnostic diagnostic;
    Kind kind = Kind::InSource;
    std::string reason;                    // the directive's `-- reason`, or the baseline file
    bool file_scope = false;               // disable-file
    std::optional<SourceRange> directive;  // the directive's comment (InSource only)
};

// Everything a check found in one file.
struct FileResult {
    std::string path;
    std::vector<Diagnostic> diagnostics;
    // Findings silenced by an `(osplint: disable=...)` directive of the file
    // (or, in the CLI, by a baseline), with the reason given. Not counted in
    // summaries or exit codes; listed by the JSON and SARIF reports.
    std::vector<SuppressedDiagnostic> suppressed;
    // Set when the file could not be read (missing, a directory, a read error,
    // too large).
    std::string io_error;
};

// Where a check reports, finding by finding, as it goes: a renderer writing
// to a stream, a collector (FileResult), a filter in front of either. The
// calls for one file come from one thread, in this order: begin_file, then
// diagnostic() / suppressed() in the order the analysis produces them (block
// by block in program order; findings about a whole program after its last
// block; findings about the file's suppression directives at its end), then
// end_file.
class OSPLINT_API DiagnosticSink {
public:
    virtual ~DiagnosticSink() = default;
    // Whether the findings must carry fingerprints (they cost memory and time).
    virtual bool wants_fingerprints() const { return false; }
    virtual void begin_file(const std::string& path) { (void)path; }
    virtual void diagnostic(Diagnostic&& d) = 0;
    virtual void suppressed(SuppressedDiagnostic&& s) { (void)s; }
    // `io_error` is empty when the file was read to its end.
    virtual void end_file(const std::string& path, const std::string& io_error) {
        (void)path;
        (void)io_error;
    }
};

}  // namespace osplint
