// A call line again: a posted program calls the same macro line after line,
// with the same arguments in the same order, and only some values change
// (`CALL OZAGR PX=48. PY=-20. PR=5. ...`, then `... PX=42.5 PY=-20. ...`).
// Such a line is not parsed again: the block of the line before it is
// updated in place. The result is the block parse would make (the
// differential test in tests/unit/test_fast_frontend.cpp parses lines both
// ways), so the rest of the analysis cannot tell.
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "syntax/frontend_fast_parser.h"

namespace osplint {

using namespace fast_detail;

void FastLineParser::Impl::keep_call(bool ok) {
    again.block = nullptr;
    if (!ok || outline || !call_plain || call_args.empty()) return;
    const Block& out = *b;
    if (out.kind != LineKind::Block || out.program_name || out.sequence || out.block_delete ||
        out.statements.size() != 1 || out.words.size() != call_args.size() || !out.assignments.empty() ||
        !out.comments.empty() || !out.errors.empty())
        return;
    const Statement& st = out.statements[0];
    if (st.kind != StmtKind::Call && st.kind != StmtKind::Modin) return;
    again.block = &out;
    again.text.assign(s, n);
    again.keyword_end = st.keyword_range.end - base;
    again.name_begin = st.name_range.begin - base;
    again.head = st.name_range.end - base;
    again.range = out.range;
    again.exprs = out.exprs.size();
    again.args = call_args;
}

namespace {

// How many bytes a and b have in common from their starts (`forward`) or
// from their ends, up to `max`.
uint32_t common(const char* a, const char* b, uint32_t max, bool forward) {
    uint32_t i = 0;
    if (forward) {
        for (; i + 8 <= max; i += 8) {
            uint64_t x, y;
            std::memcpy(&x, a + i, 8);
            std::memcpy(&y, b + i, 8);
            if (x != y) break;
        }
        while (i < max && a[i] == b[i]) ++i;
    } else {
        for (; i + 8 <= max; i += 8) {
            uint64_t x, y;
            std::memcpy(&x, a - i - 8, 8);
            std::memcpy(&y, b - i - 8, 8);
            if (x != y) break;
        }
        while (i < max && a[-1 - static_cast<int64_t>(i)] == b[-1 - static_cast<int64_t>(i)]) ++i;
    }
    return i;
}

}  // namespace

bool FastLineParser::Impl::again_call(const LineRef& line, Block& out) {
    Again& g = again;
    const char* t = g.text.data();
    const auto m = static_cast<uint32_t>(g.text.size());
    const uint32_t h = g.head;
    // The block is as the last line left it.
    if (out.range != g.range || out.words.size() != g.args.size() || out.statements.size() != 1 ||
        out.program_name || out.sequence || out.block_delete || !out.assignments.empty() ||
        !out.comments.empty() || !out.errors.empty())
        return false;
    // The bytes the two lines share at their starts and at their ends: the
    // arguments there are the same (a posted line changes one or two values).
    const uint32_t shortest = std::min(n, m);
    const uint32_t head = common(s, t, shortest, true);
    if (head <= h) return false;  // another macro, or no blank after its name
    const uint32_t tail = common(s + n, t + m, shortest - head, false);
    const int64_t shift = static_cast<int64_t>(n) - static_cast<int64_t>(m);
    const size_t count = g.args.size();
    size_t first = 0;  // the arguments before `first` end before `head`, their blank after them too
    while (first < count && g.args[first].end < head) ++first;
    size_t last = count;  // those from `last` on begin, their blank before them too, in the tail
    while (last > first && g.args[last - 1].begin > m - tail) --last;
    // The arguments between: each read again, from the end of the one
    // before, with its digits' value where its text changed; nothing is
    // written before the whole line is read.
    std::vector<CallArg>& now = call_args;
    now.resize(count);
    digits.resize(count);
    const auto blank = [&](uint32_t i) { return (kClass[static_cast<unsigned char>(s[i])] & kBlankClass) != 0; };
    // Whether a value gains or loses its sign: the expressions are made again.
    bool reshape = out.exprs.size() != g.exprs;
    uint32_t p = first == 0 ? h : g.args[first - 1].end;
    for (size_t k = first; k < last; ++k) {
        const CallArg& old = g.args[k];
        uint32_t q = p;
        while (q < n && blank(q)) ++q;
        // The name, the blanks and `=` as they were.
        const uint32_t prefix = old.value_begin - old.begin;
        if (q == p || n - q < prefix) return false;
        for (uint32_t i = 0; i < prefix; ++i)
            if (s[q + i] != t[old.begin + i]) return false;
        // The value up to a blank, compared with the last one on the way.
        const uint32_t value = q + prefix;
        uint32_t end = value;
        uint32_t o = old.value_begin;
        bool unchanged = true;
        for (; end < n && !blank(end); ++end, ++o)
            if (unchanged && (o == old.end || s[end] != t[o])) unchanged = false;
        unchanged = unchanged && o == old.end;
        CallArg& a = now[k];
        a = {q, q + (old.name_end - old.begin), value, end, old.sign, false};
        if (!unchanged) {
            // Another value: still a plain number.
            PlainArg r;
            if (!plain_arg<true>(q, r) || r.value_begin != value || r.end != end) return false;
            a.sign = r.digits_begin > value;
            a.changed = true;
            digits[k] = r.value;
            reshape = reshape || a.sign != old.sign;
        }
        p = end;
    }
    // Blanks only, one at least, up to the next argument; blanks only up to
    // the end of the line after the last one.
    const uint32_t to = last < count ? static_cast<uint32_t>(g.args[last].begin + shift) : n;
    if (p > to || (last < count && p == to)) return false;
    while (p < to && blank(p)) ++p;
    if (p != to) return false;
    // The words and their expressions, as plain_arg_word makes them: in
    // place while each value keeps its sign or its lack of one (the nodes
    // stay where they are: each argument's number, then its sign's node).
    // The arguments before `first` and from `last` on are where they were,
    // moved by `shift` for the latter.
    exprs_used = 0;
    exprs_have = out.exprs.size();
    // The line starts elsewhere in the file: the ranges of an argument read
    // as it was move by as much (and by `shift` more from `last` on).
    const uint32_t moved = base - g.range.begin;  // modulo 2^32, as the offsets add up
    for (size_t k = 0; k < count; ++k) {
        CallArg& a = g.args[k];
        if (!reshape && (k < first || k >= last)) {
            uint32_t d = moved;
            if (k >= last) {
                const auto by = [&](uint32_t x) { return static_cast<uint32_t>(x + shift); };
                a = {by(a.begin), by(a.name_end), by(a.value_begin), by(a.end), a.sign, false};
                d += static_cast<uint32_t>(shift);
            }
            const auto move = [d](ByteRange& r) {
                r.begin += d;
                r.end += d;
            };
            Word& w = out.words[k];
            move(w.range);
            move(w.address_range);
            move(w.value_range);
            move(out.exprs[exprs_used++].range);
            if (a.sign) move(out.exprs[exprs_used++].range);
            continue;
        }
        if (k >= first && k < last) {
            a = now[k];
        } else if (k >= last) {
            const auto by = [&](uint32_t x) { return static_cast<uint32_t>(x + shift); };
            a = {by(a.begin), by(a.name_end), by(a.value_begin), by(a.end), a.sign, false};
        }
        const bool changed = a.changed;
        a.changed = false;
        const uint32_t value = a.value_begin;
        Word& w = out.words[k];
        const ByteRange digits_range = abs(value + (a.sign ? 1 : 0), a.end);
        if (reshape) {
            double v = digits[k];
            if (!changed) {
                if (!w.number) return false;
                v = s[value] == '-' ? -*w.number : *w.number;
            }
            ExprNode& num = new_expr(ExprKind::Number, digits_range);
            num.number = v;
            w.value = last_expr();
            if (a.sign) {
                ExprNode& un = new_expr(ExprKind::Unary, abs(value, a.end), s[value]);
                set_child(un.children, w.value);
                w.value = last_expr();
            }
        } else {
            ExprNode& num = out.exprs[exprs_used++];
            num.range = digits_range;
            if (changed) num.number = digits[k];
            if (a.sign) {
                ExprNode& un = out.exprs[exprs_used++];
                un.range = abs(value, a.end);
                if (changed) set_char(un.op, s[value]);
            }
        }
        if (changed) {
            w.number = a.sign && s[value] == '-' ? -digits[k] : digits[k];
            set_text(w.value_text, s + value, a.end - value);
        }
        w.range = abs(a.begin, a.end);
        w.address_range = abs(a.begin, a.name_end);
        w.value_range = abs(value, a.end);
    }
    if (reshape) expr_pool.finish(out.exprs, exprs_used);
    g.exprs = out.exprs.size();
    Statement& st = out.statements[0];
    st.keyword_range = abs(0, g.keyword_end);
    st.name_range = abs(g.name_begin, h);
    st.range = abs(0, g.args.back().end);
    out.line = line.line;
    out.line_start = line.start;
    out.range = {line.start, line.start + n};
    g.text.assign(s, n);
    g.range = out.range;
    return true;
}

}  // namespace osplint
