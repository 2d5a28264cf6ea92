#include "engine/flow.h"

#include <algorithm>

#include "semantics/transfer.h"

namespace osplint {

ProgramFlow::ProgramFlow(const ProgramOutline& program, uint64_t end)
    : end_(end), references_(program.references.begin(), program.references.end()) {
    flow_ = !program.flow.empty();
    // DO / WHILE n ... END n: the innermost open loop of the same number.
    std::map<int, std::vector<const FlowSite*>> open;
    for (const FlowSite& site : program.flow) {
        for (const FlowStatement& st : site.statements) {
            if ((st.kind == StmtKind::While || st.kind == StmtKind::Do) && st.loop >= 0) {
                open[st.loop].push_back(&site);
            } else if (st.kind == StmtKind::End && st.loop >= 0) {
                auto& stack = open[st.loop];
                if (stack.empty()) continue;
                const FlowSite* head = stack.back();
                stack.pop_back();
                LoopPair pair;
                pair.head = head->offset;
                pair.end = site.offset;
                pair.after_end = site.next;
                for (const FlowStatement& h : head->statements)
                    if (h.kind == StmtKind::While) pair.while_loop = true;
                by_head_[pair.head] = pair;
                heads_.add(pair.head);
                head_offsets_.push_back(pair.head);
                by_end_[pair.end] = pair;
            } else if ((st.kind == StmtKind::Goto || st.kind == StmtKind::If) && !st.name.empty()) {
                uint32_t& last = last_jump_.try_emplace(st.name, 0).first->second;
                last = std::max(last, site.offset);
            }
        }
    }
    std::sort(head_offsets_.begin(), head_offsets_.end());
    head_offsets_.erase(std::unique(head_offsets_.begin(), head_offsets_.end()), head_offsets_.end());
}

const LoopPair* ProgramFlow::loop_at_head(uint32_t offset) const {
    if (!heads_.may_hold(offset)) return nullptr;
    auto it = by_head_.find(offset);
    return it == by_head_.end() ? nullptr : &it->second;
}

const LoopPair* ProgramFlow::loop_at_end(uint32_t offset) const {
    auto it = by_end_.find(offset);
    return it == by_end_.end() ? nullptr : &it->second;
}

std::vector<LoopPair> ProgramFlow::loops() const {
    std::vector<LoopPair> out;
    out.reserve(by_head_.size());
    for (const auto& [head, pair] : by_head_) out.push_back(pair);
    std::sort(out.begin(), out.end(), [](const LoopPair& a, const LoopPair& b) { return a.head < b.head; });
    return out;
}

std::optional<uint32_t> ProgramFlow::last_jump_to(std::string_view name) const {
    auto it = last_jump_.find(name);
    if (it == last_jump_.end()) return std::nullopt;
    return it->second;
}

bool ProgramFlow::is_referenced(std::string_view name) const {
    return !references_.empty() && references_.find(name) != references_.end();
}

ByteRange jump_range(const Block& b) {
    ByteRange r;
    for (const auto& st : b.statements) {
        if (st.kind != StmtKind::Goto && st.kind != StmtKind::If && st.kind != StmtKind::While &&
            st.kind != StmtKind::End)
            continue;
        if (r.empty()) r.begin = st.range.begin;
        r.end = st.range.end;
    }
    return r;
}

bool has_flow_statement(const Block& b) {
    for (const auto& st : b.statements)
        switch (st.kind) {
            case StmtKind::Goto:
            case StmtKind::If:
            case StmtKind::While:
            case StmtKind::Do:
            case StmtKind::End: return true;
            default: break;
        }
    return false;
}

BlockEdges block_edges(const Block& b, uint32_t offset, uint32_t next, const ProgramFlow& flow) {
    BlockEdges e;
    for (const auto& st : b.statements) {
        switch (st.kind) {
            case StmtKind::Goto:
                if (!st.name.empty()) e.jumps.push_back(st.name);
                if (!b.block_delete) e.falls_through = false;
                break;
            case StmtKind::If:
                if (!st.name.empty()) e.jumps.push_back(st.name);
                break;
            case StmtKind::While:
                if (const LoopPair* p = flow.loop_at_head(offset)) {
                    if (p->after_end < flow.end()) e.targets.push_back(p->after_end);
                    else e.exits = true;  // the loop is the last thing in the program
                }
                break;
            case StmtKind::End:
                if (const LoopPair* p = flow.loop_at_end(offset)) {
                    e.targets.push_back(p->head);
                    // A WHILE loop exits at its head; a bare DO loop only through a jump.
                    if (!b.block_delete || p->while_loop) e.falls_through = false;
                }
                break;
            default: break;
        }
    }
    if (ends_program(b)) {
        e.exits = true;
        if (!b.block_delete) e.falls_through = false;
    }
    if (e.falls_through && next >= flow.end()) e.exits = true;  // control falls off the last block
    return e;
}

}  // namespace osplint
