// How the checkpoints of a walk (engine/walk.h) are moved to an edited text
// and compared with the states of the walk over it: offsets, states, the
// sweeps over a loop and the loop's checkpoints. Internal to the engine:
// checkpoints.cpp (resuming at a checkpoint) and converge.cpp (ending early
// after an edit inside one line).
#pragma once

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/walk.h"

namespace osplint::moves {

// An old position in the text a checkpoint was taken in, in the text now
// (nullopt: inside the part that was replaced).
inline std::optional<uint32_t> moved(uint32_t offset, uint64_t old_size, const TextChange& e) {
    if (offset < e.prefix) return offset;
    if (offset >= old_size - e.suffix) return static_cast<uint32_t>(static_cast<int64_t>(offset) + e.bytes);
    return std::nullopt;
}

// The same for the start of a block: after a change inside one line, that
// line starts where it did (LineEditMove::block), even when its first byte
// changed.
inline std::optional<uint32_t> moved_block(uint32_t offset, uint64_t old_size, const TextChange& e) {
    if (e.next_line && e.lines == 0 && offset <= e.line_start) return offset;
    return moved(offset, old_size, e);
}

// The same for where the line before `offset` ends: the text before the
// change is the same, so the line after it starts there still (a line
// written at the change is the one after it now).
inline std::optional<uint32_t> moved_line_end(uint32_t offset, uint64_t old_size, const TextChange& e) {
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

inline bool same_state(const MaybeState& a, const MaybeState& b) {
    return a.reachable == b.reachable && (!a.reachable || a.state == b.state);
}

// Whether two first sweeps over a loop from `head` leave the same states
// wherever the walk with the rules reads them before the block at `at`: the
// joins and the blocks loop edges reach up to it, the sequence names defined
// from the head to it.
inline bool same_before(const SweepState& a, const SweepState& b, uint32_t head, uint32_t at) {
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
inline bool same_structure(const FileOutline& old, const FileOutline& now, size_t upto, const TextChange& e) {
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

// ------------------------------------------- ending early after an edit

// A state of the text before an edit inside one line, moved to the text
// after it (nullopt: it holds a range of the changed line).
inline std::optional<MaybeState> moved_state(const MaybeState& s, const LineEditMove& m) {
    MaybeState out = s;
    if (!out.state.each_range([&](ByteRange& r) { return m.range(r); })) return std::nullopt;
    return out;
}

inline bool same_moved(const MaybeState& now, const MaybeState& old, const LineEditMove& m) {
    if (now.reachable != old.reachable) return false;
    if (!now.reachable) return true;
    const auto moved = moved_state(old, m);
    return moved && moved->state == now.state;
}

// Two maps of states by block offset, the old one's keys and states moved.
inline bool same_moved_map(const std::map<uint32_t, MaybeState>& now, const std::map<uint32_t, MaybeState>& old,
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

inline std::unique_ptr<Rule> moved_rule(const Rule& r, const LineEditMove& m) {
    auto out = r.clone();
    if (!out->move_ranges([&](ByteRange& x) { return m.range(x); })) return nullptr;
    return out;
}

// The summaries used so far by `a`, then those of `b` it does not name.
inline std::vector<std::pair<std::string, const SubprogramSummary*>> summaries_union(
    const std::vector<std::pair<std::string, const SubprogramSummary*>>& a,
    const std::vector<std::pair<std::string, const SubprogramSummary*>>& b) {
    auto out = a;
    for (const auto& x : b)
        if (std::none_of(out.begin(), out.end(), [&](const auto& y) { return y.first == x.first; })) out.push_back(x);
    return out;
}

inline bool same_states(const std::map<uint32_t, MaybeState>& a, const std::map<uint32_t, MaybeState>& b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const auto& x, const auto& y) {
               return x.first == y.first && same_state(x.second, y.second);
           });
}

inline bool same_states(const std::unordered_map<std::string, MaybeState>& a,
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
inline bool same_sweep_end(const SweepState& a, const SweepState& b) {
    return a.loop_changed == b.loop_changed && a.extent == b.extent && a.next == b.next &&
           a.next_line == b.next_line && same_state(a.flowing, b.flowing) && same_state(a.final_state, b.final_state) &&
           same_states(a.join, b.join) && same_states(a.pending_offset, b.pending_offset) &&
           same_states(a.pending_name, b.pending_name) && a.defs == b.defs;
}

}  // namespace osplint::moves
