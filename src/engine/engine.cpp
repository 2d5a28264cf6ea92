// The walk of the analysis engine (see engine.h).
#include "engine/engine.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <unordered_map>
#include <utility>

#include "catalog/catalog.h"
#include "engine/fingerprint.h"
#include "engine/fold.h"
#include "engine/flow.h"
#include "engine/positions.h"
#include "engine/summaries.h"
#include "engine/suppress.h"
#include "semantics/eval.h"
#include "semantics/transfer.h"
#include "support/text.h"
#include "syntax/frontend_fast.h"
#include "syntax/outline.h"

namespace osplint {
namespace {

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

// A line of a loop held in memory while the loop is iterated.
struct HeldLine {
    Block block;
    uint32_t line = 0;
    uint32_t start = 0;
    uint32_t text_size = 0;
    uint32_t terminator_size = 0;
};

// When a sweep last entered a join, and when what flows into it last changed.
struct JoinStamps {
    uint64_t entered = 0;
    uint64_t changed = 0;
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
};

}  // namespace

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
};

namespace {

int64_t line_ends(std::string_view s) {
    int64_t n = 0;
    for (size_t i = 0; i < s.size(); ++i)
        if (s[i] == '\n' || (s[i] == '\r' && !(i + 1 < s.size() && s[i + 1] == '\n'))) ++n;
    return n;
}

}  // namespace

TextChange text_change(std::string_view before, std::string_view after) {
    const size_t shorter = std::min(before.size(), after.size());
    // Whole blocks compared first (memcmp), then the bytes of the block that differs.
    constexpr size_t kBlock = 4096;
    size_t prefix = 0;
    while (prefix + kBlock <= shorter && std::memcmp(before.data() + prefix, after.data() + prefix, kBlock) == 0)
        prefix += kBlock;
    while (prefix < shorter && before[prefix] == after[prefix]) ++prefix;
    if (prefix > 0 && before[prefix - 1] == '\r') --prefix;  // a CR whose LF may have changed
    size_t suffix = 0;
    while (suffix + kBlock <= shorter - prefix &&
           std::memcmp(before.data() + before.size() - suffix - kBlock, after.data() + after.size() - suffix - kBlock,
                       kBlock) == 0)
        suffix += kBlock;
    while (suffix < shorter - prefix && before[before.size() - 1 - suffix] == after[after.size() - 1 - suffix]) ++suffix;
    // Never an LF without the CR before it, nor the CR of the prefix.
    while (suffix > 0 && before[before.size() - suffix] == '\n' &&
           ((before.size() - suffix > prefix && before[before.size() - suffix - 1] == '\r') ||
            (after.size() - suffix > prefix && after[after.size() - suffix - 1] == '\r')))
        --suffix;
    TextChange c;
    c.prefix = static_cast<uint32_t>(prefix);
    c.suffix = static_cast<uint32_t>(suffix);
    c.bytes = static_cast<int64_t>(after.size()) - static_cast<int64_t>(before.size());
    c.lines = line_ends(after.substr(prefix, after.size() - suffix - prefix)) -
              line_ends(before.substr(prefix, before.size() - suffix - prefix));
    return c;
}

CheckpointPlace checkpoint_place(const WalkCheckpoint& c) {
    return {c.frozen->offset, c.frozen->line, c.frozen->diagnostics, c.frozen->suppressed};
}

namespace {

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
    bool read(Block& b, LineRef& line);
    void fail(std::string message);

    // --- the walk
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
    template <class Hold>
    void first_sweep(uint32_t index, uint32_t& extent, Hold&& hold);
    bool loop_head(const Block& b, uint32_t offset, uint32_t& extent) const;
    void walk_loop(const Block& head, const LineRef& head_line);
    // A sweep returns false when it stopped early (it converged, or the walk stops).
    bool sweep_held(std::vector<HeldLine>& held, const std::string& text, Mode mode);
    bool sweep_file(uint32_t start, uint32_t start_line, uint64_t end, Mode mode);
    void visit(const Block& b, const LineRef& line, Mode mode);
    // resolve_call, with the summary of a user subprogram the CALL reaches.
    std::optional<MacroCall> resolve(const Block& b, const ModalState& before) const;
    void enter(const Block& b, uint32_t offset);
    void leave(const Block& b, const LineRef& line);
    // The state after the block at `offset` (its jump: `line`, `range`) flows to a sequence name or an offset.
    void contribute_name(std::string_view name, uint32_t offset, uint32_t line, ByteRange range);
    void contribute_offset(uint32_t target, uint32_t offset, uint32_t line, ByteRange range);
    void join_reached(uint32_t target, uint32_t offset, uint32_t line, ByteRange range);
    void set_state(const MaybeState& s);
    void check(const BlockView& view, const LineRef& line, bool plain);

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
    bool plain_ok_ = true;            // plain_moves_possible with this catalog
    std::optional<SuppressionFilter> filter_;
    ProgramNames names_;              // this file's program names
    // The summaries of the subprograms (of this file or beside it) its CALLs reached, by name.
    mutable std::map<std::string, const SubprogramSummary*, std::less<>> summary_of_;
    const SubprogramSummary* local_summary(const std::string& name) const;  // of a program of this file
    mutable std::vector<std::pair<std::string, const SubprogramSummary*>> local_used_;  // FrozenWalk::local_used
    bool fingerprints_ = false;
    OccurrenceCounter occurrences_;

    LineStream main_;
    FastLineParser parser_;
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
    std::map<uint32_t, MaybeState> pending_offset_;             // states left by loop edges, by target block
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
    Folder folder_{0};
    Block block_buf_;           // the block read last by the walk
    Block comment_block_;       // a line parsed again for its comments
    // The fingerprint text of the last line a finding was on: a line with many
    // findings is read and folded once.
    uint32_t fingerprint_line_ = 0;
    std::string fingerprint_program_;
    std::string fingerprint_text_;
    std::map<std::string, uint64_t, std::less<>> fingerprint_keys_;  // by rule
    FastLineParser comment_parser_;
};

// ------------------------------------------------------------------ setup

std::string Walk::run() {
    // A UTF-16 file is not read as bytes of a program (every line would be a
    // syntax error): it is said once what it is.
    unsigned char bom[2] = {0, 0};
    if (src_.read(0, reinterpret_cast<char*>(bom), 2) == 2 &&
        ((bom[0] == 0xFF && bom[1] == 0xFE) || (bom[0] == 0xFE && bom[1] == 0xFF))) {
        sink_.begin_file(path_);
        sink_.end_file(path_, std::string(kUtf16Message));
        return std::string(kUtf16Message);
    }
    OutlineOptions oo;
    oo.chunk_size = options_.chunk_size;
    outline_ = outline_file(src_, oo);
    stats_.outline_lines_parsed += outline_.lines_parsed;
    if (options_.outline) *options_.outline = outline_;
    sink_.begin_file(path_);
    if (!outline_.ok()) {
        sink_.end_file(path_, outline_.error);
        return outline_.error;
    }
    stats_.bytes = outline_.size;
    stats_.lines = outline_.lines;
    positions_.set_size(outline_.size);
    fingerprints_ = sink_.wants_fingerprints();
    folder_ = Folder(options_.fold);

    if (options_.run_rules) rules_ = select_rules(*options_.rules, config_, options_.only_rules);
    for (auto& r : rules_)
        if (r->sees_plain_moves(config_)) plain_rules_.push_back(r.get());
    plain_ok_ = plain_moves_possible(config_.catalog);
    filter_.emplace(outline_, *options_.rules, config_,
                    options_.run_rules ? options_.only_rules : std::vector<std::string>{"(none)"});
    initial_used_ = filter_->used();
    for (const auto& p : outline_.programs)
        if (!p.name.empty()) names_.insert(p.name);
    library_ = is_subprogram_file(path_);

    size_t first = 0;
    if (options_.checkpoints && options_.checkpoint_every)
        shared_outline_ = std::make_shared<const FileOutline>(outline_);
    if (options_.checkpoints && resume_from_checkpoints()) {
        bool resumed = true;
        if (resume_in_loop_) {
            // Inside a loop: when the edit changed the states where its paths
            // join, the walk starts before the loop after all.
            const uint32_t head = resume_in_loop_->loop->head;
            if (!resume_loop()) {
                ++stats_.loop_resume_misses;
                resumed = fall_back_before(head);
            }
            resume_in_loop_.reset();
        }
        if (resumed) {
            walk_blocks();
            end_program_walk();
            first = program_index_ + 1;
        }
    }
    for (size_t i = first; i < outline_.programs.size() && !stop_ && error_.empty(); ++i) walk_program(i);
    if (error_.empty() && !stop_ && main_.next_offset() != outline_.size) fail(kChangedMessage);
    // Written in place (same size) while it was read: the findings may be of neither text.
    if (error_.empty())
        if (std::string changed = src_.changed(); !changed.empty()) fail(std::move(changed));

    // The findings that stand for the folded ones, then those about the directives.
    for (Diagnostic& d : folder_.finish([&](uint64_t, ByteRange r) { return positions_.range(r); }))
        sink_.diagnostic(std::move(d));
    for (Diagnostic& d : filter_->finish()) sink_.diagnostic(std::move(d));
    sink_.end_file(path_, error_);
    return error_;
}

void Walk::fail(std::string message) {
    if (error_.empty()) error_ = std::move(message);
    stop_ = true;
}

bool Walk::read(Block& b, LineRef& line) {
    if (!main_.next(line)) {
        if (main_.error()) fail(main_.stop_reason().empty() ? src_.error() : main_.stop_reason());
        else fail(kChangedMessage);
        return false;
    }
    if (main_.last_start() + line.text.size() + line.terminator.size() > kMaxInputSize) {
        fail(kTooLargeMessage);
        return false;
    }
    positions_.note_line(line);
    ++stats_.blocks_parsed;
    if (!parser_.parse(line, b)) ++stats_.fallback_lines;
    if (options_.cancel && (++walked_ & 1023) == 0 && options_.cancel->load(std::memory_order_relaxed)) {
        fail(std::string(kCancelled));
        return false;
    }
    return true;
}

// ------------------------------------------------------------- programs

void Walk::walk_program(size_t index) {
    const ProgramOutline& po = outline_.programs[index];
    program_index_ = index;
    flow_ = ProgramFlow(po, outline_.program_end(index));
    tracks_labels_ = !po.references.empty();
    pending_name_.clear();
    pending_offset_.clear();
    defs_.clear();
    join_.clear();
    final_state_ = MaybeState{};
    ++stats_.programs;

    // A walk that makes a summary takes every program for a subprogram: it
    // walks one program of a main file alone, from the entry it was given.
    subprogram_ = library_ || po.has_rts || options_.subprogram_entry;
    if (po.has_content && !subprogram_) {
        subprogram_ = seen_main_;
        seen_main_ = true;
    }
    program_ = Program{};
    program_.name = po.name;
    program_.name_range = po.name_range;
    program_.first_block = po.line - 1;
    if (main_.next_offset() != po.offset) main_.seek(po.offset, po.line);

    ProgramView pv{program_, subprogram_, nullptr};
    for (auto& r : rules_) r->begin_program(*this, pv);
    if (options_.observer) options_.observer->program(program_, subprogram_);

    *A_ = subprogram_ && options_.subprogram_entry ? *options_.subprogram_entry : initial_state(config_, subprogram_);
    reachable_ = true;
    near_ = false;
    walk_blocks();
    end_program_walk();
}

void Walk::walk_blocks() {
    Block& b = block_buf_;
    LineRef line;
    while (!stop_ && main_.next_offset() < flow_.end()) {
        if (shared_outline_ && main_.next_offset() >= next_checkpoint_) take_checkpoint();
        if (!read(b, line)) break;
        uint32_t extent = 0;
        if (flow_.has_flow() && loop_head(b, line.start, extent)) walk_loop(b, line);
        else visit(b, line, Mode::Rules);
    }
}

void Walk::end_program_walk() {
    positions_.clear_current();
    block_ = nullptr;
    if (error_.empty() && !(stop_ && options_.observer)) {
        program_.end_block = main_.next_line() - 1;
        ProgramView pv{program_, subprogram_, final_state_.reachable ? &final_state_.state : nullptr};
        for (auto& r : rules_) r->end_program(*this, pv);
        if (options_.observer) options_.observer->program_end(program_, pv.final_state);
        flush();
    }
}

// --------------------------------------------------------- checkpoints

std::shared_ptr<FrozenWalk> Walk::freeze() {
    auto f = std::make_shared<FrozenWalk>();
    f->config = &config_;
    f->only_rules = options_.only_rules;
    f->run_rules = options_.run_rules;
    f->program = program_index_;
    f->offset = static_cast<uint32_t>(main_.next_offset());
    f->line = main_.next_line();
    f->diagnostics = delivered_diagnostics_;
    f->suppressed = delivered_suppressed_;
    f->reach = delivered_reach_;
    f->local_used = local_used_;
    f->seen_main = seen_main_;
    f->subprogram = subprogram_;
    f->program_info = program_;
    f->flowing = MaybeState{reachable_, reachable_ ? *A_ : ModalState{}};
    f->pending_name = pending_name_;
    f->defs = defs_;
    f->final_state = final_state_;
    for (const auto& r : rules_) f->rules.push_back(r->clone());
    f->used = filter_->used();
    f->marks = positions_.marks_before(f->line);
    if (folder_.enabled()) f->folder = folder_;
    if (fingerprints_) f->occurrences = occurrences_;
    return f;
}

void Walk::take_checkpoint() {
    auto c = std::make_shared<WalkCheckpoint>();
    c->outline = shared_outline_;
    c->pending_offset = pending_offset_;
    c->frozen = freeze();
    options_.checkpoints->push_back(std::move(c));
    next_checkpoint_ = main_.next_offset() + options_.checkpoint_every;
}

namespace {

// An old position in the text a checkpoint was taken in, in the text now
// (nullopt: inside the part that was replaced).
std::optional<uint32_t> moved(uint32_t offset, uint64_t old_size, const TextChange& e) {
    if (offset < e.prefix) return offset;
    if (offset >= old_size - e.suffix) return static_cast<uint32_t>(static_cast<int64_t>(offset) + e.bytes);
    return std::nullopt;
}

// A map by offset in the old text, by offset in the text now (false: a key
// was in the part that was replaced).
template <class V>
bool move_keys(const std::map<uint32_t, V>& in, std::map<uint32_t, V>& out, uint64_t old_size, const TextChange& e) {
    out.clear();
    for (const auto& [k, v] : in) {
        const auto m = moved(k, old_size, e);
        if (!m) return false;
        out.emplace_hint(out.end(), *m, v);
    }
    return true;
}

std::shared_ptr<const SweepState> move_sweep(const SweepState& in, uint64_t old_size, const TextChange& e) {
    auto out = std::make_shared<SweepState>(in);
    if (!move_keys(in.join, out->join, old_size, e) || !move_keys(in.pending_offset, out->pending_offset, old_size, e) ||
        !move_keys(in.probes, out->probes, old_size, e) || !move_keys(in.join_stamps, out->join_stamps, old_size, e))
        return nullptr;
    for (auto& [name, offsets] : out->defs)
        for (uint32_t& o : offsets) {
            const auto m = moved(o, old_size, e);
            if (!m) return nullptr;
            o = *m;
        }
    const auto extent = moved(in.extent, old_size, e);
    if (!extent) return nullptr;
    out->extent = *extent;
    return out;
}

std::shared_ptr<const LoopCheckpoint> move_loop(const LoopCheckpoint& in, uint64_t old_size, const TextChange& e) {
    auto out = std::make_shared<LoopCheckpoint>(in);
    out->first = move_sweep(*in.first, old_size, e);
    out->after_first = move_sweep(*in.after_first, old_size, e);
    if (!out->first || !out->after_first || !move_keys(in.join, out->join, old_size, e) ||
        !move_keys(in.brought_offset, out->brought_offset, old_size, e))
        return nullptr;
    return out;
}

bool same_state(const MaybeState& a, const MaybeState& b) {
    return a.reachable == b.reachable && (!a.reachable || a.state == b.state);
}

template <class Map>
bool same_states(const Map& a, const Map& b) {
    if (a.size() != b.size()) return false;
    for (const auto& [k, v] : a) {
        const auto it = b.find(k);
        if (it == b.end() || !same_state(v, it->second)) return false;
    }
    return true;
}

// Whether two first sweeps over a loop from `head` leave the same states
// wherever the walk with the rules reads them before the block at `at`: the
// joins and the blocks loop edges reach up to it, the sequence names defined
// from the head to it.
bool same_before(const SweepState& a, const SweepState& b, uint32_t head, uint32_t at) {
    if (a.loop_changed != b.loop_changed || a.defs != b.defs) return false;
    auto same_upto = [&](const std::map<uint32_t, MaybeState>& x, const std::map<uint32_t, MaybeState>& y) {
        auto i = x.begin(), j = y.begin();
        for (; i != x.end() && i->first <= at; ++i, ++j)
            if (j == y.end() || j->first != i->first || !same_state(i->second, j->second)) return false;
        return j == y.end() || j->first > at;
    };
    if (!same_upto(a.join, b.join) || !same_upto(a.pending_offset, b.pending_offset)) return false;
    for (const auto& [name, offsets] : a.defs) {
        if (std::none_of(offsets.begin(), offsets.end(), [&](uint32_t o) { return o >= head && o <= at; })) continue;
        const auto x = a.pending_name.find(name);
        const auto y = b.pending_name.find(name);
        if ((x == a.pending_name.end()) != (y == b.pending_name.end())) return false;
        if (x != a.pending_name.end() && !same_state(x->second, y->second)) return false;
    }
    return true;
}

// Whether the outline of the text now is the old one moved by the change, for
// what a walk resumed in program `upto` depends on: the programs up to it,
// every program's name, and every directive.
bool same_structure(const FileOutline& old, const FileOutline& now, size_t upto, const TextChange& e) {
    if (old.programs.size() != now.programs.size() || old.directives.size() != now.directives.size()) return false;
    if (e.prefix > old.size || e.suffix > old.size - e.prefix) return false;
    auto at = [&](uint32_t offset, uint32_t expected) {
        const auto m = moved(offset, old.size, e);
        return m && *m == expected;
    };
    auto line_at = [&](uint32_t offset, uint32_t line, uint32_t expected) {
        return offset < e.prefix ? line == expected : static_cast<int64_t>(line) + e.lines == expected;
    };
    auto range_at = [&](ByteRange r, ByteRange expected) {
        return (r.empty() && expected.empty() && r.begin == expected.begin) ||
               (at(r.begin, expected.begin) && at(r.end, expected.end));
    };
    for (size_t i = 0; i < old.programs.size(); ++i) {
        const ProgramOutline& a = old.programs[i];
        const ProgramOutline& b = now.programs[i];
        if (a.name != b.name) return false;
        if (i > upto) continue;
        if (!at(a.offset, b.offset) || !line_at(a.offset, a.line, b.line) || a.has_rts != b.has_rts ||
            a.has_content != b.has_content || a.references != b.references || a.flow.size() != b.flow.size() ||
            !(a.name.empty() || range_at(a.name_range, b.name_range)))
            return false;
        for (size_t k = 0; k < a.flow.size(); ++k) {
            const FlowSite& x = a.flow[k];
            const FlowSite& y = b.flow[k];
            if (!at(x.offset, y.offset) || !line_at(x.offset, x.line, y.line) || !at(x.next, y.next) ||
                x.block_delete != y.block_delete || !(x.statements == y.statements))
                return false;
        }
    }
    if (old.programs.size() > upto + 1 && !at(old.programs[upto + 1].offset, now.programs[upto + 1].offset))
        return false;
    for (size_t i = 0; i < old.directives.size(); ++i) {
        const DirectiveSite& x = old.directives[i];
        const DirectiveSite& y = now.directives[i];
        if (!at(x.offset, y.offset) || !line_at(x.offset, x.line, y.line) || x.text != y.text ||
            x.program != y.program || x.comments.size() != y.comments.size() || x.target.has_value() != y.target.has_value())
            return false;
        for (size_t k = 0; k < x.comments.size(); ++k)
            if (!range_at(x.comments[k], y.comments[k])) return false;
        if (x.target && (!at(*x.target, *y.target) || !line_at(*x.target, x.target_line, y.target_line))) return false;
    }
    return true;
}

}  // namespace

// The checkpoints of the previous analysis that are still valid for this
// text, moved to it; the walk starts at the last of them. Returns whether it
// does (false: from the start, with none of the old checkpoints).
bool Walk::resume_from_checkpoints() {
    std::vector<Checkpoint> old = std::move(*options_.checkpoints);
    options_.checkpoints->clear();
    if (!options_.checkpoint_every) return false;
    const TextChange& e = options_.edit;
    for (const Checkpoint& c : old) {
        const FrozenWalk& f = *c->frozen;
        if (f.config != &config_ || f.only_rules != options_.only_rules || f.run_rules != options_.run_rules ||
            f.folder.has_value() != folder_.enabled() || f.occurrences.has_value() != fingerprints_ || !c->outline)
            break;
        if (f.offset >= e.prefix || f.reach > e.prefix || f.program >= outline_.programs.size() ||
            !same_structure(*c->outline, outline_, f.program, e))
            break;
        // The file's own subprograms the walk used must leave the same behind in the new text.
        bool same_summaries = true;
        for (const auto& [name, used] : f.local_used) {
            const SubprogramSummary* now = local_summary(name);
            if (!(now && used ? same_effect(*now, *used) : now == used)) same_summaries = false;
        }
        if (!same_summaries) break;
        auto moved_c = std::make_shared<WalkCheckpoint>();
        moved_c->outline = shared_outline_;
        moved_c->frozen = c->frozen;
        bool ok = true;
        for (const auto& [offset, state] : c->pending_offset) {
            const auto m = moved(offset, c->outline->size, e);
            if (!m) ok = false;
            else moved_c->pending_offset.emplace(*m, state);
        }
        if (!ok) break;
        if (c->loop) {
            if (c->loop_moves.size() >= kMaxLoopMoves) break;
            moved_c->loop = c->loop;
            moved_c->loop_moves = c->loop_moves;
            moved_c->loop_moves.emplace_back(c->outline->size, e);
        }
        options_.checkpoints->push_back(std::move(moved_c));
    }
    // The last checkpoint, inside a loop: its states moved to this text (or
    // the one before it, when an offset it holds was in a part replaced since).
    while (!options_.checkpoints->empty() && options_.checkpoints->back()->loop) {
        Checkpoint& last = options_.checkpoints->back();
        std::shared_ptr<const LoopCheckpoint> l = last->loop;
        for (const auto& [size, change] : last->loop_moves)
            if (l) l = move_loop(*l, size, change);
        if (!l) {
            options_.checkpoints->pop_back();
            continue;
        }
        auto now = std::make_shared<WalkCheckpoint>(*last);
        now->loop = std::move(l);
        now->loop_moves.clear();
        last = std::move(now);
        break;
    }
    if (options_.checkpoints->empty()) return false;
    const Checkpoint& c = options_.checkpoints->back();
    restore(*c);
    if (options_.resumed_at) *options_.resumed_at = checkpoint_place(*c);
    if (c->loop) resume_in_loop_ = c;
    return true;
}

// The walk as it was at a checkpoint (of this text, or moved to it).
void Walk::restore(const WalkCheckpoint& c) {
    const FrozenWalk& f = *c.frozen;
    const ProgramOutline& po = outline_.programs[f.program];
    program_index_ = f.program;
    flow_ = ProgramFlow(po, outline_.program_end(f.program));
    tracks_labels_ = !po.references.empty();
    pending_name_ = f.pending_name;
    pending_offset_ = c.pending_offset;
    defs_ = f.defs;
    join_.clear();
    final_state_ = f.final_state;
    seen_main_ = f.seen_main;
    subprogram_ = f.subprogram;
    program_ = f.program_info;
    rules_.clear();
    plain_rules_.clear();
    for (const auto& r : f.rules) rules_.push_back(r->clone());
    for (auto& r : rules_)
        if (r->sees_plain_moves(config_)) plain_rules_.push_back(r.get());
    filter_->set_used(f.used);
    positions_.restore(f.marks);
    if (f.folder) folder_ = *f.folder;
    if (f.occurrences) occurrences_ = *f.occurrences;
    delivered_diagnostics_ = f.diagnostics;
    delivered_suppressed_ = f.suppressed;
    delivered_reach_ = f.reach;
    local_used_ = f.local_used;
    for (const auto& [name, used] : f.local_used) summary_of_[name] = local_summary(name);
    set_state(f.flowing);
    main_.seek(f.offset, f.line);
    next_checkpoint_ = f.offset + options_.checkpoint_every;
    ++stats_.programs;
}

// Whether the block starts a loop of the flow graph; `extent` grows to the
// last block the loop reaches back from.
bool Walk::loop_head(const Block& b, uint32_t offset, uint32_t& extent) const {
    bool head = false;
    if (b.sequence && tracks_labels_)
        if (auto last = flow_.last_jump_to(b.sequence->name); last && *last >= offset) {
            extent = std::max(extent, *last);
            head = true;
        }
    if (const LoopPair* p = flow_.loop_at_head(offset)) {
        extent = std::max(extent, p->end);
        head = true;
    }
    return head;
}

// --------------------------------------------------------------- loops

void Walk::walk_loop(const Block& head, const LineRef& head_line) {
    ++stats_.loops;
    const uint32_t start = head_line.start;
    const uint32_t start_line = head_line.line;
    uint32_t extent = start;
    loop_head(head, start, extent);
    const MaybeState entry{reachable_, reachable_ ? *A_ : ModalState{}};

    in_loop_ = true;
    loop_start_ = start;
    loop_head_line_ = start_line;
    loop_entry_ = entry;
    join_.clear();
    start_loop_marks(start);
    loop_checkpoints_.clear();

    // First sweep, from the input: finds how far the loop reaches, holds its
    // lines when they are few enough.
    std::vector<HeldLine> held;
    std::string held_text;
    // A loop of more bytes than its blocks may be held in would not fit: it
    // is not even tried (its extent only grows as the sweep finds more).
    bool holding = options_.held_loop_blocks > 0 && extent - start <= options_.held_loop_blocks * kHeldBytesPerBlock;
    auto hold = [&](const Block& b, const LineRef& l) {
        if (!holding) return;
        if (held.size() >= options_.held_loop_blocks) {
            holding = false;
            held.clear();
            held_text.clear();
            return;
        }
        held.push_back({b, l.line, l.start, static_cast<uint32_t>(l.text.size()),
                        static_cast<uint32_t>(l.terminator.size())});
        held_text.append(l.text);
        held_text.append(l.terminator);
    };
    loop_changed_ = false;
    probes_.clear();
    join_stamps_.clear();
    set_state(entry);
    hold(head, head_line);
    converged(start, 0, false);
    visit(head, head_line, Mode::Iterate);
    first_sweep(1, extent, hold);
    const uint64_t end = main_.next_offset();
    const uint32_t end_line = main_.next_line();
    ++stats_.loop_sweeps;
    if (holding) ++stats_.held_loops;
    // What falls out of the loop's last block, merged over every sweep: each
    // sweep is a way through the loop, and a block's transfer need not give a
    // wider state for a wider one (a cycle commanded again continues the old
    // one only when that is known), so the last sweep alone may miss a path.
    MaybeState out;
    auto leave_sweep = [&] {
        if (reachable_) out.merge(*A_);
    };
    leave_sweep();

    // A loop read again from the input: the rules walk it at once, if that turns out right.
    const bool speculate = !holding && loop_changed_ && !options_.observer && !stop_;
    if (speculate && !loop_marks_.empty()) {
        after_first_ = std::make_shared<const SweepState>(sweep_state(extent, 0));
        bringing_ = true;
    }
    const bool stands = speculate && walk_speculatively(start, start_line, end, entry);
    bringing_ = false;
    if (stands) {
        ++stats_.speculative_walks;
        leave_sweep();
        set_state(out);
        end_loop();
        return;
    }
    loop_marks_.clear();  // the loop takes more sweeps: no checkpoint inside it
    // Iterate until the states where paths join stop changing.
    while (!stop_ && loop_changed_) {
        loop_changed_ = false;
        set_state(entry);
        const bool whole = holding ? sweep_held(held, held_text, Mode::Iterate)
                                   : sweep_file(start, start_line, end, Mode::Iterate);
        ++stats_.loop_sweeps;
        // A sweep that converged early would end as the one before it did.
        if (whole) leave_sweep();
    }
    // Once more, with the rules.
    if (!stop_) {
        set_state(entry);
        if (holding) sweep_held(held, held_text, Mode::Rules);
        else sweep_file(start, start_line, end, Mode::Rules);
        leave_sweep();
        set_state(out);
    }
    if (holding && !stop_) main_.seek(end, end_line);
    end_loop();
}

void Walk::end_loop() {
    in_loop_ = false;
    bringing_ = false;
    brought_name_.clear();
    brought_offset_.clear();
    brought_final_ = MaybeState{};
    join_.clear();
    probes_.clear();
    join_stamps_.clear();
    loop_marks_.clear();
    loop_mark_next_ = 0;
    loop_checkpoints_.clear();
    after_first_.reset();
}

// The first sweep over a loop from its `index`-th block on (the loop's head
// was visited), to the last block it reaches back from (`extent` grows as
// the sweep finds more); `hold` sees each block.
template <class Hold>
void Walk::first_sweep(uint32_t index, uint32_t& extent, Hold&& hold) {
    Block b;
    LineRef line;
    for (; !stop_ && main_.next_offset() <= extent && main_.next_offset() < flow_.end(); ++index) {
        mark_loop(extent, index);
        if (!read(b, line)) break;
        loop_head(b, line.start, extent);
        hold(b, line);
        converged(line.start, index, false);
        visit(b, line, Mode::Iterate);
    }
}

bool Walk::sweep_held(std::vector<HeldLine>& held, const std::string& text, Mode mode) {
    if (mode == Mode::Rules) {
        positions_.clear_current();
        positions_.held.set(text, held.front().start, held.front().line);
        held_ = &held;
    }
    size_t at = 0;
    uint32_t index = 0;
    bool whole = true;
    for (const HeldLine& h : held) {
        if (stop_ || (mode == Mode::Iterate && converged(h.start, index++, true))) {
            whole = false;
            break;
        }
        const std::string_view t(text.data() + at, h.text_size);
        const std::string_view term(text.data() + at + h.text_size, h.terminator_size);
        at += h.text_size + h.terminator_size;
        visit(h.block, LineRef{t, term, h.line, h.start}, mode);
    }
    positions_.held.clear();
    held_ = nullptr;
    return whole && !stop_;
}

bool Walk::sweep_file(uint32_t start, uint32_t start_line, uint64_t end, Mode mode) {
    main_.seek(start, start_line);
    Block b;
    LineRef line;
    for (uint32_t index = 0; !stop_ && main_.next_offset() < end; ++index) {
        if (speculating_ && loop_mark_next_ < loop_marks_.size()) {
            while (loop_mark_next_ < loop_marks_.size() && loop_marks_[loop_mark_next_].offset < main_.next_offset())
                ++loop_mark_next_;
            if (loop_mark_next_ < loop_marks_.size() && loop_marks_[loop_mark_next_].offset == main_.next_offset())
                take_loop_checkpoint();
        }
        if (!read(b, line)) break;
        if (mode == Mode::Iterate && converged(line.start, index, true)) return false;
        visit(b, line, mode);
    }
    return !stop_;
}

void Walk::set_state(const MaybeState& s) {
    reachable_ = s.reachable;
    if (s.reachable) *A_ = s.state;
    near_ = false;
}

// ---------------------------------------------------------------- blocks

// The state at the block's start where paths join: the state falling into
// it, merged with what jumps and loop edges left for it (and, inside a loop
// being iterated, with what earlier sweeps brought there).
void Walk::enter(const Block& b, uint32_t offset) {
    const bool labelled = b.sequence && tracks_labels_ && flow_.is_referenced(b.sequence->name);
    const MaybeState* by_name = nullptr;
    const MaybeState* by_offset = nullptr;
    if (labelled) {
        auto& defs = defs_[b.sequence->name];
        if (defs.empty() || defs.back() < offset) defs.push_back(offset);
        if (auto it = pending_name_.find(b.sequence->name); it != pending_name_.end()) by_name = &it->second;
    }
    if (!pending_offset_.empty())
        if (auto it = pending_offset_.find(offset); it != pending_offset_.end()) by_offset = &it->second;
    if (!by_name && !by_offset) return;  // no path but the one falling into the block
    // The merge is made in place, in the state flowing in.
    bool reachable = reachable_;
    for (const MaybeState* p : {by_name, by_offset}) {
        if (!p || !p->reachable) continue;
        if (reachable) A_->merge(p->state);
        else *A_ = p->state;
        reachable = true;
    }
    if (in_loop_) {
        MaybeState& j = join_[offset];
        if (reachable) {
            if (j.reachable) {
                j.state.merge(*A_);
                *A_ = j.state;
            } else {
                j.state = *A_;
                j.reachable = true;
            }
        } else if (j.reachable) {
            *A_ = j.state;
            reachable = true;
        }
        join_stamps_[offset].entered = ++stamp_;
    }
    reachable_ = reachable;
    near_ = false;
}

void Walk::contribute_name(std::string_view name, uint32_t offset, uint32_t line, ByteRange range) {
    if (bringing_) brought_name_[std::string(name)].merge_jump(*B_, line, range);
    auto [it, inserted] = pending_name_.try_emplace(std::string(name));
    if (!it->second.merge_jump(*B_, line, range) || !in_loop_) return;
    if (auto d = defs_.find(it->first); d != defs_.end())
        for (uint32_t def : d->second)
            if (def >= loop_start_) join_reached(def, offset, line, range);
}

void Walk::contribute_offset(uint32_t target, uint32_t offset, uint32_t line, ByteRange range) {
    if (bringing_) brought_offset_[target].merge_jump(*B_, line, range);
    if (!pending_offset_[target].merge_jump(*B_, line, range) || !in_loop_) return;
    if (target >= loop_start_) join_reached(target, offset, line, range);
}

// The state after the block at `offset` (B_) now also flows into the join at
// `target` inside the loop being iterated. When that changes what the join
// has seen, a join already walked in this sweep needs another sweep; a join
// further on sees something new in this one.
void Walk::join_reached(uint32_t target, uint32_t offset, uint32_t line, ByteRange range) {
    if (auto j = join_.find(target); j != join_.end()) {
        MaybeState merged = j->second;
        if (!merged.merge_jump(*B_, line, range)) return;  // nothing new there
    }
    if (target <= offset) loop_changed_ = true;
    mark_changed(target);
}

// At every kProbeBlocks-th block of a sweep: records the state flowing into
// the block, and (when `check`) says whether the sweep can stop here.
bool Walk::converged(uint32_t offset, uint32_t index, bool check) {
    if (index % kProbeBlocks != 0) return false;
    const MaybeState now{reachable_, reachable_ ? *A_ : ModalState{}};
    auto [it, inserted] = probes_.try_emplace(offset, now);
    if (inserted) return false;
    const bool same = it->second.reachable == now.reachable && (!now.reachable || it->second.state == now.state);
    if (!same) {
        it->second = now;
        return false;
    }
    if (!check) return false;
    for (auto j = join_stamps_.lower_bound(offset); j != join_stamps_.end(); ++j)
        if (j->second.changed > j->second.entered) return false;
    return true;
}

// After the block: the state flows on to its successors.
void Walk::leave(const Block& b, const LineRef& line) {
    flow_out(b, *A_, *B_);
    const uint32_t next = line.end();
    bool falls = true, exits = false;
    if (has_flow_statement(b)) {
        const BlockEdges e = block_edges(b, line.start, next, flow_);
        const ByteRange jump = jump_range(b);
        for (std::string_view name : e.jumps) contribute_name(name, line.start, line.line, jump);
        for (uint32_t t : e.targets) contribute_offset(t, line.start, line.line, jump);
        falls = e.falls_through;
        exits = e.exits;
    } else {
        if (ends_program(b)) {
            exits = true;
            if (!b.block_delete) falls = false;
        }
        if (falls && next >= flow_.end()) exits = true;
    }
    if (exits) bring_final(*B_);
    std::swap(A_, B_);
    reachable_ = falls;
}

std::optional<MacroCall> Walk::resolve(const Block& b, const ModalState& before) const {
    std::optional<MacroCall> call = resolve_call(b, before, config_.catalog);
    if (call && options_.summaries && call->kind == CallKind::Call && !call->spec && !call->name.empty()) {
        // Asked once per name and file: a posted program calls the same few names again and again.
        auto [it, added] = summary_of_.try_emplace(call->name, nullptr);
        if (added) {
            // A name this file defines is its own program (no file beside it
            // is read); the program that calls itself stays unknown.
            if (names_.find(call->name) == names_.end())
                it->second = options_.summaries->find(config_, path_, call->name);
            else if (call->name != program_.name)
                local_used_.emplace_back(call->name, it->second = local_summary(call->name));
        }
        call->summary = it->second;
    }
    return call;
}

const SubprogramSummary* Walk::local_summary(const std::string& name) const {
    for (size_t i = 0; i < outline_.programs.size(); ++i) {
        const ProgramOutline& po = outline_.programs[i];
        if (po.name != name) continue;  // the first program of that name, as the control finds it
        const uint64_t end = i + 1 < outline_.programs.size() ? outline_.programs[i + 1].offset : outline_.size;
        return options_.summaries->local(config_, path_, src_, po.offset, end, po.line, name);
    }
    return nullptr;
}

void Walk::visit(const Block& b, const LineRef& line, Mode mode) {
    enter(b, line.start);
    const bool rules = mode == Mode::Rules;
    if (rules) {
        if (!held_) positions_.set_current(line);
        block_ = &b;
    }
    if (!reachable_) {
        if (!rules) return;
        const std::optional<MacroCall> call = resolve(b, unknown_);
        ModalState after = unknown_;
        apply_block(b, call ? &*call : nullptr, config_.catalog, after);
        check(BlockView{b, unknown_, after, call ? &*call : nullptr, false}, line, false);
        near_ = false;
        return;
    }
    ++stats_.transfers;
    const bool plain_line = parser_.last_plain() && &b == &block_buf_;
    if (plain_ok_ && (plain_line || is_plain_move_block(b)) && plain_move_state(*A_)) {
        // A plain move (semantics/transfer.h). A and B differ at most in what a
        // plain move sets when `near_`, so those fields make B equal to A again.
        if (near_) {
            B_->motion = A_->motion;
            B_->g60_from = A_->g60_from;
            B_->feed = A_->feed;
            B_->feed_commanded = A_->feed_commanded;
            B_->x = A_->x;
            B_->y = A_->y;
            B_->z = A_->z;
        } else {
            *B_ = *A_;
        }
        apply_plain_move(b, *B_);
        if (rules) check(BlockView{b, *A_, *B_, nullptr, true}, line, true);
        if (line.end() >= flow_.end()) bring_final(*B_);  // control falls off the last block
        std::swap(A_, B_);
        near_ = true;
        return;
    }
    const std::optional<MacroCall> call = resolve(b, *A_);
    *B_ = *A_;
    apply_block(b, call ? &*call : nullptr, config_.catalog, *B_);
    near_ = false;
    if (rules) check(BlockView{b, *A_, *B_, call ? &*call : nullptr, true}, line, false);
    leave(b, line);
}

void Walk::check(const BlockView& view, const LineRef& line, bool plain) {
    if (plain) {
        for (Rule* r : plain_rules_)
            if (r->wants_plain_moves() || view.block.sequence) r->check_block(*this, view);
    } else {
        for (auto& r : rules_) r->check_block(*this, view);
    }
    if (options_.observer && !options_.observer->block(view, line)) stop_ = true;
    if (!findings_.empty()) flush();
}

// ------------------------------------------------------------- findings

std::string_view Walk::text(ByteRange r) const {
    for (const Window* w : {&positions_.current(), static_cast<const Window*>(&positions_.held)}) {
        if (w->contains(r.begin) && w->contains(r.end)) return w->text.substr(r.begin - w->base, r.size());
        // Past the end of the window: past the end of the file too when the
        // window's last line has no terminator.
        if (w->contains(r.begin) && !w->starts.empty() && w->starts.back() != w->text.size())
            return w->text.substr(r.begin - w->base, r.size());
    }
    // Elsewhere in the file (no rule asks for that today): read it.
    const uint64_t size = outline_.size;
    const uint64_t begin = std::min<uint64_t>(r.begin, size);
    const uint64_t len = std::min<uint64_t>(r.size(), size - begin);
    scratch_text_.assign(len, '\0');
    const int64_t got = len ? src_.read(begin, scratch_text_.data(), len) : 0;
    scratch_text_.resize(got > 0 ? static_cast<size_t>(got) : 0);
    return scratch_text_;
}

bool Walk::has_label(std::string_view name) const {
    if (auto it = defs_.find(std::string(name)); it != defs_.end() && !it->second.empty()) return true;
    if (flow_.is_referenced(name)) return false;
    // A name the outline did not see referenced: the walk kept none of its
    // definitions. Unknown, so no finding rests on it.
    ++stats_.label_misses;
    return true;
}

bool Walk::has_program(std::string_view name) const {
    if (name.empty()) {
        for (const auto& p : outline_.programs)
            if (p.name.empty()) return true;
        return false;
    }
    if (names_.find(name) != names_.end()) return true;
    return options_.known_programs && options_.known_programs->find(name) != options_.known_programs->end();
}

Diagnostic& Walk::report(const RuleMeta& rule, ByteRange range, std::string message) {
    Diagnostic d;
    d.rule = std::string(rule.id);
    d.name = std::string(rule.name);
    d.severity = config_.severity_of(rule.id, rule.severity, rule.enabled_by_default).value_or(rule.severity);
    d.message = std::move(message);
    d.range = positions_.range(range);
    d.line_text = positions_.line_text(d.range.start.line, 1000);
    d.kind = pending_verdict_ ? pending_kind_ : message_kind(rule.id, d.message);
    findings_.push_back(std::move(d));
    verdicts_.push_back(pending_verdict_);
    pending_verdict_.reset();
    return findings_.back();
}

bool Walk::folded(const RuleMeta& rule, std::string_view key, ByteRange range) {
    pending_verdict_.reset();
    if (!folder_.enabled()) return false;
    // A finding a directive silences is reported (and then suppressed), never folded.
    if (!filter_->empty()) {
        Diagnostic probe;
        probe.rule = std::string(rule.id);
        probe.range.start = positions_.position(range.begin);
        if (filter_->covers(probe)) return false;
    }
    pending_kind_ = keyed_kind(rule.id, key);
    const Folder::Verdict v = folder_.next(pending_kind_, range);
    if (v == Folder::Verdict::Count) return true;
    pending_verdict_ = v;
    return false;
}

std::string Walk::fingerprint_for(std::string_view rule, uint32_t line) {
    if (line != fingerprint_line_ || line == 0 || program_.name != fingerprint_program_) {
        const LineData ld = positions_.line(line);
        fingerprint_text_ = fingerprint_text(ld.text, ld.start, ld.ok ? comments_of(ld) : nullptr);
        fingerprint_line_ = line;
        fingerprint_program_ = program_.name;
        fingerprint_keys_.clear();
    }
    auto it = fingerprint_keys_.find(rule);
    if (it == fingerprint_keys_.end())
        it = fingerprint_keys_.emplace(std::string(rule), fingerprint_key(rule, program_.name, fingerprint_text_)).first;
    return make_fingerprint(it->second, occurrences_.next(it->second));
}

// The comments of the block of a line.
const std::vector<Comment>* Walk::comments_of(const LineData& ld) {
    if (block_ && block_->line == ld.line) return &block_->comments;
    if (held_)
        for (const HeldLine& h : *held_)
            if (h.line == ld.line) return &h.block.comments;
    if (ld.text.empty() && ld.terminator.empty()) return nullptr;  // no block
    comment_parser_.parse(LineRef{ld.text, ld.terminator, ld.line, ld.start}, comment_block_);
    return &comment_block_.comments;
}

void Walk::flush() {
    // Decide in position order (the order the findings are handed on), and
    // give fingerprints in the order the rules reported (the occurrence count
    // of a fingerprint follows it): only to the findings that are shown.
    const size_t n = findings_.size();
    std::vector<size_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return diagnostic_less(findings_[a], findings_[b]); });
    std::vector<std::optional<SuppressedDiagnostic>> silenced(n);
    std::vector<Folder::Verdict> verdict(n, Folder::Verdict::Show);
    for (size_t i : order) {
        SuppressedDiagnostic s;
        if (filter_->silence(findings_[i], s)) silenced[i] = std::move(s);
        else verdict[i] = verdicts_[i] ? *verdicts_[i] : folder_.next(findings_[i].kind, findings_[i].range.bytes);
    }
    if (fingerprints_)
        for (size_t i = 0; i < n; ++i) {
            Diagnostic& d = silenced[i] ? silenced[i]->diagnostic : findings_[i];
            if (silenced[i] || verdict[i] != Folder::Verdict::Count)
                d.fingerprint = fingerprint_for(d.rule, d.range.start.line);
        }
    for (size_t i : order) {
        if (silenced[i]) deliver(std::move(*silenced[i]));
        else if (verdict[i] == Folder::Verdict::Show) deliver(std::move(findings_[i]));
        else if (verdict[i] == Folder::Verdict::Hold) folder_.hold(findings_[i].kind, std::move(findings_[i]));
    }
    findings_.clear();
    verdicts_.clear();
}

namespace {

// The furthest byte a finding points at (its range, notes and fixes).
uint32_t reach_of(const Diagnostic& d) {
    uint32_t r = d.range.bytes.end;
    for (const Note& n : d.notes)
        if (n.range) r = std::max(r, n.range->bytes.end);
    for (const Fix& f : d.fixes)
        for (const TextEdit& e : f.edits) r = std::max(r, e.range.bytes.end);
    return r;
}

}  // namespace

void Walk::extend_reach(const Diagnostic& d) { delivered_reach_ = std::max(delivered_reach_, reach_of(d)); }

void Walk::deliver(Diagnostic&& d) {
    if (!speculating_) {
        ++delivered_diagnostics_;
        extend_reach(d);
        sink_.diagnostic(std::move(d));
    } else if (speculative_.size() < kMaxSpeculativeFindings) {
        speculative_.emplace_back(std::move(d), std::nullopt);
    } else {
        speculation_overflow_ = true;
    }
}

void Walk::deliver(SuppressedDiagnostic&& s) {
    if (!speculating_) {
        ++delivered_suppressed_;
        extend_reach(s.diagnostic);
        if (s.directive) delivered_reach_ = std::max(delivered_reach_, s.directive->bytes.end);
        sink_.suppressed(std::move(s));
    } else if (speculative_.size() < kMaxSpeculativeFindings) {
        speculative_.emplace_back(std::nullopt, std::move(s));
    } else {
        speculation_overflow_ = true;
    }
}

void Walk::begin_speculation() {
    speculating_ = true;
    speculation_overflow_ = false;
    speculative_.clear();
    loop_changed_ = false;
}

// After a walk with the rules whose findings were kept aside: when it changed
// no state where paths join, its findings and the checkpoints it took inside
// the loop are handed on (true); otherwise they are dropped.
bool Walk::end_speculation() {
    speculating_ = false;
    const bool stands = !stop_ && !loop_changed_ && !speculation_overflow_;
    if (stands) {
        for (auto& [d, s] : speculative_) {
            if (d) deliver(std::move(*d));
            else deliver(std::move(*s));
        }
        for (Checkpoint& c : loop_checkpoints_) options_.checkpoints->push_back(std::move(c));
        if (!loop_checkpoints_.empty()) loop_states_left_ -= std::min(loop_states_left_, loop_mark_cost_);
    }
    speculative_.clear();
    loop_checkpoints_.clear();
    return stands;
}

// Walks the loop with the rules, its findings kept aside; returns whether they
// stand (no state where paths join changed). Otherwise everything the walk
// did to the rules and the findings is undone.
bool Walk::walk_speculatively(uint32_t start, uint32_t start_line, uint64_t end, const MaybeState& entry) {
    Speculation before;
    for (const auto& r : rules_) before.rules.push_back(r->clone());
    before.folder = folder_;
    before.used = filter_->used();
    if (fingerprints_) before.occurrences = occurrences_;
    begin_speculation();
    set_state(entry);
    sweep_file(start, start_line, end, Mode::Rules);
    if (end_speculation()) return true;
    rules_ = std::move(before.rules);
    plain_rules_.clear();
    for (auto& r : rules_)
        if (r->sees_plain_moves(config_)) plain_rules_.push_back(r.get());
    folder_ = std::move(before.folder);
    filter_->set_used(before.used);
    if (fingerprints_) occurrences_ = std::move(before.occurrences);
    loop_changed_ = true;
    return false;
}

// ------------------------------------------------- checkpoints inside loops

SweepState Walk::sweep_state(uint32_t extent, uint32_t index) const {
    SweepState s;
    s.flowing = MaybeState{reachable_, reachable_ ? *A_ : ModalState{}};
    s.join = join_;
    s.pending_name = pending_name_;
    s.pending_offset = pending_offset_;
    s.defs = defs_;
    s.final_state = final_state_;
    s.probes = probes_;
    s.join_stamps = join_stamps_;
    s.stamp = stamp_;
    s.extent = extent;
    s.index = index;
    s.loop_changed = loop_changed_;
    return s;
}

void Walk::restore_sweep(const SweepState& s) {
    set_state(s.flowing);
    join_ = s.join;
    pending_name_ = s.pending_name;
    pending_offset_ = s.pending_offset;
    defs_ = s.defs;
    final_state_ = s.final_state;
    probes_ = s.probes;
    join_stamps_ = s.join_stamps;
    stamp_ = s.stamp;
    loop_changed_ = s.loop_changed;
}

// In the first sweep over a loop, before the block at the next offset: its
// states, every checkpoint_every bytes, for the checkpoint the walk with the
// rules may take there.
void Walk::mark_loop(uint32_t extent, uint32_t index) {
    if (!shared_outline_ || loop_states_left_ == 0 || main_.next_offset() < next_loop_mark_) return;
    auto first = std::make_shared<const SweepState>(sweep_state(extent, index));
    const size_t cost = 1 + first->join.size() + first->pending_offset.size() + first->pending_name.size() +
                        first->probes.size() + first->join_stamps.size();
    loop_marks_.push_back({static_cast<uint32_t>(main_.next_offset()), std::move(first), cost});
    loop_mark_cost_ += cost;
    while (loop_mark_cost_ > std::min(kLoopMarkBudget, loop_states_left_) && loop_marks_.size() > 1) {
        size_t kept = 0;
        loop_mark_cost_ = 0;
        for (size_t i = 0; i < loop_marks_.size(); i += 2) {
            loop_mark_cost_ += loop_marks_[i].cost;
            loop_marks_[kept++] = std::move(loop_marks_[i]);
        }
        loop_marks_.resize(kept);
        loop_mark_spacing_ *= 2;
    }
    next_loop_mark_ = main_.next_offset() + loop_mark_spacing_;
}

// In the walk with the rules after the first sweep, before a block the first
// sweep marked. The findings it keeps aside count as handed over: they are,
// before any finding after the block, if the walk stands.
void Walk::take_loop_checkpoint() {
    const LoopMark& m = loop_marks_[loop_mark_next_++];
    auto f = freeze();
    for (const auto& [d, s] : speculative_) {
        if (d) {
            ++f->diagnostics;
            f->reach = std::max(f->reach, reach_of(*d));
        } else {
            ++f->suppressed;
            f->reach = std::max(f->reach, reach_of(s->diagnostic));
            if (s->directive) f->reach = std::max(f->reach, s->directive->bytes.end);
        }
    }
    auto l = std::make_shared<LoopCheckpoint>();
    l->head = loop_start_;
    l->head_line = loop_head_line_;
    l->entry = loop_entry_;
    l->first = m.first;
    l->after_first = after_first_;
    l->join = join_;
    l->brought_name = brought_name_;
    l->brought_offset = brought_offset_;
    l->brought_final = brought_final_;
    auto c = std::make_shared<WalkCheckpoint>();
    c->outline = shared_outline_;  // pending_offset: resume_loop makes it from the loop's states
    c->frozen = std::move(f);
    c->loop = std::move(l);
    loop_checkpoints_.push_back(std::move(c));
}

// Resumes at a checkpoint inside a loop (resume_in_loop_, restored): the
// first sweep goes on from its block over the new text; when it leaves the
// states the previous analysis's walk with the rules started from, that walk
// goes on from the block too, with the findings before it the caller's.
// False when the loop must be walked from before its head (the walk is then
// in no state to go on).
bool Walk::resume_loop() {
    const WalkCheckpoint& c = *resume_in_loop_;
    const FrozenWalk& f = *c.frozen;
    const LoopCheckpoint& l = *c.loop;
    ++stats_.loops;
    in_loop_ = true;
    loop_start_ = l.head;
    loop_head_line_ = l.head_line;
    loop_entry_ = l.entry;
    start_loop_marks(f.offset);
    loop_checkpoints_.clear();
    restore_sweep(*l.first);
    uint32_t extent = l.first->extent;
    first_sweep(l.first->index, extent, [](const Block&, const LineRef&) {});
    const uint64_t end = main_.next_offset();
    ++stats_.loop_sweeps;
    if (stop_) return true;  // cancelled, or the input failed: the walk ends anyway
    MaybeState out;
    if (reachable_) out.merge(*A_);
    auto now = std::make_shared<const SweepState>(sweep_state(extent, 0));
    if (!now->loop_changed || !same_before(*now, *l.after_first, l.head, f.offset)) {
        end_loop();
        return false;
    }
    // The walk with the rules up to the block is then the one of the previous
    // analysis: at the block, the joins it passed are as it left them, and
    // the states further on are the new first sweep's with what that walk
    // brought to them.
    after_first_ = std::move(now);
    join_ = after_first_->join;
    for (const auto& [k, v] : l.join)
        if (k <= f.offset) join_[k] = v;
    pending_name_ = after_first_->pending_name;
    for (const auto& [name, v] : l.brought_name) pending_name_[name].merge(v);
    pending_offset_ = after_first_->pending_offset;
    for (const auto& [k, v] : l.brought_offset) pending_offset_[k].merge(v);
    final_state_ = after_first_->final_state;
    final_state_.merge(l.brought_final);
    defs_ = after_first_->defs;
    brought_name_ = l.brought_name;
    brought_offset_ = l.brought_offset;
    brought_final_ = l.brought_final;
    bringing_ = true;
    set_state(f.flowing);
    loop_mark_next_ = 0;
    begin_speculation();
    sweep_file(f.offset, f.line, end, Mode::Rules);
    bringing_ = false;
    if (stop_) return true;
    if (!end_speculation()) {
        end_loop();
        return false;
    }
    if (reachable_) out.merge(*A_);
    set_state(out);
    end_loop();
    ++stats_.speculative_walks;
    ++stats_.loop_resumes;
    return true;
}

// After resume_loop failed: the walk starts again at the last checkpoint
// before the loop's head (outside loops), or from the start of the file
// (false). Nothing was handed to the sink since the checkpoint it resumed at.
bool Walk::fall_back_before(uint32_t head) {
    std::vector<Checkpoint>& cps = *options_.checkpoints;
    while (!cps.empty() && (cps.back()->loop || cps.back()->frozen->offset > head)) cps.pop_back();
    if (cps.empty()) {
        reset_to_start();
        if (options_.resumed_at) options_.resumed_at->reset();
        return false;
    }
    restore(*cps.back());
    if (options_.resumed_at) *options_.resumed_at = checkpoint_place(*cps.back());
    return true;
}

void Walk::reset_to_start() {
    options_.checkpoints->clear();
    loop_states_left_ = kLoopStates;
    rules_.clear();
    if (options_.run_rules) rules_ = select_rules(*options_.rules, config_, options_.only_rules);
    plain_rules_.clear();
    for (auto& r : rules_)
        if (r->sees_plain_moves(config_)) plain_rules_.push_back(r.get());
    filter_->set_used(initial_used_);
    positions_.restore(Positions::Marks{});
    folder_ = Folder(options_.fold);
    occurrences_ = OccurrenceCounter{};
    delivered_diagnostics_ = 0;
    delivered_suppressed_ = 0;
    delivered_reach_ = 0;
    local_used_.clear();
    seen_main_ = false;
    next_checkpoint_ = 0;
    pending_name_.clear();
    pending_offset_.clear();
    defs_.clear();
    final_state_ = MaybeState{};
    main_.seek(0, 1);
}

}  // namespace

std::string run_engine(const std::string& path, ByteSource& src, const Config& config, const EngineOptions& options,
                       DiagnosticSink& sink, EngineStats* stats) {
    EngineStats own;
    Walk walk(path, src, config, options, sink, stats ? *stats : own);
    return walk.run();
}

}  // namespace osplint
