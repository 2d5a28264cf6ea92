// The analysis engine: one input in, findings out, in a stream.
//
// Every entry point runs this: `osplint check` on files and standard input,
// the language server on open documents, `osplint trace`, the library.
//
//   1. The outline (syntax/outline.h): one fast pass over the input finds the
//      programs, the blocks that jump or loop, the sequence names jumped to
//      and the suppression directives.
//   2. The walk: program by program, block by block, each line parsed once
//      (syntax/frontend_fast.h), the modal state carried from block to block
//      (semantics/transfer.h), every enabled rule shown every block with the
//      state before and after it. Where paths join (a sequence name jumped
//      to, a loop head), the state is the merge of every state that reaches
//      it. A jump forward leaves its state at the name it targets; a jump
//      back (or a DO/WHILE ... END loop) makes its target the head of a loop
//      of the flow graph: the walk iterates the blocks from the head to the
//      last jump back, without the rules, until the states where paths join
//      no longer change, then walks them once more with the rules. A loop of
//      up to `held_loop_blocks` blocks is held in memory while it is
//      iterated; a longer one is read again from the input.
//   3. Findings are made as rules report them, checked against the file's
//      suppression directives, folded when there are many of one kind
//      (engine/fold.h), and handed to a DiagnosticSink: those of a block after
//      the block, those about a whole program after the program, the folded
//      ones and those about the directives at the end of the file.
//
// What the walk keeps: the current line and block, two modal states, the
// merged states at the blocks where paths join, the sequence names jumped to
// with the blocks that define them, a checkpoint every 1024 lines, the rules'
// own state. Nothing grows with the size of the input or with the number of
// findings (fingerprints, when a sink asks for them, keep 8 bytes per distinct
// finding).
#pragma once

#include <atomic>
#include <memory>
#include <optional>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "engine/rule.h"
#include "engine/workspace.h"
#include "osplint/diagnostic.h"
#include "semantics/calls.h"
#include "semantics/config.h"
#include "support/io.h"
#include "syntax/outline.h"

namespace osplint {

// Sees every block the rules see, in the same order (trace, the language
// server's hover and inlay hints, tests).
class BlockObserver {
public:
    virtual ~BlockObserver() = default;
    // Return false to stop the walk after this block.
    virtual bool block(const BlockView& view, const LineRef& line) = 0;
    // Called when a program starts (before its first block).
    virtual void program(const Program& program, bool subprogram) {
        (void)program;
        (void)subprogram;
    }
    // Called when a program has been walked, with the state merged over every
    // path that ends it (nullptr: none does).
    virtual void program_end(const Program& program, const ModalState* final_state) {
        (void)program;
        (void)final_state;
    }
};

class SubprogramSummaries;

// A sink that keeps no finding: walks made for their states (trace, hover,
// inlay hints, subprogram summaries) and `check --diff`.
class DiscardFindings final : public DiagnosticSink {
public:
    void diagnostic(Diagnostic&&) override {}
};

// The walk's state before a block, kept so that a later analysis of an edited
// text can start there (the language server after an edit). Opaque: made and
// read by the engine only.
struct WalkCheckpoint;
using Checkpoint = std::shared_ptr<const WalkCheckpoint>;
// Where a checkpoint was taken, and how many findings (and suppressed
// findings) had been handed to the sink by then.
struct CheckpointPlace {
    uint32_t offset = 0;
    uint32_t line = 0;
    uint64_t diagnostics = 0;
    uint64_t suppressed = 0;
};
CheckpointPlace checkpoint_place(const WalkCheckpoint& c);
// Where an analysis after an edit ended early (EngineOptions::converged).
struct Convergence {
    CheckpointPlace at;            // in the new text, with the findings made before it
    uint64_t old_diagnostics = 0;  // the findings the previous analysis had made before it
    uint64_t old_suppressed = 0;
};

// What changed between the text a checkpoint was taken in and the text now:
// the bytes before `prefix` are the same, and so are the last `suffix` bytes
// of both (the part between was replaced; `lines` is how many lines the
// replacement added, or removed when negative).
struct TextChange {
    uint32_t prefix = 0;
    uint32_t suffix = 0;
    int64_t bytes = 0;  // new size - old size
    int64_t lines = 0;
    // The change lies inside one line, with a line break after it, that holds
    // no byte an outlined line must hold (syntax/outline.h), before the change
    // and after it; `line_start` is where that line starts. The outline of
    // the new text is then the old one moved (moved_outline).
    bool plain_line = false;
    uint32_t line_start = 0;
    // When the change lies inside one line that a break ends, in both texts
    // (no line break replaced or written): where the line after it starts in
    // the text before the change (line_start is set too). 0 otherwise.
    uint32_t next_line = 0;
};
// Offsets and ranges of the text before a change inside one line
// (TextChange::next_line), in the text after it: those before the changed
// line stay, those from the next line on move by the change's byte count. The
// changed line's own (its columns and its text changed) cannot be moved: the
// functions return false for them. Line numbers are the same in both texts.
struct LineEditMove {
    uint32_t line_start = 0;
    uint32_t next_line = 0;
    int64_t bytes = 0;
    // The start of a block (the changed line's start stays).
    bool block(uint32_t& offset) const {
        if (offset <= line_start) return true;
        if (offset < next_line) return false;
        offset = static_cast<uint32_t>(static_cast<int64_t>(offset) + bytes);
        return true;
    }
    bool range(ByteRange& r) const {
        if (r.begin == 0 && r.end == 0) return true;  // no range
        if (r.begin >= line_start && r.begin < next_line) return false;
        if (r.end > line_start && r.end < next_line) return false;
        if (r.begin >= next_line) r.begin = static_cast<uint32_t>(static_cast<int64_t>(r.begin) + bytes);
        if (r.end >= next_line) r.end = static_cast<uint32_t>(static_cast<int64_t>(r.end) + bytes);
        return true;
    }
};
// The move of a change inside one line; nullopt for any other change.
std::optional<LineEditMove> line_edit_move(const TextChange& e);
// A finding of the text before such a change, in the text after it (its
// range, its notes', its fixes' and its folded range): false when one of
// them is on the changed line.
bool move_diagnostic(Diagnostic& d, const LineEditMove& m);
// The change from `before` to `after` (never splitting a CR LF).
TextChange text_change(std::string_view before, std::string_view after);
// The outline of the text before `e` (`old`), moved to the text after it,
// when that is what outline_file would make of the new text: `e` changed a
// plain line (TextChange::plain_line) that is not one the outline parses
// whatever it holds (up to the file's first block, or from a suppression
// directive to the block it applies to). nullopt otherwise.
std::optional<FileOutline> moved_outline(const FileOutline& old, const TextChange& e);

struct EngineOptions {
    const RuleRegistry* rules = nullptr;           // required
    const ProgramNames* known_programs = nullptr;  // program names defined outside this input
    // Only run these rules (IDs); empty: every rule the configuration enables.
    std::vector<std::string> only_rules;
    size_t chunk_size = size_t(1) << 20;       // bytes read at a time
    size_t held_loop_blocks = 8192;            // a loop of this many blocks or fewer is held in memory
    BlockObserver* observer = nullptr;
    bool run_rules = true;            // false: only the walk and the observer (trace, hover)
    uint64_t fold = 0;                // findings of one kind shown per file before the others fold (0: off)
    FileOutline* outline = nullptr;   // receives the input's outline when set
    // Set from another thread to abandon the walk (the engine then reports
    // "cancelled" as its I/O error).
    const std::atomic<bool>* cancel = nullptr;
    // Checkpoints (the language server): one before the first block at or
    // after every `checkpoint_every` bytes (0: none), outside loops or inside
    // a loop read again from the input whose walk with the rules followed one
    // sweep. On input,
    // `checkpoints` holds those of the previous analysis of this document and
    // `edit` says how its text changed since; the walk then starts at the last
    // of them it can (the text before it and the structure it depends on
    // unchanged), hands the sink only the findings made from there on, and
    // sets `resumed_at` (the caller keeps the findings made before it). On
    // output, `checkpoints` holds the earlier ones still valid for the new
    // text and the new ones.
    uint64_t checkpoint_every = 0;
    std::vector<Checkpoint>* checkpoints = nullptr;
    TextChange edit;
    std::optional<CheckpointPlace>* resumed_at = nullptr;
    // When the edit lay inside one line, the walk ends early where its state
    // is again the one the previous analysis had at one of its checkpoints
    // (moved by the edit); it then sets `converged` (the caller keeps the
    // findings that analysis made from that checkpoint on, moved with
    // move_diagnostic, after the new ones). The checkpoints of that analysis
    // after it are moved to the new text and kept.
    std::optional<Convergence>* converged = nullptr;
    // What the user subprograms that CALLs reach leave behind
    // (engine/summaries.h); nullptr: each is taken to leave the modes as they were.
    SubprogramSummaries* summaries = nullptr;
    // The state each subprogram starts with, instead of "nothing known" (the
    // walks that make the summaries).
    const ModalState* subprogram_entry = nullptr;
};

// What the engine did (tests and benchmarks).
struct EngineStats {
    uint64_t bytes = 0;
    uint64_t lines = 0;                // lines of the input
    uint64_t outline_lines_parsed = 0; // lines the outline parsed
    uint64_t outlines_moved = 0;       // outlines of an edited text made by moving the old one
    uint64_t blocks_parsed = 0;        // blocks the walk parsed (counting loops read again)
    uint64_t fallback_lines = 0;       // ... of which by the tree-sitter front end
    uint64_t programs = 0;
    uint64_t loops = 0;                // loops of the flow graph iterated
    uint64_t loop_sweeps = 0;          // sweeps over them without the rules
    uint64_t held_loops = 0;           // loops held in memory
    uint64_t speculative_walks = 0;    // loops walked with the rules after one sweep, and found right
    uint64_t transfers = 0;            // blocks applied to a state
    uint64_t run_blocks = 0;           // ... of which plain moves applied a run at a time (Walk::skim_run)
    uint64_t value_blocks = 0;         // ... of which plain moves the rules checked without a block (Walk::skim_checked)
    uint64_t calls_again = 0;          // calls taken from the call before but for their values (resolve_call_again)
    uint64_t repeats = 0;              // blocks that repeated the one before, moved (Rule::quiet_on_repeat)
    uint64_t text_repeats = 0;         // ... of which told from their text alone (Walk::repeat_line)
    uint64_t modin_calls_kept = 0;     // positioning blocks of an open MODIN that kept the call before (resolve_call)
    uint64_t label_misses = 0;         // has_label asked for a name the walk did not keep (should stay 0)
    uint64_t loop_resumes = 0;         // analyses resumed at a checkpoint inside a loop
    uint64_t loop_resume_misses = 0;   // ... that found the loop's states changed and started before it
    uint64_t convergences = 0;         // analyses after an edit that ended early (EngineOptions::converged)
    uint64_t loop_convergences = 0;    // ... inside a loop
    uint64_t sweep_convergences = 0;   // first sweeps over a loop after an edit that ended early, as before it
    uint64_t checkpoints_renewed = 0;  // checkpoints inside a loop before an edit found the new text's
};

inline constexpr std::string_view kCancelled = "cancelled";


// Analyses `src` (reported under `path`) and hands the findings to `sink`:
// begin_file, the findings, end_file. Returns the I/O error ("" when the input
// was read to its end).
std::string run_engine(const std::string& path, ByteSource& src, const Config& config, const EngineOptions& options,
                       DiagnosticSink& sink, EngineStats* stats = nullptr);

}  // namespace osplint
