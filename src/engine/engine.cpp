// The walk of the analysis engine (see engine.h and engine/walk.h): programs,
// loops and blocks; the findings are in findings.cpp, checkpoints in
// checkpoints.cpp.
#include "engine/walk.h"

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <utility>

#include "catalog/catalog.h"
#include "engine/summaries.h"
#include "semantics/eval.h"
#include "semantics/transfer.h"
#include "support/text.h"

namespace osplint {

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
    make_outline();
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
    index_plain_rules();
    plain_ok_ = plain_moves_possible(config_.catalog);
    runs_ok_ = !options_.checkpoints && !options_.observer;
    // A batch walk reads the next chunk of a large input on another thread
    // (the outline's threads have ended by now).
    if (runs_ok_) main_.read_ahead();
    filter_.emplace(outline_, *options_.rules, config_,
                    options_.run_rules ? options_.only_rules : std::vector<std::string>{"(none)"});
    initial_used_ = filter_->used();
    for (const auto& p : outline_.programs)
        if (!p.name.empty()) names_.insert(p.name);
    library_ = is_subprogram_file(path_);

    size_t first = 0;
    if (options_.converged) options_.converged->reset();
    if (options_.checkpoints && options_.checkpoint_every) {
        shared_outline_ = std::make_shared<const FileOutline>(outline_);
        walk_summaries_ = std::make_shared<LocalSummaries>();
    }
    if (options_.checkpoints) first = walk_resumed();
    for (size_t i = first; i < outline_.programs.size() && !stop_ && error_.empty(); ++i) walk_program(i);
    if (error_.empty() && !stop_ && main_.next_offset() != outline_.size) fail(kChangedMessage);
    // Written in place (same size) while it was read: the findings may be of neither text.
    if (error_.empty())
        if (std::string changed = src_.changed(); !changed.empty()) fail(std::move(changed));
    if (converged_ && error_.empty()) {
        // The rest, the findings at the end of the file included, is the previous analysis's.
        finish_summaries();
        sink_.end_file(path_, error_);
        return error_;
    }
    if (options_.converged) options_.converged->reset();
    if (error_.empty()) finish_summaries();

    // The findings that stand for the folded ones, then those about the directives.
    for (Diagnostic& d : folder_.finish([&](uint64_t, ByteRange r) { return positions_.range(r); }))
        sink_.diagnostic(std::move(d));
    for (Diagnostic& d : filter_->finish()) sink_.diagnostic(std::move(d));
    sink_.end_file(path_, error_);
    return error_;
}

// The outline of the input. After an edit of a plain line, the outline of
// the text before it, moved (every checkpoint of the previous analysis holds
// that text's outline).
void Walk::make_outline() {
    std::optional<FileOutline> moved;
    if (options_.checkpoints && !options_.checkpoints->empty() && options_.checkpoints->front()->outline) {
        const FileOutline& before = *options_.checkpoints->front()->outline;
        const std::optional<uint64_t> size = src_.size();
        if (size && static_cast<int64_t>(*size) == static_cast<int64_t>(before.size) + options_.edit.bytes)
            moved = moved_outline(before, options_.edit);
    }
    if (moved) {
        outline_ = std::move(*moved);
        ++stats_.outlines_moved;
    } else {
        OutlineOptions oo;
        oo.chunk_size = options_.chunk_size;
        outline_ = outline_file(src_, oo);
    }
}

// After an edit: the walk from the last checkpoint of the previous analysis
// it can start at to the end of that checkpoint's program. Returns the index
// of the first program still to be walked (0: the walk starts at the start).
size_t Walk::walk_resumed() {
    if (!resume_from_checkpoints()) return 0;
    if (resume_in_loop_) {
        // Inside a loop: when the edit changed the states where its paths
        // join, the walk starts before the loop after all.
        const uint32_t head = resume_in_loop_->loop->head;
        bool resumed = true;
        if (!resume_loop()) {
            ++stats_.loop_resume_misses;
            resumed = fall_back_before(head);
        }
        resume_in_loop_.reset();
        if (!resumed) return 0;
    }
    walk_blocks();
    end_program_walk();
    return program_index_ + 1;
}

void Walk::fail(std::string message) {
    if (error_.empty()) error_ = std::move(message);
    stop_ = true;
}

bool Walk::read(Block& b, LineRef& line, bool moves) {
    if (!fetch(line)) return false;
    parse(b, line, moves);
    return true;
}

bool Walk::fetch(LineRef& line) {
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
    if (options_.cancel && (++walked_ & 1023) == 0 && options_.cancel->load(std::memory_order_relaxed)) {
        fail(std::string(kCancelled));
        return false;
    }
    return true;
}

void Walk::parse(Block& b, const LineRef& line, bool moves) {
    if (!(moves ? parser_.parse_moves(line, b) : parser_.parse(line, b))) ++stats_.fallback_lines;
    partial_ = moves && parser_.last_partial() ? &b : nullptr;
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
    ++flow_epoch_;
    reachable_ = true;
    near_ = false;
    walk_blocks();
    end_program_walk();
}

void Walk::walk_blocks() {
    Block& b = block_buf_;
    LineRef line;
    while (!stop_ && main_.next_offset() < flow_.end()) {
        converge_if_due();
        if (stop_) break;
        if (shared_outline_ && main_.next_offset() >= next_checkpoint_) take_checkpoint();
        const bool move = may_be_move();
        if (!repeat_.armed || !may_repeat()) {
            if (move && rules_idle() && skim_run(kRunLines, flow_.end())) continue;
            if (quiet_run(kRunLines, flow_.end(), move)) continue;
        } else if (repeat_run(kRunLines)) {
            continue;
        }
        const Next next = read_for_rules(b, line, move);
        if (next == Next::End) break;
        if (next == Next::Checked) continue;
        uint32_t extent = 0;
        if (flow_.has_flow() && loop_head(b, line.start, extent)) {
            read_whole(b, line);  // a loop may hold its head
            walk_loop(b, line);
        } else {
            visit(b, line, Mode::Rules);
        }
    }
}

void Walk::end_program_walk() {
    positions_.clear_current();
    block_ = nullptr;
    if (converged_) return;  // the previous analysis made the findings from there on
    if (error_.empty() && !(stop_ && options_.observer)) {
        program_.end_block = main_.next_line() - 1;
        ProgramView pv{program_, subprogram_, final_state_.reachable ? &final_state_.state : nullptr};
        for (auto& r : rules_) r->end_program(*this, pv);
        if (options_.observer) options_.observer->program_end(program_, pv.final_state);
        flush();
    }
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
    // lines when they are few enough. A loop of more bytes than its blocks may
    // be held in would not fit: it is not even tried (its extent only grows
    // as the sweep finds more).
    HeldLoop held;
    held.holding = options_.held_loop_blocks > 0 && extent - start <= options_.held_loop_blocks * kHeldBytesPerBlock;
    loop_changed_ = false;
    probes_.clear();
    join_stamps_.clear();
    set_state(entry);
    held.hold(head, head_line, options_.held_loop_blocks);
    converged(start, 0, false);
    visit(head, head_line, Mode::Iterate);
    if (first_sweep(1, extent, &held)) held.drop();  // it ended early (after an edit): not every block was read
    const uint64_t end = main_.next_offset();
    const uint32_t end_line = main_.next_line();
    ++stats_.loop_sweeps;
    if (held.holding) ++stats_.held_loops;
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
    const bool speculate = !held.holding && loop_changed_ && !options_.observer && !stop_;
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
        const bool whole = held.holding ? sweep_held(held.lines, held.text, Mode::Iterate)
                                   : sweep_file(start, start_line, end, Mode::Iterate);
        ++stats_.loop_sweeps;
        // A sweep that converged early would end as the one before it did.
        if (whole) leave_sweep();
    }
    // Once more, with the rules.
    if (!stop_) {
        set_state(entry);
        if (held.holding) sweep_held(held.lines, held.text, Mode::Rules);
        else sweep_file(start, start_line, end, Mode::Rules);
        leave_sweep();
        set_state(out);
    }
    if (held.holding && !stop_) main_.seek(end, end_line);
    end_loop();
}

// The first sweep over a loop from its `index`-th block on (the loop's head
// was visited), to the last block it reaches back from (`extent` grows as
// the sweep finds more); `held`, when given, holds each block it can.
bool Walk::first_sweep(uint32_t index, uint32_t& extent, HeldLoop* held) {
    Block b;
    LineRef line;
    const bool may_converge = !ahead_.empty();
    if (may_converge) start_ahead_in_loop();
    for (; !stop_ && main_.next_offset() <= extent && main_.next_offset() < flow_.end(); ++index) {
        if (may_converge)
            if (const size_t i = ahead_in_loop(); i != kNone && sweep_converges(i, extent, index)) return true;
        mark_loop(extent, index);
        if (!(held && held->holding))
            if (const uint32_t k = skim_run(probe_gap(index), uint64_t(extent) + 1)) {
                index += k - 1;
                continue;
            }
        if (!fetch(line)) break;
        converged(line.start, index, false);
        // A loop whose lines are held keeps each block whole (its other
        // sweeps visit them); one read again applies a plain move from its
        // values alone.
        const bool holding = held && held->holding;
        if (!holding && skim(line)) continue;
        parse(b, line, !holding && plain_ok_ && plain_may_apply());
        loop_head(b, line.start, extent);
        if (holding) held->hold(b, line, options_.held_loop_blocks);
        visit(b, line, Mode::Iterate);
    }
    return false;
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
    const bool may_converge = bringing_ && mode == Mode::Rules && !ahead_.empty();
    if (may_converge) start_ahead_in_loop();
    for (uint32_t index = 0; !stop_ && main_.next_offset() < end; ++index) {
        if (may_converge)
            if (const size_t i = ahead_in_loop(); i != kNone && try_converge_in_loop(i)) return false;
        if (speculating_ && loop_mark_next_ < loop_marks_.size()) {
            while (loop_mark_next_ < loop_marks_.size() && loop_marks_[loop_mark_next_].offset < main_.next_offset())
                ++loop_mark_next_;
            if (loop_mark_next_ < loop_marks_.size() && loop_marks_[loop_mark_next_].offset == main_.next_offset())
                take_loop_checkpoint();
        }
        if (mode == Mode::Iterate) {
            if (const uint32_t k = skim_run(probe_gap(index), end)) {
                index += k - 1;
                continue;
            }
            if (!fetch(line)) break;
            if (converged(line.start, index, true)) return false;
            if (skim(line)) continue;
            parse(b, line, plain_ok_ && plain_may_apply());
            visit(b, line, mode);
            continue;
        }
        const bool move = may_be_move();
        if (move && rules_idle())
            if (const uint32_t k = skim_run(kRunLines, end)) {
                index += k - 1;
                continue;
            }
        if (const uint32_t k = quiet_run(kRunLines, end, move)) {
            index += k - 1;
            continue;
        }
        const Next next = read_for_rules(b, line, move);
        if (next == Next::End) break;
        if (next == Next::Checked) continue;
        visit(b, line, mode);
    }
    return !stop_;
}

void Walk::set_state(const MaybeState& s) {
    ++flow_epoch_;
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
    if (labelled) {
        auto& defs = defs_[b.sequence->name];
        if (defs.empty() || defs.back() < offset) defs.push_back(offset);
        if (auto it = pending_name_.find(b.sequence->name); it != pending_name_.end()) by_name = &it->second;
    }
    const MaybeState* by_offset = pending_offset_.find(offset);
    if (!by_name && !by_offset) return;  // no path but the one falling into the block
    ++flow_epoch_;
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

const MacroCall* Walk::resolve(const Block& b, const ModalState& before) const {
    if (&b == resolved_block_ && parser_.last_again() && parser_.fills() == resolved_fills_) {
        resolve_call_again(b, before, call_);
        ++stats_.calls_again;
        return &call_;
    }
    resolved_block_ = nullptr;
    const uint64_t kept = arg_links_.modin.kept;
    if (!resolve_call(b, before, config_.catalog, &arg_links_, call_)) return nullptr;
    stats_.modin_calls_kept += arg_links_.modin.kept - kept;
    resolved_block_ = &b;
    resolved_fills_ = parser_.fills();
    MacroCall* call = &call_;
    if (options_.summaries && call->kind == CallKind::Call && !call->spec && !call->name.empty()) {
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
        read_whole(b, line);
        const MacroCall* call = resolve(b, unknown_);
        ModalState after;
        apply_block(b, call, config_.catalog, unknown_, after, &macro_ends_, &call_transfers_);
        check(BlockView{b, unknown_, after, call, false}, line, false);
        near_ = false;
        return;
    }
    ++stats_.transfers;
    const bool partial = &b == partial_;  // a plain move read in part
    const bool plain_line = partial || (parser_.last_plain() && &b == &block_buf_);
    if (plain_ok_ && (plain_line || is_plain_move_block(b)) && plain_move_state(*A_)) {
        // A plain move (semantics/transfer.h).
        apply_plain_move(b, plain_after());
        if (rules) check(BlockView{b, *A_, *B_, nullptr, true, true}, line, true);
        plain_done(line);
        return;
    }
    // A block read in part that is more than a plain move here (in a fixed
    // cycle, under MODIN) is parsed whole; a block read whole stays as it is.
    read_whole(b, line);
    const MacroCall* call = resolve(b, *A_);
    RepeatSpans spans;
    const Repeated again = rules ? repeated(b, call, *A_, line, spans) : Repeated::No;
    apply_block(b, call, config_.catalog, *A_, *B_, &macro_ends_, &call_transfers_, again == Repeated::Yes);
    near_ = false;
    if (rules) check(BlockView{b, *A_, *B_, call, true}, line, false, again, spans);
    leave(b, line);
}

ModalState& Walk::plain_after() {
    // A and B differ at most in what a plain move sets when `near_`, so those
    // fields make B equal to A again.
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
    return *B_;
}

void Walk::plain_done(const LineRef& line) {
    if (line.end() >= flow_.end()) bring_final(*B_);  // control falls off the last block
    std::swap(A_, B_);
    near_ = true;
}

// In a sweep without the rules, what visit does for a plain move that has no
// sequence name and that no loop edge flows into, made from the move's
// values alone: no block is built (FastLineParser::plain_move).
bool Walk::skim(const LineRef& line) {
    if (!apply_plain_values(line, true)) return false;
    plain_done(line);
    return true;
}

// What skim and skim_checked share: whether the line is a plain move that
// visit would apply as one, read from its values alone (into plain_move_);
// when it is, applied (B_ is the state after it).
bool Walk::apply_plain_values(const LineRef& line, bool names) {
    if (!plain_ok_ || !reachable_ || !plain_move_state(*A_)) return false;
    if (!parser_.plain_move(line, plain_move_)) return false;
    if (pending_offset_.find(line.start) || flow_.loop_at_head(line.start)) return false;
    // A name that paths may join at (enter) or that the rules cannot take so.
    if (!plain_move_.sequence.empty() &&
        (!names || (tracks_labels_ && flow_.is_referenced(plain_move_.sequence))))
        return false;
    partial_ = nullptr;
    ++stats_.transfers;
    apply_plain_move(plain_move_, line.line, plain_after());
    return true;
}

// The next line of the walk with the rules: a plain move checked from its
// values alone (skim_checked), or its block, read for visit. A plain move
// starts with its sequence name or with a G, X, Y, Z or F word
// (FastLineParser::plain_move); a line that starts otherwise (a comment, a
// tool change, a spindle code, a CALL) is not tried as one.
bool Walk::may_be_move() const {
    const std::string_view text = main_.buffered();
    size_t i = 0;
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\f' || text[i] == '\v')) ++i;
    if (i == text.size()) return true;  // not read yet
    switch (text[i]) {
        case 'N': case 'G': case 'X': case 'Y': case 'Z': case 'F':
        case 'n': case 'g': case 'x': case 'y': case 'z': case 'f':
            return true;
        default:
            return false;
    }
}

Walk::Next Walk::read_for_rules(Block& b, LineRef& line, bool move) {
    if (!fetch(line)) return Next::End;
    if (repeat_.armed && repeat_line(line)) return Next::Checked;  // the test first: no call on most lines
    if (!move || !rules_take_values()) {
        parse(b, line, moves_with_rules() && plain_may_apply());
        return Next::Block;
    }
    if (skim_checked(line)) return Next::Checked;
    parse(b, line, plain_may_apply());
    return Next::Block;
}

// Whether the next line starts as the block the rules saw last did, up to
// the value of its first position word, while that block may be repeated
// from the text (repeat_line): the walk reads it at once then, rather than
// first trying it as the start of a run of plain moves.
bool Walk::may_repeat() const {
    if (!repeat_.armed || !repeat_.from_text || repeat_.transfers != stats_.transfers) return false;
    const std::string_view text = main_.buffered();
    const size_t head = repeat_.count ? repeat_.cuts[0] : repeat_.text.size();
    return text.size() >= head && same_prefix(text.data(), repeat_.text.data(), head) == head;
}

// Whether the walk with the rules may read the next plain move from its
// values (skim_checked): in a batch analysis, while every rule that wants
// plain moves takes them so (Rule::takes_plain_values).
bool Walk::rules_take_values() const {
    if (!runs_ok_ || !moves_with_rules()) return false;
    for (const Rule* r : plain_rules_)
        if (r->wants_plain_moves() && !r->takes_plain_values()) return false;
    return true;
}

// In the walk with the rules, what visit and check do for a plain move
// without a sequence name, made from the move's values alone: no block is
// built; the rules that want plain moves see it through check_plain_move.
bool Walk::skim_checked(const LineRef& line) {
    if (!apply_plain_values(line, named_values_)) return false;
    ++stats_.value_blocks;
    if (!held_) positions_.set_current(line);
    block_ = nullptr;
    const PlainMoveView view{plain_move_, {line.start, line.start + static_cast<uint32_t>(line.text.size())},
                             line.line, *A_, *B_};
    const bool named = !plain_move_.sequence.empty();
    for (size_t i = 0; i < plain_rules_.size(); ++i)
        if (plain_rules_[i]->wants_plain_moves() || (named && plain_named_[i]))
            plain_rules_[i]->check_plain_move(*this, view);
    if (!findings_.empty()) flush();
    plain_done(line);
    return true;
}

// skim over a run of plain moves at once (FastLineParser::plain_run), in a
// batch analysis: in a sweep without the rules, or in the walk with them
// while no rule looks at plain moves (rules_idle): the lines from the next
// one on, while each is a plain move skim would apply, up to `max_lines`,
// the block before `start_limit` and the next block a loop edge or a loop
// head makes a join. Returns the blocks read.
uint32_t Walk::skim_run(uint32_t max_lines, uint64_t start_limit, FastLineParser::IntDigits int_digits) {
    run_over_ = false;
    if (max_lines == 0 || !runs_ok_) return 0;
    const std::string_view text = main_.buffered();
    // Most other lines are told by their first word (a sequence name, a
    // comment, a keyword): the walk tries a run at every such line.
    size_t first = 0;
    while (first < text.size() && text[first] == ' ') ++first;
    if (first == text.size() || std::string_view("XYZFG").find(text[first]) == std::string_view::npos) return 0;
    if (!plain_ok_ || !reachable_ || !plain_move_state(*A_)) return 0;
    // Only the last word of each address counts in absolute mode or an
    // unknown one; in incremental mode each move adds to the position.
    if (A_->distance.known && A_->distance.value != Distance::Absolute) return 0;
    // A run ends where fetch would look at the cancel flag (every 1024th line).
    if (options_.cancel) max_lines = std::min<uint32_t>(max_lines, 1024 - (walked_ & 1023));
    const uint64_t from = main_.next_offset();
    if (from >= UINT32_MAX) return 0;
    const uint32_t at = static_cast<uint32_t>(from);
    start_limit = std::min<uint64_t>({start_limit, flow_.end(), pending_offset_.next_at(at), flow_.next_loop_head(at)});
    // The last block of the program brings the final state (plain_done); fetch refuses a line past kMaxInputSize.
    const uint64_t end_limit = std::min<uint64_t>(flow_.end(), kMaxInputSize + 1);
    const uint32_t first_line = main_.next_line();
    const auto run = parser_.plain_run(text, at, max_lines, start_limit, end_limit, first_line,
                                       Positions::kCheckpointLines,
                                       [&](size_t start, uint32_t line) {
                                           positions_.note_line(LineRef{{}, {}, line, at + static_cast<uint32_t>(start)});
                                       },
                                       int_digits);
    run_over_ = run.over;
    if (run.lines == 0) return 0;
    main_.skip_buffered(run.bytes, run.lines, run.last_start);
    partial_ = nullptr;
    stats_.blocks_parsed += run.lines;
    stats_.transfers += run.lines;
    stats_.run_blocks += run.lines;
    apply_plain_move(run.last, first_line + run.lines - 1, plain_after());
    std::swap(A_, B_);
    near_ = true;
    if (options_.cancel && ((walked_ + run.lines) >> 10) != (walked_ >> 10) &&
        options_.cancel->load(std::memory_order_relaxed)) {
        walked_ += run.lines;
        fail(std::string(kCancelled));
        return run.lines;
    }
    walked_ += run.lines;
    return run.lines;
}

void Walk::read_whole(const Block& b, const LineRef& line) {
    if (&b != partial_) return;
    parser_.parse(line, *partial_);
    partial_ = nullptr;
}

// Whether the rules would do nothing on the plain moves to come, which
// carry no sequence name: none looks at plain moves, or none wants them now
// (Rule::wants_plain_moves, which changes only when a rule sees a block).
bool Walk::rules_idle() const {
    for (const Rule* r : plain_rules_)
        if (r->wants_plain_moves()) return false;
    return true;
}

bool Walk::rules_quiet(FastLineParser::IntDigits& digits) const {
    digits.fill(FastLineParser::kAnyDigits);
    bool any = false;
    for (size_t i = 0; i < plain_rules_.size(); ++i) {
        if (!plain_rules_[i]->wants_plain_moves()) continue;
        if (!plain_digits_[i]) return false;
        any = true;
        for (size_t k = 0; k < 3; ++k) digits[k] = std::min(digits[k], (*plain_digits_[i])[k]);
    }
    return any;
}

uint32_t Walk::quiet_run(uint32_t max_lines, uint64_t start_limit, bool move) {
    if (quiet_wait_ > 0) {
        --quiet_wait_;
        return 0;
    }
    if (!move) return 0;  // skim_run would stop at once
    FastLineParser::IntDigits digits;
    if (!rules_quiet(digits)) return 0;
    const uint32_t k = skim_run(max_lines, start_limit, digits);
    if (k > 0) {
        quiet_backoff_ = 0;
    } else if (run_over_) {
        quiet_backoff_ = std::min<uint32_t>(quiet_backoff_ * 2 + 1, 63);
        quiet_wait_ = quiet_backoff_;
    }
    return k;
}

void Walk::index_plain_rules() {
    ++flow_epoch_;
    repeat_.armed = false;
    repeat_rules_of_.clear();
    call_rules_.clear();
    for (auto& r : rules_)
        if (r->sees_plain_calls()) call_rules_.push_back(r.get());
    rules_for_listed_.fill(false);
    call_rules_of_.clear();
    last_call_rules_ = nullptr;
    plain_rules_.clear();
    plain_named_.clear();
    plain_digits_.clear();
    named_values_ = true;
    for (auto& r : rules_) {
        if (!r->sees_plain_moves(config_)) continue;
        plain_rules_.push_back(r.get());
        const bool named = r->meta().blocks == RuleBlocks::Named;
        plain_named_.push_back(named);
        if (named && !r->takes_plain_values()) named_values_ = false;
        std::optional<FastLineParser::IntDigits> digits;
        if (const auto below = r->quiet_below(config_)) {
            // A value with k digits before its point is below 10^k: the most
            // digits whose every value is below the bound (none below 1).
            digits.emplace();
            for (size_t k = 0; k < 3 && digits; ++k) {
                const double b = (*below)[k];
                if (!(b >= 1)) {
                    digits.reset();
                    break;
                }
                uint8_t n = 0;
                double p = 10;
                while (n < 15 && p <= b) ++n, p *= 10;
                (*digits)[k] = n == 15 ? FastLineParser::kAnyDigits : n;
            }
        }
        plain_digits_.push_back(digits);
    }
}

const std::vector<Rule*>& Walk::rules_for(uint8_t has) {
    std::vector<Rule*>& list = rules_for_[has];
    if (!rules_for_listed_[has]) {
        list.clear();
        for (auto& r : rules_)
            if (const uint8_t needs = r->block_needs(); needs == Rule::kEveryBlock || (needs & has))
                list.push_back(r.get());
        rules_for_listed_[has] = true;
    }
    return list;
}

const std::vector<Rule*>& Walk::call_rules_of(const MacroCall& call) {
    const std::pair<const MacroSpec*, CallKind> of{call.spec, call.kind};
    if (last_call_rules_ && last_call_of_ == of) return *last_call_rules_;
    auto [it, added] = call_rules_of_.try_emplace(of);
    if (added)
        for (Rule* r : call_rules_)
            if (r->sees_plain_calls_of(*call.spec, call.kind)) it->second.push_back(r);
    last_call_of_ = of;
    last_call_rules_ = &it->second;
    return it->second;
}

const std::vector<Rule*>& Walk::repeat_rules_of(const MacroSpec* spec, CallKind kind, bool plain_call) {
    auto [it, added] = repeat_rules_of_.try_emplace(std::tuple{spec, kind, plain_call});
    if (added) {
        for (const auto& r : rules_) {
            if (plain_call && (!r->sees_plain_calls() || !r->sees_plain_calls_of(*spec, kind))) continue;
            if (!r->quiet_on_repeat(config_, spec)) it->second.push_back(r.get());
        }
    }
    return it->second;
}

// Whether the rules may see the block as a repeat of the block before it
// (Rule::quiet_on_repeat), or see it so the next one may be: a block of words
// whose numbers are written out, perhaps one CALL or MODIN of a catalog
// macro, in a known plane; `spans` gets where the values of the plane's
// position words are in the line.
bool Walk::repeatable(const Block& b, const MacroCall* c, const ModalState& before, const LineRef& line,
                      RepeatSpans& spans) const {
    if (b.kind != LineKind::Block || b.program_name || b.sequence || b.block_delete || !b.assignments.empty() ||
        !b.errors.empty() || !before.plane.known || b.line_start != line.start)
        return false;
    if (c && (!c->spec || c->summary)) return false;
    const bool call_line = c && (c->kind == CallKind::Call || c->kind == CallKind::Modin);
    if (call_line ? b.statements.size() != 1 : !b.statements.empty()) return false;
    if (c && c->kind == CallKind::MCode) return false;
    const PlaneAxes axes = plane_axes(before.plane.value);
    spans.count = 0;
    const auto add = [&](const Word& w, char axis) {
        if (!w.number || spans.count == 2 || w.value_range.begin < line.start ||
            w.value_range.end > line.start + line.text.size())
            return false;
        spans.axis[spans.count] = axis;
        spans.at[spans.count++] = {w.value_range.begin - line.start, w.value_range.end - line.start};
        return true;
    };
    if (call_line) {
        const int plane = plane_number(before.plane.value);
        for (const char axis : {axes.first, axes.second}) {
            const ArgSpec* a = c->spec->position_arg(plane, axis);
            const MacroArg* m = a ? c->given(*a) : nullptr;
            if (m && m->word && !add(*m->word, axis)) return false;
        }
        if (spans.count == 2 && spans.at[1].begin < spans.at[0].begin) {
            std::swap(spans.at[0], spans.at[1]);
            std::swap(spans.axis[0], spans.axis[1]);
        }
    } else {
        for (const Word& w : b.words)
            if (w.address.size() == 1 && (w.address[0] == axes.first || w.address[0] == axes.second) &&
                !add(w, w.address[0]))
                return false;
        // A block that names no position in the plane (a tool change, a
        // spindle or coolant code) is not written line after line: it is
        // not compared with the block after it.
        if (spans.count == 0) return false;
    }
    return true;
}

// Whether the block repeats the one the rules saw just before it: the same
// line but for the values of the plane's position words, with no block and
// no other state between, after a block that was quiet and left the state
// as it found it but for the position in the plane (Walk::check). Then the
// state before it is that block's but for that position, and the transfer
// step may take the memos that block left as they are (apply_block).
Walk::Repeated Walk::repeated(const Block& b, const MacroCall* c, const ModalState& before, const LineRef& line,
                              RepeatSpans& spans) const {
    if (!repeatable(b, c, before, line, spans)) return Repeated::No;
    const MacroSpec* spec = c ? c->spec : nullptr;
    const CallKind kind = c ? c->kind : CallKind::None;
    if (!repeat_.armed || repeat_.transfers + 1 != stats_.transfers || repeat_.epoch != flow_epoch_ ||
        repeat_.spec != spec || repeat_.kind != kind || repeat_.count != spans.count)
        return Repeated::May;
    const std::string_view t = line.text;
    const std::string& k = repeat_.text;
    uint32_t cut_len = 0;
    for (uint8_t i = 0; i < spans.count; ++i) cut_len += spans.at[i].size();
    if (t.size() - cut_len != k.size()) return Repeated::May;
    uint32_t from = 0, at = 0;
    for (uint8_t i = 0; i <= spans.count; ++i) {
        const uint32_t to = i < spans.count ? spans.at[i].begin : static_cast<uint32_t>(t.size());
        const uint32_t cut = i < spans.count ? repeat_.cuts[i] : static_cast<uint32_t>(k.size());
        if (cut - at != to - from || t.compare(from, to - from, k, at, cut - at) != 0) return Repeated::May;
        at = cut;
        if (i < spans.count) from = spans.at[i].end;
    }
    return Repeated::Yes;
}

bool Walk::repeats_text(std::string_view t, std::array<double, 2>* values) const {
    return repeat_length(t, values) == t.size();
}

size_t Walk::repeat_length(std::string_view t, std::array<double, 2>* values) const {
    const std::string& k = repeat_.text;
    uint32_t from = 0, at = 0;  // in t, in k
    for (uint8_t i = 0;; ++i) {
        const uint32_t cut = i < repeat_.count ? repeat_.cuts[i] : static_cast<uint32_t>(k.size());
        const uint32_t len = cut - at;
        if (t.size() - from < len || same_prefix(t.data() + from, k.data() + at, len) != len) return kNoRepeat;
        from += len;
        if (i == repeat_.count) return from;
        at = cut;
        const uint32_t end =
            values ? FastLineParser::plain_value(t, from, (*values)[i]) : FastLineParser::plain_value_end(t, from);
        if (end == from) return kNoRepeat;
        from = end;
    }
}

// The lines from the next one on that repeat_line would take, up to
// `max_lines`, told from the input's buffer: each is matched with
// repeat_.text there, and its line break looked at after the match (LF or
// CR LF; any other line is left to fetch). What fetch and repeat_line do
// for each is done here: the state repeat_line asks about stays as it is
// through the run, and it ends before the first line where repeat_line
// would refuse (where paths join, where a loop starts, at the end of the
// program, at a value a rule is not quiet for) and, when the walk may be
// cancelled, where fetch would look at the flag. Returns the lines passed
// over.
uint32_t Walk::repeat_run(uint32_t max_lines) {
    if (!repeat_.armed || !repeat_.from_text || !runs_ok_ || ahead_next_ < ahead_.size()) return 0;
    if (repeat_.transfers != stats_.transfers || repeat_.epoch != flow_epoch_ || !reachable_) return 0;
    const uint64_t from = main_.next_offset();
    if (from >= UINT32_MAX) return 0;
    if (options_.cancel) max_lines = std::min<uint32_t>(max_lines, 1024 - (walked_ & 1023));
    const std::string_view text = main_.buffered();
    const uint32_t at = static_cast<uint32_t>(from);
    const uint64_t start_limit = std::min(pending_offset_.next_at(at), flow_.next_loop_head(at));
    // fetch refuses a line past kMaxInputSize; repeat_line, one that ends the program.
    const uint64_t end_limit = std::min<uint64_t>(flow_.end(), kMaxInputSize + 1);
    const uint32_t first_line = main_.next_line();
    const bool want_values = repeat_.sets_plane || repeat_.by_values;
    std::array<double, 2> values{};
    size_t pos = 0, last_start = 0;
    uint32_t lines = 0;
    while (lines < max_lines) {
        const std::string_view rest = text.substr(pos);
        const size_t len = repeat_length(rest, want_values ? &values : nullptr);
        if (len == kNoRepeat || len > kMaxLineLength) break;
        size_t term = 0;
        if (len < rest.size() && rest[len] == '\n') term = 1;
        else if (len + 1 < rest.size() && rest[len] == '\r' && rest[len + 1] == '\n') term = 2;
        else break;
        const uint64_t start = from + pos;
        if (start >= start_limit || start + len + term >= end_limit) break;
        if (repeat_.by_values && !repeat_.quiet_at(values)) break;
        const uint32_t line = first_line + lines;
        if (line % Positions::kCheckpointLines == 0)
            positions_.note_line(LineRef{{}, {}, line, at + static_cast<uint32_t>(pos)});
        if (repeat_.sets_plane) {
            // A_ is the state the block before left (Walk::leave).
            for (uint8_t i = 0; i < repeat_.count; ++i) *A_->axis_ref(repeat_.axes[i]) = Val<double>::of(values[i]);
            near_ = false;
        }
        last_start = pos;
        pos += len + term;
        ++lines;
    }
    if (lines == 0) return 0;
    main_.skip_buffered(pos, lines, last_start);
    stats_.blocks_parsed += lines;
    stats_.transfers += lines;
    stats_.repeats += lines;
    stats_.text_repeats += lines;
    repeat_.transfers = stats_.transfers;
    if (options_.cancel && ((walked_ + lines) >> 10) != (walked_ >> 10) &&
        options_.cancel->load(std::memory_order_relaxed)) {
        walked_ += lines;
        fail(std::string(kCancelled));
        return lines;
    }
    walked_ += lines;
    return lines;
}

// Such a line is what visit would find a repeat (Walk::repeated) of a block
// that no rule sees then, and apply_block would leave the state as it is
// (repeat_leaves_state for a CALL, repeat_keeps_state for a hole or a
// positioning block, asked when the block was armed): visit is left out.
// Only in a batch walk outside loops (no checkpoint, no observer), where no
// path joins at the line and control does not fall off the program after it.
bool Walk::repeat_line(const LineRef& line) {
    std::array<double, 2> values{};
    if (!repeat_.armed || !repeat_.from_text || repeat_.transfers != stats_.transfers ||
        repeat_.epoch != flow_epoch_ || !reachable_ || line.end() >= flow_.end() ||
        !repeats_text(line.text, repeat_.sets_plane || repeat_.by_values ? &values : nullptr) ||
        pending_offset_.find(line.start) || flow_.loop_at_head(line.start) ||
        (repeat_.by_values && !repeat_.quiet_at(values)))
        return false;
    if (repeat_.sets_plane) {
        // A_ is the state the block before left (Walk::leave).
        for (uint8_t i = 0; i < repeat_.count; ++i) *A_->axis_ref(repeat_.axes[i]) = Val<double>::of(values[i]);
        near_ = false;
    }
    ++stats_.transfers;
    ++stats_.repeats;
    ++stats_.text_repeats;
    repeat_.transfers = stats_.transfers;
    return true;
}

// Whether the state after the block is the state before it but for the
// position in the plane.
bool Walk::same_apart_from_plane(const BlockView& view) const {
    if (&view.before != A_ || &view.after != B_) return false;
    const PlaneAxes axes = plane_axes(view.before.plane.value);
    Val<double>* first = B_->axis_ref(axes.first);
    Val<double>* second = B_->axis_ref(axes.second);
    const Val<double> keep_first = *first, keep_second = *second;
    *first = A_->axis(axes.first);
    *second = A_->axis(axes.second);
    const bool same = *A_ == *B_;
    *first = keep_first;
    *second = keep_second;
    return same;
}

void Walk::check(const BlockView& view, const LineRef& line, bool plain, Repeated again, const RepeatSpans& spans) {
    if (plain) {
        // Where paths join (a name a jump or N word names), the state may not be
        // what a rule saw last: every rule that sees plain moves sees the move.
        const bool named = view.block.sequence.has_value();
        const bool join = named && tracks_labels_ && flow_.is_referenced(view.block.sequence->name);
        for (size_t i = 0; i < plain_rules_.size(); ++i)
            if (join || plain_rules_[i]->wants_plain_moves() || (named && plain_named_[i]))
                plain_rules_[i]->check_block(*this, view);
        repeat_.armed = false;
    } else {
        const bool plain_call = is_plain_call(view);
        // A repeat of the block before (Walk::repeated) whose state after it
        // is, as that one's was, the state before it but for the position in
        // the plane: the rules see what they saw on that block, moved.
        const bool repeat = again == Repeated::Yes && same_apart_from_plane(view);
        const uint64_t reports = reports_;
        if (repeat) {
            ++stats_.repeats;
            for (Rule* r : *repeat_.rules) r->check_block(*this, view);
        } else if (plain_call) {
            for (Rule* r : call_rules_of(*view.call)) r->check_block(*this, view);
        } else {
            const uint8_t has = Rule::what_block_has(view.block) | (view.call ? Rule::kCall : 0) |
                                (active_cycle(view.before) ? Rule::kCycleBefore : 0) |
                                (active_cycle(view.after) ? Rule::kCycleAfter : 0);
            for (Rule* r : rules_for(has)) r->check_block(*this, view);
        }
        // The state compared once: before the rules for a repeat, after them
        // for a block that may start one (and then only when it was quiet).
        repeat_.armed =
            again != Repeated::No && reports_ == reports && (repeat || same_apart_from_plane(view));
        if (repeat_.armed) {
            repeat_.transfers = stats_.transfers;
            repeat_.epoch = flow_epoch_;
            if (!repeat) {
                repeat_.spec = view.call ? view.call->spec : nullptr;
                repeat_.kind = view.call ? view.call->kind : CallKind::None;
                repeat_.count = spans.count;
                repeat_.text.clear();
                uint32_t from = 0;
                for (uint8_t i = 0; i < spans.count; ++i) {
                    repeat_.text.append(line.text.substr(from, spans.at[i].begin - from));
                    repeat_.cuts[i] = static_cast<uint32_t>(repeat_.text.size());
                    from = spans.at[i].end;
                }
                repeat_.text.append(line.text.substr(from));
                repeat_.rules = &repeat_rules_of(repeat_.spec, repeat_.kind, plain_call);
            }
            // Asked again after a repeat: a rule that saw it may be quiet now,
            // and the transfer step's memos are those the block left.
            repeat_.sets_plane = false;
            repeat_.from_text = runs_ok_ && !options_.observer && !in_loop_ && !held_;
            repeat_.by_values = false;
            repeat_.quiet = {};
            for (Rule* r : *repeat_.rules) {
                if (!repeat_.from_text) break;
                if (r->quiet_on_repeat_of(view)) continue;
                std::array<Rule::QuietRange, 2> quiet{};
                if (!r->repeat_values_decide(config_, view, spans.axis, spans.count, quiet)) {
                    repeat_.from_text = false;
                    break;
                }
                repeat_.by_values = true;
                for (size_t i = 0; i < 2; ++i) {
                    repeat_.quiet[i].lo = std::max(repeat_.quiet[i].lo, quiet[i].lo);
                    repeat_.quiet[i].hi = std::min(repeat_.quiet[i].hi, quiet[i].hi);
                }
            }
            if (repeat_.from_text && repeat_.kind == CallKind::Call) {
                repeat_.from_text =
                    plain_call && repeat_leaves_state(*repeat_.spec, *B_, call_transfers_, macro_ends_);
            } else if (repeat_.from_text && !repeat_keeps_state(view.block, view.call, *B_, macro_ends_)) {
                // Or the repeat moves the tool to its values (the same spans, in the same order).
                repeat_.sets_plane = repeat_.from_text = repeat_sets_plane(view.block, view.call, *B_);
                repeat_.axes = spans.axis;
            }
        }
    }
    if (options_.observer && !options_.observer->block(view, line)) stop_ = true;
    if (!findings_.empty()) flush();
}

// ------------------------------------------------------------ speculation

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
    if (converged_) return true;  // the previous analysis's walk from there on stood
    if (end_speculation()) return true;
    rules_ = std::move(before.rules);
    index_plain_rules();
    folder_ = std::move(before.folder);
    filter_->set_used(before.used);
    if (fingerprints_) occurrences_ = std::move(before.occurrences);
    loop_changed_ = true;
    return false;
}


std::string run_engine(const std::string& path, ByteSource& src, const Config& config, const EngineOptions& options,
                       DiagnosticSink& sink, EngineStats* stats) {
    EngineStats own;
    Walk walk(path, src, config, options, sink, stats ? *stats : own);
    return walk.run();
}

}  // namespace osplint
