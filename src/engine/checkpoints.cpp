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

#include "engine/summaries.h"

namespace osplint {

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
    c->pending_offset = pending_offset_;
    c->frozen = freeze();
    c->summaries = walk_summaries_;
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

// The same for the start of a block: after a change inside one line, that
// line starts where it did (LineEditMove::block), even when its first byte
// changed.
std::optional<uint32_t> moved_block(uint32_t offset, uint64_t old_size, const TextChange& e) {
    if (e.next_line && e.lines == 0 && offset <= e.line_start) return offset;
    return moved(offset, old_size, e);
}

// The same for where the line before `offset` ends: the text before the
// change is the same, so the line after it starts there still (a line
// written at the change is the one after it now).
std::optional<uint32_t> moved_line_end(uint32_t offset, uint64_t old_size, const TextChange& e) {
    if (offset <= e.prefix) return offset;
    return moved(offset, old_size, e);
}

// How the offsets of a checkpoint inside a loop are moved through a change
// of the text: KeysMove moves its blocks only (a checkpoint before the change,
// whose states the walk resumed there reads only where they are the same as
// the new text's: resume_loop); LineMove, for a change inside one line after
// the checkpoint, moves the byte ranges its states hold too (LineEditMove: a
// range on that line cannot be moved).
struct KeysMove {
    static constexpr bool kRanges = false;
    uint64_t old_size = 0;
    TextChange e;
    bool block(uint32_t& o) const {
        const auto m = moved_block(o, old_size, e);
        if (m) o = *m;
        return m.has_value();
    }
    bool range(ByteRange&) const { return true; }
};
struct LineMove {
    static constexpr bool kRanges = true;
    const LineEditMove& m;
    bool block(uint32_t& o) const { return m.block(o); }
    bool range(ByteRange& r) const { return m.range(r); }
};

template <class Mover>
bool move_state(MaybeState& s, const Mover& mv) {
    if constexpr (Mover::kRanges) return !s.reachable || s.state.each_range([&](ByteRange& r) { return mv.range(r); });
    return true;
}

// A map by offset (of states or not), its keys and states moved.
template <class V, class Mover>
bool move_map(std::map<uint32_t, V>& x, const Mover& mv) {
    std::map<uint32_t, V> out;
    for (auto& [k, v] : x) {
        uint32_t o = k;
        if (!mv.block(o)) return false;
        if constexpr (std::is_same_v<V, MaybeState>)
            if (!move_state(v, mv)) return false;
        out.emplace_hint(out.end(), o, std::move(v));
    }
    x = std::move(out);
    return true;
}

template <class Mover>
bool move_names(std::unordered_map<std::string, MaybeState>& x, const Mover& mv) {
    if constexpr (Mover::kRanges)
        for (auto& [name, s] : x)
            if (!move_state(s, mv)) return false;
    return true;
}

template <class Mover>
bool move_defs(std::unordered_map<std::string, std::vector<uint32_t>>& defs, const Mover& mv) {
    for (auto& [name, offsets] : defs)
        for (uint32_t& o : offsets)
            if (!mv.block(o)) return false;
    return true;
}

template <class Mover>
std::shared_ptr<const SweepState> move_sweep(const SweepState& in, const Mover& mv) {
    auto out = std::make_shared<SweepState>(in);
    if (!move_state(out->flowing, mv) || !move_map(out->join, mv) || !move_names(out->pending_name, mv) ||
        !move_map(out->pending_offset, mv) || !move_defs(out->defs, mv) || !move_state(out->final_state, mv) ||
        !move_map(out->probes, mv) || !move_map(out->join_stamps, mv) || !mv.block(out->extent))
        return nullptr;
    if (!mv.block(out->next)) {
        // The line the sweep read next was changed. Only a walk that ends
        // where the sweep ended seeks there (LineMove); a resumed one sweeps
        // on and reads it again, and no sweep ends at this offset.
        if constexpr (Mover::kRanges) return nullptr;
        out->next = SweepState::kChanged;
    }
    return out;
}

// `sweeps` (when set) keeps the sweeps moved so far by what they were: the
// checkpoints of one loop share the states its first sweep left.
template <class Mover>
std::shared_ptr<const LoopCheckpoint> move_loop(
    const LoopCheckpoint& in, const Mover& mv,
    std::map<const SweepState*, std::shared_ptr<const SweepState>>* sweeps = nullptr) {
    auto out = std::make_shared<LoopCheckpoint>(in);
    out->first = move_sweep(*in.first, mv);
    if (sweeps) {
        auto& s = (*sweeps)[in.after_first.get()];
        if (!s) s = move_sweep(*in.after_first, mv);
        out->after_first = s;
    } else {
        out->after_first = move_sweep(*in.after_first, mv);
    }
    if (!out->first || !out->after_first || !mv.block(out->head) || !move_state(out->entry, mv) ||
        !move_map(out->join, mv) || !move_names(out->brought_name, mv) || !move_map(out->brought_offset, mv) ||
        !move_state(out->brought_final, mv))
        return nullptr;
    return out;
}

bool same_state(const MaybeState& a, const MaybeState& b) {
    return a.reachable == b.reachable && (!a.reachable || a.state == b.state);
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
    // Whether `offset`, moved by `move` (moved, moved_block or moved_line_end), is `expected`.
    auto lands = [&](auto move, uint32_t offset, uint32_t expected) {
        const std::optional<uint32_t> m = move(offset, old.size, e);
        return m && *m == expected;
    };
    auto at = [&](uint32_t offset, uint32_t expected) { return lands(moved, offset, expected); };
    auto block_at = [&](uint32_t offset, uint32_t expected) { return lands(moved_block, offset, expected); };
    auto line_end_at = [&](uint32_t offset, uint32_t expected) { return lands(moved_line_end, offset, expected); };
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
        if (!block_at(a.offset, b.offset) || !line_at(a.offset, a.line, b.line) || a.has_rts != b.has_rts ||
            a.has_content != b.has_content || a.references != b.references || a.flow.size() != b.flow.size() ||
            !(a.name.empty() || range_at(a.name_range, b.name_range)))
            return false;
        for (size_t k = 0; k < a.flow.size(); ++k) {
            const FlowSite& x = a.flow[k];
            const FlowSite& y = b.flow[k];
            if (!block_at(x.offset, y.offset) || !line_at(x.offset, x.line, y.line) || !line_end_at(x.next, y.next) ||
                x.block_delete != y.block_delete || !(x.statements == y.statements))
                return false;
        }
    }
    if (old.programs.size() > upto + 1 && !block_at(old.programs[upto + 1].offset, now.programs[upto + 1].offset))
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

// ------------------------------------------- ending early after an edit

namespace {

// A state of the text before an edit inside one line, moved to the text
// after it (nullopt: it holds a range of the changed line).
std::optional<MaybeState> moved_state(const MaybeState& s, const LineEditMove& m) {
    MaybeState out = s;
    if (!out.state.each_range([&](ByteRange& r) { return m.range(r); })) return std::nullopt;
    return out;
}

bool same_moved(const MaybeState& now, const MaybeState& old, const LineEditMove& m) {
    if (now.reachable != old.reachable) return false;
    if (!now.reachable) return true;
    const auto moved = moved_state(old, m);
    return moved && moved->state == now.state;
}

// Two maps of states by block offset, the old one's keys and states moved.
bool same_moved_map(const std::map<uint32_t, MaybeState>& now, const std::map<uint32_t, MaybeState>& old,
                    const LineEditMove& m) {
    if (now.size() != old.size()) return false;
    for (const auto& [k, v] : old) {
        uint32_t key = k;
        if (!m.block(key)) return false;
        const auto it = now.find(key);
        if (it == now.end() || !same_moved(it->second, v, m)) return false;
    }
    return true;
}

std::unique_ptr<Rule> moved_rule(const Rule& r, const LineEditMove& m) {
    auto out = r.clone();
    if (!out->move_ranges([&](ByteRange& x) { return m.range(x); })) return nullptr;
    return out;
}

// The summaries used so far by `a`, then those of `b` it does not name.
std::vector<std::pair<std::string, const SubprogramSummary*>> summaries_union(
    const std::vector<std::pair<std::string, const SubprogramSummary*>>& a,
    const std::vector<std::pair<std::string, const SubprogramSummary*>>& b) {
    auto out = a;
    for (const auto& x : b)
        if (std::none_of(out.begin(), out.end(), [&](const auto& y) { return y.first == x.first; })) out.push_back(x);
    return out;
}

}  // namespace

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

namespace {

bool same_states(const std::map<uint32_t, MaybeState>& a, const std::map<uint32_t, MaybeState>& b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const auto& x, const auto& y) {
               return x.first == y.first && same_state(x.second, y.second);
           });
}

bool same_states(const std::unordered_map<std::string, MaybeState>& a,
                 const std::unordered_map<std::string, MaybeState>& b) {
    if (a.size() != b.size()) return false;
    for (const auto& [name, s] : a) {
        const auto it = b.find(name);
        if (it == b.end() || !same_state(s, it->second)) return false;
    }
    return true;
}

// Whether two first sweeps over a loop left the same states behind: the walk
// with the rules after them starts from the same states.
bool same_sweep_end(const SweepState& a, const SweepState& b) {
    return a.loop_changed == b.loop_changed && a.extent == b.extent && a.next == b.next &&
           a.next_line == b.next_line && same_state(a.flowing, b.flowing) && same_state(a.final_state, b.final_state) &&
           same_states(a.join, b.join) && same_states(a.pending_offset, b.pending_offset) &&
           same_states(a.pending_name, b.pending_name) && a.defs == b.defs;
}

}  // namespace

// Whether the first sweep over the loop, before its `index`-th block, is in
// the state `s` holds.
bool Walk::sweep_is(const SweepState& s, uint32_t extent, uint32_t index) const {
    return s.index == index && s.extent == extent && s.loop_changed == loop_changed_ && s.stamp == stamp_ &&
           same_state(s.flowing, MaybeState{reachable_, reachable_ ? *A_ : ModalState{}}) &&
           same_state(s.final_state, final_state_) && same_states(s.join, join_) &&
           same_states(s.pending_offset, pending_offset_) && same_states(s.pending_name, pending_name_) &&
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
    if (!old.loop && !same_moved_map(pending_offset_, old.pending_offset, m)) return false;
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

}  // namespace osplint
