// The checker: program model in, diagnostics out.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "semantics/config.h"
#include "support/diagnostic.h"
#include "semantics/modal.h"
#include "engine/rule.h"
#include "syntax/source.h"

namespace osplint {

// Program names known beyond the file being checked (other checked files,
// .SSB/.SUB/.LIB files of the same directory), upper case.
using ProgramNames = std::set<std::string, std::less<>>;

struct AnalysisOptions {
    const ProgramNames* known_programs = nullptr;
    bool keep_states = false;  // fill AnalysisResult::blocks (trace, language server)
    // Only run these rules (IDs); empty = every enabled rule. Used by fixtures.
    std::vector<std::string> only_rules;
};

struct BlockInfo {
    ModalState before;
    ModalState after;
    std::optional<MacroCall> call;  // args' Word pointers point into ProgramFile::blocks
    bool reachable = false;
};

struct AnalysisResult {
    std::vector<Diagnostic> diagnostics;  // sorted
    std::vector<BlockInfo> blocks;        // per block, when keep_states
    // Instrumentation: how many times the fixpoint applied a block to a state
    // (over every program of the file). Stays within a small multiple of the
    // number of blocks: each block's entry state can only lose information.
    uint64_t transfer_count = 0;
};

// Runs every enabled rule over a parsed file.
AnalysisResult analyze(const ProgramFile& file, const Config& config, const AnalysisOptions& options = {});

// Sequence names of a program's blocks -> the blocks that define them
// (indices from the program's first block).
using Labels = std::unordered_map<std::string, std::vector<uint32_t>>;
Labels labels_of(const Block* blocks, uint32_t count);
// Whether a file holds subprograms only (.SSB/.SUB/.LIB/.MSB): each of its
// programs starts with an unknown state.
bool file_is_subprogram_library(std::string_view path);
// Whether a block ends its program where control reaches it (M02, M30, RTS).
bool ends_program(const Block& block);

// One program, analysed as analyze() analyses each: its control flow, the
// modal state at every block to a fixpoint, then every rule on every block
// in order. Shared by analyze() and the streaming check's programs with jumps.
struct ProgramInput {
    const Block* blocks = nullptr;  // the program's blocks
    uint32_t count = 0;
    const Program* program = nullptr;
    const std::vector<Block>* file_blocks = nullptr;  // ProgramView::blocks (null when streaming)
    bool subprogram = false;
    const Labels* labels = nullptr;
};
// Called for block i after the rules saw it.
using BlockHook = std::function<void(uint32_t i, const BlockView& view, const std::optional<MacroCall>& call)>;
// Runs `rules` over the program; `before(i)`, when set, is called before the
// rules see block i. Returns how many times a block was applied to a state.
uint64_t analyze_program(const ProgramInput& input, const Config& config, RuleContext& ctx,
                         const std::vector<std::unique_ptr<Rule>>& rules, const std::function<void(uint32_t)>& before,
                         const BlockHook& after);

// The state at the start of a program (from the configuration's machine defaults).
ModalState initial_state(const Config& config, bool subprogram);

// Applies one block to the state (the transfer function shared by everything
// that needs modal state: the analyzer, `osplint trace`, the language server).
void apply_block(const Block& block, const MacroCall* call, const Catalog& catalog, ModalState& state);

// Plain moves. Most blocks of a CAM-posted program are `X.. Y.. Z..`, perhaps
// with a sequence name, G0..G3 and F. A block is a plain move when its words
// are only literal X, Y, Z, F and G0/G1/G2/G3 (no `=`, no expression), it has
// no program name, block delete, statement or assignment, and it runs while
// no fixed cycle and no MODIN is known to be modal (`plain_move_state`), and
// no G0..G3 is registered as a macro code (`plain_moves_possible`). On such a
// block resolve_call finds nothing, and apply_block only sets the motion mode,
// the feed and the positions: `apply_plain_move` does just that, and the batch
// path calls only the rules that look at such blocks (Rule::sees_plain_moves).
bool is_plain_move_block(const Block& block);
inline bool plain_move_state(const ModalState& s) {
    return s.cycle.known && !s.cycle.value && s.modin.known && !s.modin.value;
}
bool plain_moves_possible(const Catalog& catalog);
// apply_block(block, nullptr, catalog, state) for a plain move in a plain-move state.
void apply_plain_move(const Block& block, ModalState& state);
// Resolves the macro or subprogram a block invokes, with evaluated arguments.
std::optional<MacroCall> resolve_call(const Block& block, const ModalState& before, const Catalog& catalog);

// The value of a word in `state`: its literal, or its expression when it can be evaluated.
std::optional<double> word_value(const Block& block, const Word& word, const ModalState& state);
// Integer code of a G/M word when it is a plain literal (G00 -> 0, M52 -> 52).
std::optional<int> code_of(const Word& word);

// Reads the program names a file defines without parsing it fully.
void collect_program_names(std::string_view text, ProgramNames& out);

// A finding of `rule` as every analysis makes it: severity from the
// configuration, its range, the first 1000 bytes of its line (no fingerprint).
Diagnostic make_diagnostic(const RuleMeta& rule, const Config& config, std::string message, const SourceRange& range,
                           std::string_view line_text);
// The text that identifies a finding's block in its fingerprint, whatever its
// line: the line with blanks folded and comments (`comments`, absolute
// offsets) left out, so that neither a shifted line nor a comment added to the
// block changes it. A comment-only line keeps its comments.
std::string fingerprint_text(std::string_view line, uint32_t line_start, const std::vector<Comment>* comments);
// Fingerprint of a finding: rule + program + normalised block text + occurrence.
std::string make_fingerprint(std::string_view rule, std::string_view program, std::string_view block_text,
                             int occurrence);

}  // namespace osplint
