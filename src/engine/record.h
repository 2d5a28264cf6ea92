// Blocks as the walk saw them, kept beyond the walk: `osplint trace`, the
// language server's hover, the tests.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "engine/engine.h"
#include "semantics/calls.h"
#include "semantics/modal.h"
#include "syntax/model.h"

namespace osplint {

struct BlockRecord {
    Block block;
    std::string text;  // the line without its terminator
    ModalState before;
    ModalState after;
    std::optional<MacroCall> call;  // its Word pointers point into `block`
    bool reachable = true;

    BlockRecord() = default;
    BlockRecord(BlockRecord&&) = default;             // a moved vector keeps its elements in place
    BlockRecord& operator=(BlockRecord&&) = default;
    BlockRecord(const BlockRecord&) = delete;
    BlockRecord& operator=(const BlockRecord&) = delete;
    BlockView view() const { return BlockView{block, before, after, call ? &*call : nullptr, reachable}; }
};

// A copy of what the view shows, its call pointing into the copied block.
BlockRecord record_block(const BlockView& view, const LineRef& line);

// Records every block (for inputs small enough to hold: tests, short documents).
class BlockRecorder : public BlockObserver {
public:
    bool block(const BlockView& view, const LineRef& line) override {
        blocks.push_back(record_block(view, line));
        return true;
    }
    // The record of a 1-based line, or nullptr.
    const BlockRecord* at(uint32_t line) const {
        for (const auto& b : blocks)
            if (b.block.line == line) return &b;
        return nullptr;
    }
    std::vector<BlockRecord> blocks;
};

}  // namespace osplint
