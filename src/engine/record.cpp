#include "engine/record.h"

namespace osplint {

BlockRecord record_block(const BlockView& view, const LineRef& line) {
    BlockRecord r;
    r.block = view.block;
    r.text.assign(line.text);
    r.before = view.before;
    r.after = view.after;
    r.reachable = view.reachable;
    if (view.call) {
        r.call = *view.call;
        const Word* old_base = view.block.words.data();
        const Word* new_base = r.block.words.data();
        auto rebase = [&](const Word*& w) {
            if (w) w = new_base + (w - old_base);
        };
        for (auto& a : r.call->args) rebase(a.word);
        rebase(r.call->repeat);
        for (auto& m : r.call->m_codes) rebase(m);
    }
    return r;
}

}  // namespace osplint
