// Ending the walk early after an edit inside one line (EngineOptions::
// converged): where the walk's state is again the one the previous analysis
// had at one of its checkpoints, moved by the edit, the rest of that
// analysis stands.
#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <utility>

#include "engine/moves.h"
#include "engine/summaries.h"
#include "engine/walk.h"

namespace osplint {

using namespace moves;

// The previous analysis's checkpoints after the changed line, when the walk
// may end at one of them (EngineOptions::converged).
void Walk::find_ahead(const std::vector<Checkpoint>& old) {
    ahead_.clear();
    ahead_at_.clear();
    ahead_loops_.clear();
    moved_sweeps_.clear();
    ahead_next_ = 0;
    edit_move_ = line_edit_move(options_.edit);
    may_converge_ = edit_move_ && options_.converged && !options_.observer && !folder_.enabled() && walk_summaries_;
    if (!may_converge_) return;
    const FileOutline* same = nullptr;  // the outline found the same as this text's, moved
    for (const Checkpoint& c : old) {
        const FrozenWalk& f = *c->frozen;
        if (!c->outline || !c->summaries || !c->summaries->complete || f.offset < edit_move_->next_line ||
            (c->loop && !c->loop_exact) ||
            f.config != &config_ || f.only_rules != options_.only_rules || f.run_rules != options_.run_rules ||
            f.folder || f.occurrences.has_value() != fingerprints_)
            continue;
        if (c->outline.get() != same) {
            if (c->outline->programs.empty() ||
                !same_structure(*c->outline, outline_, c->outline->programs.size() - 1, options_.edit))
                continue;
            same = c->outline.get();
        }
        uint32_t at = f.offset;
        if (!edit_move_->block(at) || (!ahead_at_.empty() && at < ahead_at_.back())) continue;
        ahead_.push_back(c);
        ahead_at_.push_back(at);
    }
    ahead_loops_.resize(ahead_.size());
}

// At a block boundary of the top level at or past the next checkpoint ahead:
// ends the walk there when its state is that checkpoint's, moved.
void Walk::try_converge() {
    while (ahead_next_ < ahead_.size()) {
        const size_t i = ahead_next_;
        if (main_.next_offset() < ahead_at_[i]) return;
        ++ahead_next_;
        if (main_.next_offset() == ahead_at_[i] && !ahead_[i]->loop && !in_loop_ && !speculating_ && !bringing_ &&
            same_as_moved(*ahead_[i])) {
            take_checkpoint();
            const Checkpoint here = options_.checkpoints->back();
            converge_at(i + 1, here->frozen, here);
            return;
        }
    }
}

// The checkpoint ahead_[i] inside a loop, moved to this text (nullptr: it
// cannot be).
std::shared_ptr<const LoopCheckpoint> Walk::ahead_loop(size_t i) {
    auto& l = ahead_loops_[i];
    if (l) return *l;
    const WalkCheckpoint& c = *ahead_[i];
    l = move_loop(*c.loop, LineMove{*edit_move_}, &moved_sweeps_);
    return *l;
}

void Walk::start_ahead_in_loop() {
    ahead_in_loop_ = static_cast<size_t>(
        std::lower_bound(ahead_at_.begin(), ahead_at_.end(), main_.next_offset()) - ahead_at_.begin());
}

size_t Walk::ahead_in_loop() {
    const uint64_t o = main_.next_offset();
    while (ahead_in_loop_ < ahead_.size() && ahead_at_[ahead_in_loop_] < o) ++ahead_in_loop_;
    for (size_t i = ahead_in_loop_; i < ahead_.size() && ahead_at_[i] == o; ++i)
        if (ahead_[i]->loop && ahead_[i]->frozen->program == program_index_) return i;
    return kNone;
}

// Whether the first sweep over the loop, before its `index`-th block, is in
// the state `s` holds.
bool Walk::sweep_is(const SweepState& s, uint32_t extent, uint32_t index) const {
    return s.index == index && s.extent == extent && s.loop_changed == loop_changed_ && s.stamp == stamp_ &&
           same_state(s.flowing, MaybeState{reachable_, reachable_ ? *A_ : ModalState{}}) &&
           same_state(s.final_state, final_state_) && same_states(s.join, join_) &&
           same_states(s.pending_offset, pending_offset_.map()) && same_states(s.pending_name, pending_name_) &&
           s.defs == defs_ && same_states(s.probes, probes_) &&
           s.join_stamps == join_stamps_;
}

// In the first sweep over a loop, before the block where the previous
// analysis took its checkpoint ahead_[i]: when the sweep is in the state that
// analysis's first sweep was in there, the rest of it would be that sweep's.
// It ends at once, with the states that sweep left; the marks further on are
// the ones it took.
bool Walk::sweep_converges(size_t i, uint32_t& extent, uint32_t index) {
    const auto l = ahead_loop(i);
    if (!l || l->head != loop_start_ || l->head_line != loop_head_line_ || !same_state(l->entry, loop_entry_) ||
        !sweep_is(*l->first, extent, index))
        return false;
    restore_sweep(*l->after_first);
    extent = l->after_first->extent;
    main_.seek(l->after_first->next, l->after_first->next_line);
    while (!loop_marks_.empty() && loop_marks_.back().offset >= ahead_at_[i]) {
        loop_mark_cost_ -= loop_marks_.back().cost;
        loop_marks_.pop_back();
    }
    for (size_t k = i; k < ahead_.size(); ++k) {
        if (!ahead_[k]->loop || ahead_[k]->frozen->program != program_index_) continue;
        const auto lk = ahead_loop(k);
        if (!lk || lk->head != loop_start_ || lk->after_first != l->after_first) continue;
        const SweepState& m = *lk->first;
        const size_t cost = 1 + m.join.size() + m.pending_offset.size() + m.pending_name.size() + m.probes.size() +
                            m.join_stamps.size();
        loop_marks_.push_back({ahead_at_[k], lk->first, cost});
        loop_mark_cost_ += cost;
    }
    ++stats_.sweep_convergences;
    return true;
}

// In the walk with the rules over a loop after its first sweep, before the
// block where the previous analysis took its checkpoint ahead_[i]: ends the
// walk there when its state (the one the first sweep left included) is that
// checkpoint's, moved. The previous analysis's walk went on from there and
// stood; so would this one.
bool Walk::try_converge_in_loop(size_t i) {
    if (loop_changed_ || speculation_overflow_ || !after_first_) return false;
    const auto l = ahead_loop(i);
    if (!l || l->head != loop_start_ || l->head_line != loop_head_line_ || !same_state(l->entry, loop_entry_) ||
        !same_sweep_end(*after_first_, *l->after_first) || !same_states(join_, l->join) ||
        !same_states(brought_name_, l->brought_name) || !same_states(brought_offset_, l->brought_offset) ||
        !same_state(brought_final_, l->brought_final) || !same_as_moved(*ahead_[i]))
        return false;
    const auto at = freeze_in_loop();
    Checkpoint here = moved_ahead(i, *ahead_[i]->frozen, *at);
    if (!here) return false;
    end_speculation();
    converge_at(i + 1, at, std::move(here));
    ++stats_.loop_convergences;
    return true;
}

// Whether the walk now is in the state `old` holds, moved by the edit.
bool Walk::same_as_moved(const WalkCheckpoint& old) const {
    const FrozenWalk& f = *old.frozen;
    const LineEditMove& m = *edit_move_;
    if (f.program != program_index_ || f.seen_main != seen_main_ || f.subprogram != subprogram_) return false;
    Program p = f.program_info;
    if (!m.range(p.name_range) || !(p == program_)) return false;
    if (!same_moved(MaybeState{reachable_, reachable_ ? *A_ : ModalState{}}, f.flowing, m) ||
        !same_moved(final_state_, f.final_state, m))
        return false;
    // Inside a loop, the states left at blocks further on are the first
    // sweep's with what the walk brought to them (compared by the caller).
    if (!old.loop && !same_moved_map(pending_offset_.map(), old.pending_offset, m)) return false;
    if (pending_name_.size() != f.pending_name.size()) return false;
    for (const auto& [name, st] : f.pending_name) {
        const auto it = pending_name_.find(name);
        if (it == pending_name_.end() || !same_moved(it->second, st, m)) return false;
    }
    if (defs_.size() != f.defs.size()) return false;
    for (const auto& [name, offsets] : f.defs) {
        const auto it = defs_.find(name);
        if (it == defs_.end() || it->second.size() != offsets.size()) return false;
        for (size_t i = 0; i < offsets.size(); ++i) {
            uint32_t o = offsets[i];
            if (!m.block(o) || o != it->second[i]) return false;
        }
    }
    if (filter_->used() != f.used || rules_.size() != f.rules.size()) return false;
    if (fingerprints_ && !occurrences_.same_counts(*f.occurrences)) return false;  // the kept findings' fingerprints
    for (size_t i = 0; i < rules_.size(); ++i) {
        if (rules_[i]->meta().id != f.rules[i]->meta().id) return false;
        const auto moved = moved_rule(*f.rules[i], m);
        if (!moved || !rules_[i]->same_state(*moved)) return false;
    }
    // The findings kept from there on rest on the summaries of the file's own
    // programs the previous analysis used: each must leave the same behind now.
    for (const auto& [name, used] : old.summaries->used) {
        const SubprogramSummary* now = local_summary(name);
        if (!(now && used ? same_effect(*now, *used) : now == used)) return false;
    }
    return true;
}

// A checkpoint of the previous analysis after the one the walk ended at
// (`f`, there `at` now), moved to this text (nullptr: it cannot be).
std::shared_ptr<FrozenWalk> Walk::moved_frozen(const FrozenWalk& f2, const FrozenWalk& f, const FrozenWalk& at) const {
    const LineEditMove& m = *edit_move_;
    auto g = std::make_shared<FrozenWalk>();
    g->config = f2.config;
    g->only_rules = f2.only_rules;
    g->run_rules = f2.run_rules;
    g->program = f2.program;
    g->offset = f2.offset;
    if (!m.block(g->offset)) return nullptr;
    g->line = f2.line;
    g->diagnostics = f2.diagnostics - f.diagnostics + at.diagnostics;
    g->suppressed = f2.suppressed - f.suppressed + at.suppressed;
    // The findings kept point at no byte of the changed line.
    uint32_t reach = f2.reach;
    if (!m.block(reach)) reach = m.line_start;
    g->reach = std::max(reach, at.reach);
    g->local_used = summaries_union(f2.local_used, at.local_used);
    g->seen_main = f2.seen_main;
    g->subprogram = f2.subprogram;
    g->program_info = f2.program_info;
    if (!m.range(g->program_info.name_range)) return nullptr;
    auto state = [&](const MaybeState& s, MaybeState& out) {
        auto moved = moved_state(s, m);
        if (moved) out = std::move(*moved);
        return moved.has_value();
    };
    if (!state(f2.flowing, g->flowing) || !state(f2.final_state, g->final_state)) return nullptr;
    for (const auto& [name, st] : f2.pending_name)
        if (!state(st, g->pending_name[name])) return nullptr;
    g->defs = f2.defs;
    for (auto& [name, offsets] : g->defs)
        for (uint32_t& o : offsets)
            if (!m.block(o)) return nullptr;
    for (const auto& r : f2.rules) {
        auto moved = moved_rule(*r, m);
        if (!moved) return nullptr;
        g->rules.push_back(std::move(moved));
    }
    g->used = f2.used;
    g->occurrences = f2.occurrences;
    g->marks = f2.marks;
    for (auto& [offset, line] : g->marks.offsets_and_lines) {
        uint32_t o = static_cast<uint32_t>(offset);
        if (!m.block(o)) return nullptr;
        offset = o;
    }
    return g;
}

// A checkpoint of the previous analysis ahead of the edit, moved to this text
// (nullptr: it cannot be), `f` being the one the walk ends at and `at` the
// walk there.
Checkpoint Walk::moved_ahead(size_t i, const FrozenWalk& f, const FrozenWalk& at) {
    const WalkCheckpoint& c = *ahead_[i];
    auto moved = std::make_shared<WalkCheckpoint>();
    moved->outline = shared_outline_;
    moved->summaries = walk_summaries_;
    moved->frozen = moved_frozen(*c.frozen, f, at);
    if (!moved->frozen) return nullptr;
    for (const auto& [offset, state] : c.pending_offset) {
        uint32_t o = offset;
        auto s = moved_state(state, *edit_move_);
        if (!s || !edit_move_->block(o)) return nullptr;
        moved->pending_offset.emplace(o, std::move(*s));
    }
    if (c.loop) {
        moved->loop = ahead_loop(i);
        if (!moved->loop) return nullptr;
    }
    return moved;
}

// Ends the walk at the previous analysis's checkpoint before ahead_[from]:
// `here` (this walk's checkpoint there) is the last one taken, the previous
// analysis's checkpoints from ahead_[from] on follow, moved; the caller keeps
// that analysis's findings from there on.
void Walk::converge_at(size_t from, const std::shared_ptr<const FrozenWalk>& at, Checkpoint here) {
    const FrozenWalk& f = *ahead_[from - 1]->frozen;
    const CheckpointPlace place = checkpoint_place(*here);
    if (options_.checkpoints->empty() || options_.checkpoints->back() != here)
        options_.checkpoints->push_back(std::move(here));
    for (size_t k = from; k < ahead_.size(); ++k) {
        Checkpoint moved = moved_ahead(k, f, *at);
        if (!moved) break;
        options_.checkpoints->push_back(std::move(moved));
    }
    *options_.converged = Convergence{place, f.diagnostics, f.suppressed};
    converged_ = true;
    stop_ = true;
    ++stats_.convergences;
}

// What WalkCheckpoint::summaries says of this analysis, once it ended.
void Walk::finish_summaries() {
    if (!walk_summaries_) return;
    walk_summaries_->used = summaries_union(local_used_, walk_summaries_->used);
    walk_summaries_->complete = true;
}

}  // namespace osplint
