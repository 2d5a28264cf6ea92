// Suppression directives written in the program's own comments.
//
//     G0 X0 M52 (osplint: disable=OSP104 -- checked on the machine)   this block
//     (osplint: disable=OSP104,OSP108 -- reason)                      the next block
//     CALL OZAGR PR=5 PZ=-20 PI=12 M52 M8
//     (osplint: disable-file=OSP005 -- shop macros live on the control)  the whole file
//
// Grammar of the comment text (case does not matter, blanks are free between tokens):
//
//     directive := "osplint" ":" action "=" id { "," id } [ "--" reason ]
//     action    := "disable" | "disable-file"
//     id        := a rule ID such as OSP104
//     reason    := any text up to the closing parenthesis (an OSP comment cannot hold ')')
//
// `disable` on a block with executable content silences the rules on that block;
// on a line holding only comments it silences them on the next block that has
// executable content. `disable-file` silences them everywhere in the file.
//
// The pass runs after analysis over the parsed file's comments (no re-parse):
// findings a directive covers move to FileResult::suppressed with the reason;
// OSP001 (syntax-error) cannot be suppressed. Directives that cannot be honoured
// are reported as OSP901 (unknown-rule-in-suppression); directive entries that
// silenced nothing as OSP902 (unused-suppression, off by default).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/analyzer.h"
#include "semantics/config.h"
#include "support/diagnostic.h"
#include "syntax/source.h"

namespace osplint {

// A finding that is not reported because a directive or a baseline covers it.
struct SuppressedDiagnostic {
    enum class Kind { InSource, Baseline };
    Diagnostic diagnostic;
    Kind kind = Kind::InSource;
    std::string reason;                    // the directive's `-- reason`, or the baseline file
    bool file_scope = false;               // disable-file
    std::optional<SourceRange> directive;  // the directive's comment (InSource only)
};

// One parsed directive. Offsets are absolute byte offsets into the file text.
struct SuppressionDirective {
    enum class Action { Disable, DisableFile };
    struct Id {
        std::string text;  // as written
        ByteRange range;
    };
    Action action = Action::Disable;
    std::vector<Id> ids;
    std::string reason;  // trimmed; empty when none was given
    ByteRange comment;   // the whole comment, parentheses included
};

// The outcome of reading one comment as a directive.
struct DirectiveParse {
    bool is_directive = false;  // the comment starts with `osplint:`
    std::optional<SuppressionDirective> directive;  // set when it is well formed
    std::string error;          // why it is malformed (when is_directive && !directive)
    ByteRange error_range;
};

// Whether a block is something a `disable` directive can apply to: executable
// content, or a line the parser could not read (its OSP001 stays reported).
bool suppression_target(const Block& b);

// Reads the comment at `comment` (parentheses included) of `text`.
DirectiveParse parse_directive(std::string_view text, ByteRange comment);

struct SuppressionResult {
    std::vector<Diagnostic> diagnostics;           // what remains, plus OSP901/OSP902, sorted
    std::vector<SuppressedDiagnostic> suppressed;  // sorted like diagnostics
};

// A line holding directive comments, as the pass needs it. Blocks are lines:
// apply_suppressions makes these from a parsed file, the streaming check
// collects them as it reads.
struct DirectiveLine {
    uint32_t line = 0;        // 1-based
    uint32_t line_start = 0;  // byte offset of the line
    std::string text;         // the line without its terminator
    std::string program;      // the name of the program it belongs to
    uint32_t target_line = 0; // the line `disable` silences (the next with content); 0: none
    std::vector<ByteRange> comments;  // absolute offsets
};

// Applies the directives of `lines` (in file order) to `diagnostics`.
SuppressionResult apply_directive_lines(const std::vector<DirectiveLine>& lines, std::vector<Diagnostic> diagnostics,
                                        const Config& config, const AnalysisOptions& options);

// Applies the directives of `file` to the findings `analyze` produced for it.
// `options.only_rules` and `config` decide whether OSP901/OSP902 are reported,
// exactly as they decide for every other rule.
SuppressionResult apply_suppressions(const ProgramFile& file, std::vector<Diagnostic> diagnostics,
                                     const Config& config, const AnalysisOptions& options = {});

}  // namespace osplint
