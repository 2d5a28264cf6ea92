// Checkpoints of the walk (engine/walk.h): taken between top-level blocks
// and inside loops, moved to an edited text, resumed at.
#include "engine/walk.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <type_traits>
#include <utility>

#include "engine/moves.h"
#include "engine/summaries.h"

namespace osplint {

using namespace moves;

namespace {

int64_t line_ends(std::string_view s) {
    int64_t n = 0;
    for (const char* p = s.data(); p < s.data() + s.size(); ++p)
        if (ends_line(p, s.data() + s.size())) ++n;
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
    const std::string_view old_part = before.substr(prefix, before.size() - suffix - prefix);
    const std::string_view new_part = after.substr(prefix, after.size() - suffix - prefix);
    c.lines = line_ends(new_part) - line_ends(old_part);
    // One plain line changed: no line break replaced or written, and the
    // line, which a break ends in both texts, holds no outline item in either.
    auto has_break = [](std::string_view s) { return find_line_break(s.data(), s.data() + s.size()) != nullptr; };
    if (!has_break(old_part) && !has_break(new_part)) {
        size_t start = prefix;
        while (start > 0 && before[start - 1] != '\n' && before[start - 1] != '\r') --start;
        auto plain = [&](std::string_view text) {
            const char* const b = text.data() + start;
            const char* const brk = find_line_break(b, text.data() + text.size());
            return brk && static_cast<size_t>(brk - b) < kMaxLineLength && !may_hold_outline_item(b, brk, true);
        };
        c.plain_line = plain(before) && plain(after);
        c.line_start = static_cast<uint32_t>(start);
        const char* const end = before.data() + before.size();
        if (const char* brk = find_line_break(before.data() + prefix, end)) {
            const char* next = brk + 1;
            if (*brk == '\r' && next < end && *next == '\n') ++next;
            // The break is in the unchanged suffix of both texts.
            if (static_cast<size_t>(brk - before.data()) >= before.size() - suffix)
                c.next_line = static_cast<uint32_t>(next - before.data());
        }
    }
    return c;
}

std::optional<LineEditMove> line_edit_move(const TextChange& e) {
    if (!e.next_line || e.lines != 0) return std::nullopt;
    return LineEditMove{e.line_start, e.next_line, e.bytes};
}

bool move_diagnostic(Diagnostic& d, const LineEditMove& m) {
    if (!m.range(d.range.bytes)) return false;
    for (Note& n : d.notes)
        if (n.range && !m.range(n.range->bytes)) return false;
    for (Fix& f : d.fixes)
        for (TextEdit& t : f.edits)
            if (!m.range(t.range.bytes)) return false;
    if (d.folded_last && !m.range(d.folded_last->bytes)) return false;
    return true;
}

std::optional<FileOutline> moved_outline(const FileOutline& old, const TextChange& e) {
    if (!e.plain_line || !old.ok() || old.programs.empty() || !old.first_block || *old.first_block >= e.line_start ||
        e.prefix < e.line_start || e.prefix > old.size || e.suffix > old.size - e.prefix)
        return std::nullopt;
    for (const DirectiveSite& d : old.directives)
        if (d.offset < e.line_start && (!d.target || *d.target >= e.line_start)) return std::nullopt;
    // Every position the outline holds starts a line or lies in a line other
    // than the changed one: those after it move with the text.
    auto at = [&](uint32_t& x) {
        if (x > e.line_start) x = static_cast<uint32_t>(static_cast<int64_t>(x) + e.bytes);
    };
    auto range = [&](ByteRange& r) {
        at(r.begin);
        at(r.end);
    };
    FileOutline out = old;
    for (ProgramOutline& p : out.programs) {
        at(p.offset);
        range(p.name_range);
        for (FlowSite& f : p.flow) {
            at(f.offset);
            at(f.next);
        }
    }
    for (DirectiveSite& d : out.directives) {
        at(d.offset);
        for (ByteRange& r : d.comments) range(r);
        if (d.target) at(*d.target);
    }
    out.size = static_cast<uint64_t>(static_cast<int64_t>(old.size) + e.bytes);
    out.lines_parsed = 0;
    return out;
}

CheckpointPlace checkpoint_place(const WalkCheckpoint& c) {
    return {c.frozen->offset, c.frozen->line, c.frozen->diagnostics, c.frozen->suppressed};
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
    c->pending_offset = pending_offset_.map();
    c->frozen = freeze();
    c->summaries = walk_summaries_;
    options_.checkpoints->push_back(std::move(c));
    next_checkpoint_ = main_.next_offset() + options_.checkpoint_every;
}

// The checkpoints of the previous analysis that are still valid for this
// text, moved to it; the walk starts at the last of them. Returns whether it
// does (false: from the start, with none of the old checkpoints).
bool Walk::resume_from_checkpoints() {
    std::vector<Checkpoint> old = std::move(*options_.checkpoints);
    options_.checkpoints->clear();
    if (!options_.checkpoint_every) return false;
    // The summaries the findings kept from the previous analysis rest on.
    const LocalSummaries* merged = nullptr;  // the checkpoints of one analysis share theirs
    for (const Checkpoint& c : old)
        if (walk_summaries_ && c->summaries && c->summaries.get() != merged) {
            walk_summaries_->used = summaries_union(walk_summaries_->used, c->summaries->used);
            merged = c->summaries.get();
        }
    find_ahead(old);
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
        moved_c->summaries = walk_summaries_;
        bool ok = true;
        for (const auto& [offset, state] : c->pending_offset) {
            const auto m = moved_block(offset, c->outline->size, e);
            if (!m) ok = false;
            else moved_c->pending_offset.emplace(*m, state);
        }
        if (!ok) break;
        if (c->loop) {
            if (c->loop_moves.size() >= kMaxLoopMoves) break;
            moved_c->loop = c->loop;
            moved_c->loop_moves = c->loop_moves;
            moved_c->loop_moves.emplace_back(c->outline->size, e);
            moved_c->loop_exact = false;
            if (c->loop_exact) moved_c->exact_before = c->loop;
        }
        options_.checkpoints->push_back(std::move(moved_c));
    }
    // The last checkpoint, inside a loop: its states moved to this text (or
    // the one before it, when an offset it holds was in a part replaced since).
    while (!options_.checkpoints->empty() && options_.checkpoints->back()->loop) {
        Checkpoint& last = options_.checkpoints->back();
        std::shared_ptr<const LoopCheckpoint> l = last->loop;
        for (const auto& [size, change] : last->loop_moves)
            if (l) l = move_loop(*l, KeysMove{size, change});
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
    for (const auto& r : f.rules) rules_.push_back(r->clone());
    index_plain_rules();
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

// ------------------------------------------------- checkpoints inside loops

SweepState Walk::sweep_state(uint32_t extent, uint32_t index) const {
    SweepState s;
    s.flowing = MaybeState{reachable_, reachable_ ? *A_ : ModalState{}};
    s.join = join_;
    s.pending_name = pending_name_;
    s.pending_offset = pending_offset_.map();
    s.defs = defs_;
    s.final_state = final_state_;
    s.probes = probes_;
    s.join_stamps = join_stamps_;
    s.stamp = stamp_;
    s.extent = extent;
    s.index = index;
    s.loop_changed = loop_changed_;
    s.next = static_cast<uint32_t>(main_.next_offset());
    s.next_line = main_.next_line();
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

// The walk with the rules after a first sweep, frozen. The findings it keeps
// aside count as handed over: they are, before any finding after the block,
// if the walk stands.
std::shared_ptr<FrozenWalk> Walk::freeze_in_loop() {
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
    return f;
}

// In the walk with the rules after the first sweep, before a block the first
// sweep marked.
void Walk::take_loop_checkpoint() {
    const LoopMark& m = loop_marks_[loop_mark_next_++];
    auto f = freeze_in_loop();
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
    c->summaries = walk_summaries_;
    c->loop = std::move(l);
    loop_checkpoints_.push_back(std::move(c));
}

// After an edit inside one line after the checkpoint `c` inside a loop, whose
// first sweep from there (`now`) left the states it left before the edit
// (moved): the walk with the rules reaches every block of the loop before
// the edit in the state it did, so the checkpoints kept before the edit whose
// states came from that sweep are those of the new text, moved; they are
// made so (and may be where a later analysis ends early: loop_exact).
void Walk::renew_kept(const WalkCheckpoint& c, const SweepState& now) {
    if (!may_converge_ || !c.exact_before) return;
    const SweepState* before = c.exact_before->after_first.get();
    const auto moved = move_sweep(*before, LineMove{*edit_move_});
    if (!moved || !same_sweep_end(now, *moved)) return;
    for (Checkpoint& k : *options_.checkpoints) {
        if (!k->loop || !k->exact_before || k->exact_before->after_first.get() != before) continue;
        auto renewed = std::make_shared<WalkCheckpoint>();
        renewed->outline = shared_outline_;
        renewed->summaries = walk_summaries_;
        renewed->frozen = moved_frozen(*k->frozen, *k->frozen, *k->frozen);
        renewed->loop = move_loop(*k->exact_before, LineMove{*edit_move_}, &moved_sweeps_);
        if (!renewed->frozen || !renewed->loop) continue;
        k = std::move(renewed);
        ++stats_.checkpoints_renewed;
    }
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
    first_sweep(l.first->index, extent, nullptr);
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
    renew_kept(c, *now);
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
    if (converged_) ++stats_.loop_resumes;
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
    index_plain_rules();
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

}  // namespace osplint
