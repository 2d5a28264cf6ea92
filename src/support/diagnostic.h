// The one diagnostic model. Every renderer (text, JSON, SARIF, gcc, GitHub,
// LSP) reads these fields and nothing else.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "syntax/model.h"
#include "syntax/source.h"

namespace osplint {

enum class Severity { Info = 0, Warning = 1, Error = 2 };

std::string_view severity_name(Severity s);                 // "info", "warning", "error"
std::optional<Severity> parse_severity(std::string_view s);  // inverse of severity_name

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
    // rule, program name, normalised block text and occurrence, never the line number.
    std::string fingerprint;
};

// Sort key used by every renderer: position, then rule ID.
bool diagnostic_less(const Diagnostic& a, const Diagnostic& b);

}  // namespace osplint
