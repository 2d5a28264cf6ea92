// Suppression directives written in the program's own comments: their syntax.
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
//     id        := a rule ID such as OSP104, or a rule name such as m52-on-call-line
//     reason    := any text up to the closing parenthesis (an OSP comment cannot hold ')')
//
// `disable` on a block with executable content applies to that block; on a
// line holding only comments it applies to the next block that has executable
// content. `disable-file` applies everywhere in the file. What a directive
// silences is decided by the engine (engine/suppress.h).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "syntax/model.h"

namespace osplint {

// One parsed directive. Offsets are those of the text it was read from.
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

// Whether any comment of the block (whose line text is `line_text`) is a directive.
bool has_directive(const Block& b, std::string_view line_text);

}  // namespace osplint
