// The walk of the analysis engine (engine.h), shared by its parts:
// engine.cpp walks programs, loops and blocks; findings.cpp makes the
// findings, folds and suppresses them and hands them on;
// checkpoints.cpp takes the walk's checkpoints, moves them to an edited text
// (with moves.h) and resumes the walk at one (also inside a loop);
// converge.cpp ends the walk early after an edit inside one line, where its
// state is the previous analysis's again. Internal to the engine.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/engine.h"
#include "engine/fingerprint.h"
#include "engine/fold.h"
#include "engine/flow.h"
#include "engine/offset_filter.h"
#include "engine/positions.h"
#include "engine/summaries.h"
#include "engine/suppress.h"
#include "semantics/eval.h"
#include "semantics/motion.h"
#include "semantics/transfer.h"
#include "syntax/frontend_fast.h"
#include "syntax/outline.h"

namespace osplint {

// A state that may be absent (no path reaches the block).
struct MaybeState {
    bool reachable = false;
    ModalState state;
    // Merges `o` in; returns whether this changed.
    bool merge(const ModalState& o) {
        if (!reachable) {
            state = o;
            reachable = true;
            return true;
        }
        ModalState before = state;
        state.merge(o);
        return !(state == before);
    }
    bool merge(const MaybeState& o) { return o.reachable ? merge(o.state) : false; }
    // Merges in `o` flowing along the jump of the block at `line`.
    bool merge_jump(const ModalState& o, uint32_t line, ByteRange range) {
        if (!reachable) {
            state = o;
            state.jumped(line, range);
            reachable = true;
            return true;
        }
        ModalState before = state;
        state.merge_jump(o, line, range);
        return !(state == before);
    }
};

// The states loop edges left for blocks further on, by the offset of the
// block they flow into: the walk asks for every block it enters, and the
// filter answers most of those without searching the map.
class OffsetStates {
public:
    using Map = std::map<uint32_t, MaybeState>;
    OffsetStates& operator=(const Map& m) {
        map_ = m;
        filter_.clear();
        for (const auto& [offset, state] : map_) filter_.add(offset);
        return *this;
    }
    const Map& map() const { return map_; }
    MaybeState& operator[](uint32_t offset) {
        filter_.add(offset);
        return map_[offset];
    }
    const MaybeState* find(uint32_t offset) const {
        if (map_.empty() || !filter_.may_hold(offset)) return nullptr;
        auto it = map_.find(offset);
        return it == map_.end() ? nullptr : &it->second;
    }
    // The first offset at or after `offset` that holds a state (UINT32_MAX: none).
    uint32_t next_at(uint32_t offset) const {
        auto it = map_.lower_bound(offset);
        return it == map_.end() ? UINT32_MAX : it->first;
    }
    void clear() {
        map_.clear();
        filter_.clear();
    }

private:
    Map map_;
    OffsetFilter filter_;
};

// A line of a loop held in memory while the loop is iterated.
struct HeldLine {
    Block block;
    uint32_t line = 0;
    uint32_t start = 0;
    uint32_t text_size = 0;
    uint32_t terminator_size = 0;
};

// The lines of a loop held in memory by its first sweep, while they are few
// enough (EngineOptions::held_loop_blocks): its other sweeps cost no parsing.
struct HeldLoop {
    std::vector<HeldLine> lines;
    std::string text;  // the lines' text and terminators, one after the other
    bool holding = false;

    void hold(const Block& b, const LineRef& l, size_t max_blocks) {
        if (!holding) return;
        if (lines.size() >= max_blocks) return drop();
        lines.push_back({b, l.line, l.start, static_cast<uint32_t>(l.text.size()),
                         static_cast<uint32_t>(l.terminator.size())});
        text.append(l.text);
        text.append(l.terminator);
    }
    void drop() {
        holding = false;
        lines.clear();
        text.clear();
    }
};

// When a sweep last entered a join, and when what flows into it last changed.
struct JoinStamps {
    uint64_t entered = 0;
    uint64_t changed = 0;
    friend bool operator==(const JoinStamps&, const JoinStamps&) = default;
};

// What the first sweep over a loop holds before one of its blocks, or when it ends.
struct SweepState {
    MaybeState flowing;
    std::map<uint32_t, MaybeState> join;
    std::unordered_map<std::string, MaybeState> pending_name;
    std::map<uint32_t, MaybeState> pending_offset;
    std::unordered_map<std::string, std::vector<uint32_t>> defs;
    MaybeState final_state;
    std::map<uint32_t, MaybeState> probes;
    std::map<uint32_t, JoinStamps> join_stamps;
    uint64_t stamp = 0;
    uint32_t extent = 0;
    uint32_t index = 0;  // of the block in the loop
    bool loop_changed = false;
    // The block the walk read next (after the loop, when the sweep ended);
    // kChanged in a state moved through an edit that changed that line.
    uint32_t next = 0;
    static constexpr uint32_t kChanged = UINT32_MAX;
    uint32_t next_line = 0;
};



// The summaries of the file's own programs an analysis used, by name
// (WalkCheckpoint::summaries); `complete` once the analysis ended.
struct LocalSummaries {
    std::vector<std::pair<std::string, const SubprogramSummary*>> used;
    bool complete = false;
};

// What a checkpoint holds that no later edit changes.
struct FrozenWalk {
    const Config* config = nullptr;
    std::vector<std::string> only_rules;
    bool run_rules = true;
    size_t program = 0;
    uint32_t offset = 0;
    uint32_t line = 0;
    uint64_t diagnostics = 0;
    uint64_t suppressed = 0;
    // The furthest byte a finding delivered so far points at (its notes, its
    // fixes, the directive that silenced it): an edit before it would leave
    // the findings the caller keeps pointing at text that moved.
    uint32_t reach = 0;
    // The summaries of the file's own programs that the walk used so far (by
    // name; nullptr: none could be made): an edit that changes what one of
    // them leaves behind changes the states after its CALLs.
    std::vector<std::pair<std::string, const SubprogramSummary*>> local_used;
    bool seen_main = false;
    bool subprogram = false;
    Program program_info;
    MaybeState flowing;
    std::unordered_map<std::string, MaybeState> pending_name;
    std::unordered_map<std::string, std::vector<uint32_t>> defs;
    MaybeState final_state;
    std::vector<std::unique_ptr<Rule>> rules;
    std::vector<bool> used;
    Positions::Marks marks;
    std::optional<Folder> folder;
    std::optional<OccurrenceCounter> occurrences;
};

// A checkpoint inside a loop read again from the input whose walk with the
// rules followed its first sweep: the loop, the first sweep before the block,
// what that sweep left (the states the walk with the rules started from), the
// joins as that walk reached the block, and what it had brought to the states
// further on. An edit after the block is analysed from there when the first
// sweep, carried on from the block over the new text, leaves the same states
// as before wherever the walk up to the block read them (Walk::resume_loop).
struct LoopCheckpoint {
    uint32_t head = 0;
    uint32_t head_line = 0;
    MaybeState entry;
    std::shared_ptr<const SweepState> first;
    std::shared_ptr<const SweepState> after_first;
    std::map<uint32_t, MaybeState> join;
    // What that walk brought, before the block, to the sequence names jumped
    // to, to the blocks loop edges reach, and to the end of the program.
    std::unordered_map<std::string, MaybeState> brought_name;
    std::map<uint32_t, MaybeState> brought_offset;
    MaybeState brought_final;
};

struct WalkCheckpoint {
    std::shared_ptr<const FileOutline> outline;  // of the text it is valid for
    // States left by loop edges for blocks further on, by their offset in that text.
    std::map<uint32_t, MaybeState> pending_offset;
    std::shared_ptr<const FrozenWalk> frozen;
    std::shared_ptr<const LoopCheckpoint> loop;  // set inside a loop
    // The edits made since `loop` was taken (the size of the text before
    // each, and the change): its offsets are moved to the text now only when
    // the walk resumes there.
    std::vector<std::pair<uint64_t, TextChange>> loop_moves;
    // False once an edit after the block was made (the states `loop` holds
    // from the first sweep on, and those `frozen` holds that came from them,
    // are then of the text before it): the walk resumes there, reading those
    // states only where they are the new text's, but never ends there.
    bool loop_exact = true;
    // When one edit after the block was made since it was exact: `loop` as it
    // was then (Walk::renew_kept).
    std::shared_ptr<const LoopCheckpoint> exact_before;
    // The summaries of the file's own programs that the findings of the
    // analysis it belongs to rest on, by name (filled when that analysis
    // ends): a later analysis that ends early here keeps those findings only
    // when each summary leaves the same behind in its text.
    std::shared_ptr<LocalSummaries> summaries;
};


// The furthest byte a finding points at (its range, notes and fixes).
inline uint32_t reach_of(const Diagnostic& d) {
    uint32_t r = d.range.bytes.end;
    for (const Note& n : d.notes)
        if (n.range) r = std::max(r, n.range->bytes.end);
    for (const Fix& f : d.fixes)
        for (const TextEdit& e : f.edits) r = std::max(r, e.range.bytes.end);
    return r;
}


class Walk final : public RuleContext {
public:
    Walk(const std::string& path, ByteSource& src, const Config& config, const EngineOptions& options,
         DiagnosticSink& sink, EngineStats& stats)
        : path_(path), src_(src), config_(config), options_(options), sink_(sink), stats_(stats),
          main_(src, options.chunk_size), positions_(src) {}

    std::string run();

    // --- RuleContext
    const Config& config() const override { return config_; }
    const Catalog& catalog() const override { return config_.catalog; }
    std::string_view path() const override { return path_; }
    std::string_view text(ByteRange r) const override;
    bool has_label(std::string_view name) const override;
    bool is_jump_target(std::string_view name) const override { return flow_.is_referenced(name); }
    bool has_program(std::string_view name) const override;
    std::optional<double> eval(const Block& block, ExprId e, const ModalState& state) const override {
        return evaluate(block, e, state);
    }
    SourceRange resolve(ByteRange r) const override { return positions_.range(r); }
    Diagnostic& report(const RuleMeta& rule, ByteRange range, std::string message) override;
    bool folded(const RuleMeta& rule, std::string_view key, ByteRange range) override;

private:
    enum class Mode { Iterate, Rules };

    // --- reading
    // With `moves`, a plain move may be read in part (FastLineParser::parse_moves):
    // enough for a sweep without the rules, and for the rules that look at
    // plain moves (their address, range, number and sequence name); visit
    // parses it whole (`read_whole`) when it needs more.
    bool read(Block& b, LineRef& line, bool moves = false);
    // read in two steps: the next line, then its block.
    bool fetch(LineRef& line);
    void parse(Block& b, const LineRef& line, bool moves);
    // In a sweep without the rules: a plain move applied from its values
    // alone, without a block; false for any other line (it is then parsed).
    bool skim(const LineRef& line);
    // `names`: whether the move may have a sequence name (one no jump or N word names).
    bool apply_plain_values(const LineRef& line, bool names);
    // In the walk with the rules, while rules_take_values(): a plain move
    // checked from its values alone (Rule::check_plain_move); false for any
    // other line (it is then parsed).
    bool rules_take_values() const;
    bool skim_checked(const LineRef& line);
    enum class Next { Block, Checked, End };
    // `move` false: the line is no plain move (may_be_move), not tried as one.
    Next read_for_rules(Block& b, LineRef& line, bool move);
    // Whether the next line may be a plain move: false when it starts (after
    // blanks) with C or M, as a CALL, MODIN or M-code line does; a posted
    // program's call lines then skip the plain-move shortcuts, which would
    // each fail on them (a cost of time only).
    bool may_be_move() const;
    bool may_repeat() const;
    uint32_t skim_run(uint32_t max_lines, uint64_t start_limit,
                      FastLineParser::IntDigits int_digits = {FastLineParser::kAnyDigits, FastLineParser::kAnyDigits,
                                                              FastLineParser::kAnyDigits});
    // The most lines skim_run may read in a sweep from its `index`-th block:
    // up to the next probe (converged() looks at that block).
    static uint32_t probe_gap(uint32_t index) {
        return index % kProbeBlocks == 0 ? 0 : kProbeBlocks - index % kProbeBlocks;
    }
    static constexpr uint32_t kRunLines = 1u << 16;  // ... in the walk with the rules
    bool rules_idle() const;
    // Whether the walk with the rules may apply a run of plain moves at once:
    // every rule that wants plain moves gives bounds (Rule::quiet_below);
    // `digits` is what the run's axis words may then have before their points.
    bool rules_quiet(FastLineParser::IntDigits& digits) const;
    // skim_run in the walk with the rules while rules_quiet. A run that
    // stopped at once before a move that may pass a bound (every move of a
    // program past the travel) is not tried again for the next 1, 3, 7 ...
    // 63 lines (a cost of time only: those lines are checked one by one).
    // `move` false: the next line is no plain move (may_be_move).
    uint32_t quiet_run(uint32_t max_lines, uint64_t start_limit, bool move);
    uint32_t quiet_wait_ = 0, quiet_backoff_ = 0;
    bool run_over_ = false;  // the last skim_run stopped before a move past its digits
    // plain_rules_, plain_named_, plain_digits_, named_values_ and call_rules_ from rules_.
    void index_plain_rules();
    // Whether skim_run may read past lines: not for the language server's
    // checkpoints (taken at blocks: mark_loop) or an analysis that may end early.
    bool runs_ok_ = false;
    // The block `b` read last, parsed whole if it was read in part.
    void read_whole(const Block& b, const LineRef& line);
    // Whether a walk with the rules may read plain moves in part: not for an
    // observer (trace, hover), which sees every field of every block.
    bool moves_with_rules() const { return plain_ok_ && !options_.observer; }
    // Whether the next block, if a plain move, may be applied as one: not in
    // a state where a plain move is more (in a fixed cycle, under MODIN), where
    // a block read in part would be read again whole. (The paths that join at
    // the block may still change this: visit reads it whole then.)
    bool plain_may_apply() const { return reachable_ && plain_move_state(*A_); }
    void fail(std::string message);

    // --- the walk
    void make_outline();
    size_t walk_resumed();
    void walk_program(size_t index);
    void walk_blocks();
    void end_program_walk();
    bool resume_from_checkpoints();
    void restore(const WalkCheckpoint& c);
    std::shared_ptr<FrozenWalk> freeze();
    void take_checkpoint();
    // --- checkpoints inside a loop (LoopCheckpoint)
    SweepState sweep_state(uint32_t extent, uint32_t index) const;
    void restore_sweep(const SweepState& s);
    void mark_loop(uint32_t extent, uint32_t index);
    void take_loop_checkpoint();
    bool resume_loop();
    bool fall_back_before(uint32_t head);
    void reset_to_start();
    void end_loop();
    // Returns true when it ended early, as the previous analysis's did (sweep_converges).
    bool first_sweep(uint32_t index, uint32_t& extent, HeldLoop* held);
    bool loop_head(const Block& b, uint32_t offset, uint32_t& extent) const;
    void walk_loop(const Block& head, const LineRef& head_line);
    // A sweep returns false when it stopped early (it converged, or the walk stops).
    bool sweep_held(std::vector<HeldLine>& held, const std::string& text, Mode mode);
    bool sweep_file(uint32_t start, uint32_t start_line, uint64_t end, Mode mode);
    void visit(const Block& b, const LineRef& line, Mode mode);
    // resolve_call, with the summary of a user subprogram the CALL reaches.
    // The macro the block runs (nullptr: none), in call_, valid until the next block.
    const MacroCall* resolve(const Block& b, const ModalState& before) const;
    void enter(const Block& b, uint32_t offset);
    void leave(const Block& b, const LineRef& line);
    // The state after the block at `offset` (its jump: `line`, `range`) flows to a sequence name or an offset.
    void contribute_name(std::string_view name, uint32_t offset, uint32_t line, ByteRange range);
    void contribute_offset(uint32_t target, uint32_t offset, uint32_t line, ByteRange range);
    void join_reached(uint32_t target, uint32_t offset, uint32_t line, ByteRange range);
    void set_state(const MaybeState& s);
    // A plain move: the state it starts from in B (from A), then B flows on.
    ModalState& plain_after();
    void plain_done(const LineRef& line);

    // --- findings
    std::string fingerprint_for(std::string_view rule, uint32_t line);
    const std::vector<Comment>* comments_of(const LineData& ld);
    void flush();

    const std::string& path_;
    ByteSource& src_;
    const Config& config_;
    const EngineOptions& options_;
    DiagnosticSink& sink_;
    EngineStats& stats_;

    FileOutline outline_;
    std::vector<std::unique_ptr<Rule>> rules_;
    std::vector<Rule*> plain_rules_;  // the rules that look at plain moves
    // rules_ by what a block has (Rule::BlockNeed bits): those that may do
    // something on it, listed the first time a block has that (rules_for).
    std::array<std::vector<Rule*>, 256> rules_for_;
    std::array<bool, 256> rules_for_listed_{};
    const std::vector<Rule*>& rules_for(uint8_t has);
    std::vector<Rule*> call_rules_;   // the rules that look at plain calls (Rule::sees_plain_calls)
    // Of those, the ones that look at a plain call of a macro made so
    // (Rule::sees_plain_calls_of), by macro and kind, and the last asked for.
    std::map<std::pair<const MacroSpec*, CallKind>, std::vector<Rule*>> call_rules_of_;
    const std::vector<Rule*>* last_call_rules_ = nullptr;
    std::pair<const MacroSpec*, CallKind> last_call_of_{nullptr, CallKind::None};
    const std::vector<Rule*>& call_rules_of(const MacroCall& call);
    // A block that repeats the one the rules saw just before it, moved in
    // the plane (Rule::quiet_on_repeat): the rules that still see it.
    struct Repeat {
        bool armed = false;       // the last block the rules saw can be repeated
        uint64_t transfers = 0;   // stats_.transfers and flow_epoch_ then: no block and no
        uint64_t epoch = 0;       // other state came between it and the next one
        const MacroSpec* spec = nullptr;
        CallKind kind = CallKind::None;
        std::string text;         // its line without the values of its plane's position words
        std::array<uint32_t, 2> cuts{};  // where those values were cut out of `text`
        uint8_t count = 0;               // how many were
        const std::vector<Rule*>* rules = nullptr;  // the rules that are not quiet on a repeat of it
        // A block no rule sees on a repeat, whose repeat leaves the state as
        // it is (a plain call, a hole, a positioning block), in a batch walk
        // outside loops: a repeat of it may be applied from its text (repeat_line).
        bool from_text = false;
        // Such a repeat sets the position in the plane to its values
        // (repeat_sets_plane): the axis of each cut, in `axes`.
        bool sets_plane = false;
        std::array<char, 2> axes{};
        // Some rules tell from a repeat's values whether they are quiet
        // (Rule::repeat_values_decide): the values for which all are.
        bool by_values = false;
        std::array<Rule::QuietRange, 2> quiet{};
        bool quiet_at(const std::array<double, 2>& values) const {
            for (uint8_t i = 0; i < count; ++i)
                if (!(values[i] >= quiet[i].lo && values[i] <= quiet[i].hi)) return false;
            return true;
        }
    };
    // Where the values of the plane's position words are on a block that may
    // be repeated (offsets in its line): at most two.
    struct RepeatSpans {
        std::array<ByteRange, 2> at{};
        std::array<char, 2> axis{};  // the plane axis each value positions
        uint8_t count = 0;
    };
    bool repeatable(const Block& b, const MacroCall* call, const ModalState& before, const LineRef& line,
                    RepeatSpans& spans) const;
    // No: the block cannot repeat one nor be repeated; May: it may be
    // repeated; Yes: it repeats the block before but for the state after it.
    enum class Repeated : uint8_t { No, May, Yes };
    Repeated repeated(const Block& b, const MacroCall* call, const ModalState& before, const LineRef& line,
                      RepeatSpans& spans) const;
    bool same_apart_from_plane(const BlockView& view) const;
    // A line that repeats the block before it (Repeat::from_text), told from
    // its text and applied without a block: the state stays as that block
    // left it and no rule sees it. False for any other line (it is then parsed).
    bool repeat_line(const LineRef& line);
    // Whether `text` is repeat_.text with a plain number at each cut; those
    // numbers in `values`, when set.
    bool repeats_text(std::string_view text, std::array<double, 2>* values) const;
    // How many bytes from the start of `text` are repeat_.text with a plain
    // number at each cut (kNoRepeat: it does not start so); `text` may go on
    // past them.
    size_t repeat_length(std::string_view text, std::array<double, 2>* values) const;
    static constexpr size_t kNoRepeat = ~size_t(0);
    uint32_t repeat_run(uint32_t max_lines);
    const std::vector<Rule*>& repeat_rules_of(const MacroSpec* spec, CallKind kind, bool plain_call);
    Repeat repeat_;
    std::map<std::tuple<const MacroSpec*, CallKind, bool>, std::vector<Rule*>> repeat_rules_of_;
    uint64_t flow_epoch_ = 0;  // counts the states set other than by a block (set_state, joins)
    uint64_t reports_ = 0;     // counts report and folded
    // The rules on a block (a plain move, or not: then `repeated` and `spans`
    // are what Walk::repeated said of it).
    void check(const BlockView& view, const LineRef& line, bool plain, Repeated repeated, const RepeatSpans& spans);
    void check(const BlockView& view, const LineRef& line, bool plain) {
        check(view, line, plain, Repeated::No, RepeatSpans{});
    }
    std::vector<char> plain_named_;   // of each, whether it is RuleBlocks::Named
    bool named_values_ = true;        // every RuleBlocks::Named rule takes plain values
    // Of each of them, its quiet_below as digits before the point (nullopt: none).
    std::vector<std::optional<FastLineParser::IntDigits>> plain_digits_;
    bool plain_ok_ = true;            // plain_moves_possible with this catalog
    std::optional<SuppressionFilter> filter_;
    ProgramNames names_;              // this file's program names
    // The summaries of the subprograms (of this file or beside it) its CALLs reached, by name.
    mutable std::map<std::string, const SubprogramSummary*, std::less<>> summary_of_;
    mutable ArgLinks arg_links_;  // the last call's argument links (link_arg_specs)
    mutable MacroCall call_;      // the block's call (resolve), its storage kept from block to block
    // The block call_ was resolved from, and parser_.fills() then: a CALL line
    // the parser updated that block to since (and nothing else) keeps call_
    // but for its values (resolve_call_again).
    mutable const Block* resolved_block_ = nullptr;
    mutable uint64_t resolved_fills_ = 0;
    MacroEndMemo macro_ends_;     // the last macro call's end point (apply_block; a cache, not state)
    CallTransferMemo call_transfers_;  // the last plain call apply_block applied (a cache, not state)
    const SubprogramSummary* local_summary(const std::string& name) const;  // of a program of this file
    mutable std::vector<std::pair<std::string, const SubprogramSummary*>> local_used_;  // FrozenWalk::local_used
    bool fingerprints_ = false;
    OccurrenceCounter occurrences_;

    LineStream main_;
    FastLineParser parser_;
    PlainMove plain_move_;  // the line skim read last
    mutable Positions positions_;
    mutable std::string scratch_text_;
    std::string error_;
    bool stop_ = false;
    uint64_t walked_ = 0;

    // --- checkpoints
    std::shared_ptr<const FileOutline> shared_outline_;
    uint64_t next_checkpoint_ = 0;
    std::vector<bool> initial_used_;  // the suppression directives' use before the walk
    // Inside a loop: where its first sweep took its states (one every
    // checkpoint_every bytes), the next of them the walk with the rules
    // reaches, the checkpoints that walk made (kept when it stands), what
    // the first sweep left, and the loop's entry.
    struct LoopMark {
        uint32_t offset = 0;
        std::shared_ptr<const SweepState> first;
        size_t cost = 0;  // the states it holds
    };
    std::vector<LoopMark> loop_marks_;
    size_t loop_mark_next_ = 0;
    uint64_t next_loop_mark_ = 0;
    // The marks of a loop hold at most about this many states (each of its
    // checkpoints as many again), and those of all the loops of an analysis
    // together kLoopStates: past it, every other mark is dropped and the
    // marks are taken twice as far apart.
    static constexpr size_t kLoopMarkBudget = 16384;
    static constexpr size_t kLoopStates = 32768;
    size_t loop_states_left_ = kLoopStates;
    static constexpr size_t kMaxLoopMoves = 64;  // edits a checkpoint inside a loop is moved through
    size_t loop_mark_cost_ = 0;
    uint64_t loop_mark_spacing_ = 0;
    void start_loop_marks(uint64_t from) {
        loop_marks_.clear();
        loop_mark_cost_ = 0;
        loop_mark_spacing_ = options_.checkpoint_every;
        next_loop_mark_ = from + loop_mark_spacing_;
    }
    std::vector<Checkpoint> loop_checkpoints_;
    std::shared_ptr<const SweepState> after_first_;
    MaybeState loop_entry_;
    uint32_t loop_head_line_ = 0;
    Checkpoint resume_in_loop_;  // the checkpoint inside a loop the walk resumes at
    // While the walk with the rules after a first sweep may take checkpoints:
    // what it brings to the states further on (LoopCheckpoint::brought_*).
    bool bringing_ = false;
    std::unordered_map<std::string, MaybeState> brought_name_;
    std::map<uint32_t, MaybeState> brought_offset_;
    MaybeState brought_final_;
    void bring_final(const ModalState& s) {
        final_state_.merge(s);
        if (bringing_) brought_final_.merge(s);
    }
    // --- ending early after an edit inside one line (EngineOptions::converged)
    std::optional<LineEditMove> edit_move_;
    // The previous analysis's checkpoints after the edit (at the top level and
    // inside loops), where they are in this text, and those inside loops
    // moved to this text (made when first asked for: ahead_loop).
    std::vector<Checkpoint> ahead_;
    std::vector<uint32_t> ahead_at_;
    std::vector<std::optional<std::shared_ptr<const LoopCheckpoint>>> ahead_loops_;
    std::map<const SweepState*, std::shared_ptr<const SweepState>> moved_sweeps_;  // shared by them
    std::shared_ptr<const LoopCheckpoint> ahead_loop(size_t i);
    size_t ahead_next_ = 0;       // the next one at the top level
    size_t ahead_in_loop_ = 0;    // the next one in the sweep over a loop
    static constexpr size_t kNone = ~size_t(0);
    void start_ahead_in_loop();
    size_t ahead_in_loop();       // the one inside the loop at the next block (kNone: none)
    bool sweep_converges(size_t i, uint32_t& extent, uint32_t index);
    bool sweep_is(const SweepState& s, uint32_t extent, uint32_t index) const;
    bool try_converge_in_loop(size_t i);
    bool may_converge_ = false;  // after an edit inside one line, with checkpoints that may be kept
    void renew_kept(const WalkCheckpoint& c, const SweepState& now);
    std::shared_ptr<FrozenWalk> freeze_in_loop();
    Checkpoint moved_ahead(size_t i, const FrozenWalk& f, const FrozenWalk& at);
    std::shared_ptr<LocalSummaries> walk_summaries_;  // WalkCheckpoint::summaries of this analysis
    bool converged_ = false;
    void find_ahead(const std::vector<Checkpoint>& old);
    bool same_as_moved(const WalkCheckpoint& old) const;
    // A checkpoint after `f` (where the walk ended, there `at` now), moved.
    std::shared_ptr<FrozenWalk> moved_frozen(const FrozenWalk& f2, const FrozenWalk& f, const FrozenWalk& at) const;
    // Ends the walk at ahead_[i] (`here`: the walk there, moved ahead_[i]).
    void converge_at(size_t i, const std::shared_ptr<const FrozenWalk>& at, Checkpoint here);
    void converge_if_due() {
        if (ahead_next_ < ahead_.size() && main_.next_offset() >= ahead_at_[ahead_next_]) try_converge();
    }
    void try_converge();
    void finish_summaries();
    uint64_t delivered_diagnostics_ = 0;
    uint64_t delivered_suppressed_ = 0;
    uint32_t delivered_reach_ = 0;
    void extend_reach(const Diagnostic& d);

    // --- the current program
    size_t program_index_ = 0;
    bool subprogram_ = false;
    ProgramFlow flow_;
    Program program_;
    bool library_ = false;
    bool seen_main_ = false;
    bool tracks_labels_ = false;  // the program references sequence names
    std::unordered_map<std::string, MaybeState> pending_name_;  // states left by jumps, by target name
    OffsetStates pending_offset_;                               // states left by loop edges, by target block
    std::unordered_map<std::string, std::vector<uint32_t>> defs_;  // referenced names -> blocks defining them
    MaybeState final_state_;

    // The state flowing into the next block: *A when reachable_.
    ModalState states_[2];
    ModalState* A_ = &states_[0];
    ModalState* B_ = &states_[1];
    bool reachable_ = false;
    bool near_ = false;  // A and B differ at most in the fields a plain move sets
    const ModalState unknown_{};

    // --- the loop being iterated
    bool in_loop_ = false;
    uint32_t loop_start_ = 0;
    bool loop_changed_ = false;
    std::map<uint32_t, MaybeState> join_;  // accumulated states at the joins inside the loop
    // A sweep that reaches a probe with the state the previous sweep had
    // there, while no join from there on changed since the previous sweep
    // entered it, would repeat the rest of that sweep: it stops there.
    static constexpr uint32_t kProbeBlocks = 2048;
    static constexpr uint64_t kHeldBytesPerBlock = 64;  // a generous line length, to guess a loop's blocks from its bytes
    std::map<uint32_t, MaybeState> probes_;  // the state flowing into a probe block, in the last sweep that passed it
    std::map<uint32_t, JoinStamps> join_stamps_;
    uint64_t stamp_ = 0;
    bool converged(uint32_t offset, uint32_t index, bool check);

    // A loop too long to hold is walked with the rules as soon as one sweep
    // has brought the states where paths join back into it: if that walk
    // changes none of them, its findings stand; if it does, they are dropped,
    // the rules are put back as they were, and the sweeps go on.
    struct Speculation {
        std::vector<std::unique_ptr<Rule>> rules;
        Folder folder{0};
        std::vector<bool> used;
        OccurrenceCounter occurrences;
    };
    static constexpr size_t kMaxSpeculativeFindings = 20000;
    bool speculating_ = false;
    bool speculation_overflow_ = false;
    std::vector<std::pair<std::optional<Diagnostic>, std::optional<SuppressedDiagnostic>>> speculative_;
    bool walk_speculatively(uint32_t start, uint32_t start_line, uint64_t end, const MaybeState& entry);
    void begin_speculation();
    bool end_speculation();
    void deliver(Diagnostic&& d);
    void deliver(SuppressedDiagnostic&& s);
    void mark_changed(uint32_t offset) {
        if (in_loop_) join_stamps_[offset].changed = ++stamp_;
    }

    // --- findings of the block (or program) in hand
    const Block* block_ = nullptr;
    const std::vector<HeldLine>* held_ = nullptr;
    std::vector<Diagnostic> findings_;
    std::vector<std::optional<Folder::Verdict>> verdicts_;  // per finding: decided when `folded` was asked
    std::optional<Folder::Verdict> pending_verdict_;        // from `folded`, for the next report
    uint64_t pending_kind_ = 0;
    // The kind of the last key `folded` was asked about: a rule that reports
    // on every move asks with the same key again and again.
    struct LastKey {
        std::string_view rule;
        std::array<char, 24> key{};
        size_t size = SIZE_MAX;  // none yet
        uint64_t kind = 0;
    } last_key_;
    Folder folder_{0};
    Block block_buf_;           // the block read last by the walk
    Block* partial_ = nullptr;  // the block read last, when read in part (read with `moves`)
    Block comment_block_;       // a line parsed again for its comments
    // The fingerprint text of the last line a finding was on: a line with many
    // findings is read and folded once.
    uint32_t fingerprint_line_ = 0;
    std::string fingerprint_program_;
    std::string fingerprint_text_;
    std::map<std::string, uint64_t, std::less<>> fingerprint_keys_;  // by rule
    FastLineParser comment_parser_;
};

}  // namespace osplint
