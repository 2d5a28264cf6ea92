// Language server: what a block will do, shown in the text. Inlay hints give,
// after a block that runs a catalog macro or drills a fixed-cycle hole, where
// the cycle axis goes (the envelope of the motion evaluator, semantics/motion.h:
// `⤓ Z-37 ⤒ Z5`), and after an argument written as an expression its value
// when the analysis knows it. Signature help shows, inside a CALL or MODIN of
// a catalog macro, its arguments with the one under the cursor.
#pragma once

#include <atomic>
#include <cstdint>

#include "engine/summaries.h"
#include "engine/workspace.h"
#include "lsp/document.h"
#include "lsp/text.h"
#include "semantics/config.h"
#include "semantics/motion.h"

namespace osplint::lsp {

// The hints of lines [first, last] (1-based): the engine walks the document
// (without the rules) up to `last` and stops there; `cancel` stops it too.
json inlay_hints(const DocumentModel& doc, const Config& config, const ProgramNames* known,
                 SubprogramSummaries* summaries, uint32_t first, uint32_t last, Encoding enc,
                 const std::atomic<bool>* cancel = nullptr);

// The label of an envelope's hint: "⤓ Z-37 ⤒ Z5"; an end the analysis cannot
// bound shows its known point and the side it may pass ("⤓ ≤Z-3 ⤒ ≥Z3" when
// the start of a hole is not known), "Z+limit" a trip to the travel limit, "Z?"
// an end with no known point. Empty when the plane or both ends are not known.
std::string envelope_label(const Envelope& env);

// Null when the offset is not in the arguments of a CALL / MODIN of a macro of the catalog.
json signature_help(const DocumentModel& doc, const Config& config, uint32_t offset);

}  // namespace osplint::lsp
