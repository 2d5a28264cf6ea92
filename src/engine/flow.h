// The control flow of one program: which blocks a block may pass control to.
//
// Blocks are lines, identified here by the offset of their line start. Edges:
//   * to the next block, unless the block jumps unconditionally (GOTO), ends
//     a loop (END), or ends the program (M02, M30, RTS) — a `/` block may be
//     skipped, so it always falls through;
//   * GOTO and IF to every block that defines the target sequence name (names
//     are local to the program; a name defined twice gives two edges);
//   * END n back to its DO n or WHILE ... DO n (the innermost open loop of the
//     same number), and WHILE to the block after its END (the loop's exit);
// and the program may end after a block that ends it, after its last block
// when control falls off it, and after a WHILE whose END is the last block.
//
// `ProgramFlow` holds what the outline says (syntax/outline.h): the loops and
// the last jump to each name. A block that defines a name jumped to from
// itself or from a later block is the head of a loop of the flow graph: the
// walk iterates from there to the last such jump (engine.cpp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <unordered_set>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/offset_filter.h"
#include "syntax/model.h"
#include "syntax/outline.h"

namespace osplint {

struct LoopPair {
    uint32_t head = 0;      // the DO / WHILE block
    uint32_t end = 0;       // the END block
    uint32_t after_end = 0; // the block after END
    bool while_loop = false;  // the head holds a WHILE (its END never falls through)
};

class ProgramFlow {
public:
    ProgramFlow() = default;
    // `end` is where the program ends (the next program's start, or the end of the input).
    ProgramFlow(const ProgramOutline& program, uint64_t end);

    uint64_t end() const { return end_; }
    // The loop whose head / END is the block at `offset`.
    const LoopPair* loop_at_head(uint32_t offset) const;
    const LoopPair* loop_at_end(uint32_t offset) const;
    // The offset of the first loop head at or after `offset` (UINT32_MAX: none).
    uint32_t next_loop_head(uint32_t offset) const {
        auto it = std::lower_bound(head_offsets_.begin(), head_offsets_.end(), offset);
        return it == head_offsets_.end() ? UINT32_MAX : *it;
    }
    // Every matched loop, by the offset of its head.
    std::vector<LoopPair> loops() const;
    // The offset of the last block that jumps to `name`.
    std::optional<uint32_t> last_jump_to(std::string_view name) const;
    // Whether a jump or an N word of the program names `name`.
    bool is_referenced(std::string_view name) const;
    bool has_jumps() const { return !last_jump_.empty(); }
    bool has_flow() const { return flow_; }

private:
    // Lookups by string_view without a temporary string.
    struct NameHash {
        using is_transparent = void;
        size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
    };
    uint64_t end_ = 0;
    bool flow_ = false;
    std::unordered_map<uint32_t, LoopPair> by_head_, by_end_;
    OffsetFilter heads_;  // the offsets of by_head_: most blocks are not a loop's head
    std::vector<uint32_t> head_offsets_;  // the same, in order
    std::unordered_map<std::string, uint32_t, NameHash, std::equal_to<>> last_jump_;
    std::unordered_set<std::string, NameHash, std::equal_to<>> references_;
};

// The edges out of one block. Shared by the walk and by the reference
// fixpoint of the tests, so that both read the flow the same way.
struct BlockEdges {
    std::vector<std::string_view> jumps;  // sequence names jumped to (GOTO, IF)
    std::vector<uint32_t> targets;        // loop edges: a loop head, or the block after a WHILE loop
    bool falls_through = true;            // to the next block of the program
    bool exits = false;                   // the program may end after this block
};
// `offset` is the block's line start, `next` the start of the next line.
BlockEdges block_edges(const Block& block, uint32_t offset, uint32_t next, const ProgramFlow& flow);

// Whether a block holds GOTO, IF, WHILE, DO or END.
bool has_flow_statement(const Block& block);
// The range of a block's jumps: from its first GOTO, IF, WHILE or END to the
// end of its last one (empty when it has none).
ByteRange jump_range(const Block& block);

}  // namespace osplint
