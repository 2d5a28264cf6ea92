#include "api/fix.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <map>

#include <fmt/format.h>

#include "engine/rule.h"

namespace osplint {

namespace {

// A finding of the rule every other rule trusts: the program does not parse there.
bool is_syntax_error(const Diagnostic& d) { return d.rule == kSyntaxErrorRule; }

// Edits [begin, end) that cannot be applied together: they share bytes, or
// both insert at one place (their order would be a guess), or one inserts
// strictly inside the other's range.
bool overlaps(const Edit& a, const Edit& b) {
    if (a.begin == a.end && b.begin == b.end) return a.begin == b.begin;
    if (a.begin == a.end) return a.begin > b.begin && a.begin < b.end;
    if (b.begin == b.end) return b.begin > a.begin && b.begin < a.end;
    return a.begin < b.end && b.begin < a.end;
}

bool edit_less(const Edit& a, const Edit& b) { return a.begin != b.begin ? a.begin < b.begin : a.end < b.end; }

// Reads [begin, end) of a source.
bool read_range(ByteSource& src, uint64_t begin, uint64_t end, std::string& out, std::string& error) {
    const size_t start = out.size();
    out.resize(start + static_cast<size_t>(end - begin));
    for (uint64_t done = 0; done < end - begin;) {
        const int64_t r = src.read(begin + done, out.data() + start + done, static_cast<size_t>(end - begin - done));
        if (r <= 0) {
            error = r < 0 ? src.error() : "the file became shorter while it was being fixed";
            return false;
        }
        done += static_cast<uint64_t>(r);
    }
    return true;
}

}  // namespace

void FixCollector::diagnostic(Diagnostic&& d) {
    if (is_syntax_error(d)) {
        if (syntax_errors_++ == 0) first_syntax_line_ = d.range.start.line;
    }
    for (const auto& f : d.fixes) {
        if (!f.safe && !unsafe_) {
            ++unsafe_left_;
            continue;
        }
        if (f.edits.empty()) continue;
        std::vector<Edit> edits;
        edits.reserve(f.edits.size());
        for (const auto& e : f.edits) edits.push_back({e.range.bytes.begin, e.range.bytes.end, e.replacement});
        std::sort(edits.begin(), edits.end(), edit_less);
        fixes_.push_back(std::move(edits));
        break;
    }
}

void FixCollector::end_file(const std::string&, const std::string& io_error) { io_error_ = io_error; }

std::vector<Edit> FixCollector::choose(uint64_t& chosen, uint64_t& waiting) const {
    chosen = waiting = 0;
    std::vector<size_t> order(fixes_.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return edit_less(fixes_[a].front(), fixes_[b].front());
    });
    // Taken edits by their start; a new edit can only overlap its neighbours.
    std::multimap<uint32_t, const Edit*> taken;
    auto clashes = [&](const Edit& e) {
        auto it = taken.upper_bound(e.end);
        while (it != taken.begin()) {
            --it;
            if (overlaps(*it->second, e)) return true;
            // Starts before e.begin and ends at or before it: nothing further left can overlap
            // unless it is longer; edits taken do not overlap each other, so the first that
            // ends before e.begin closes the search.
            if (it->second->end < e.begin) break;
        }
        return false;
    };
    std::vector<const std::vector<Edit>*> previous;
    for (size_t i : order) {
        const auto& fix = fixes_[i];
        bool same = false;
        for (const auto* p : previous)
            if (*p == fix) same = true;
        if (same) continue;  // another finding's identical fix is already taken
        bool ok = true;
        for (const auto& e : fix)
            if (clashes(e)) ok = false;
        // The edits of one fix must not overlap each other either.
        for (size_t k = 1; ok && k < fix.size(); ++k)
            if (overlaps(fix[k - 1], fix[k])) ok = false;
        if (!ok) {
            ++waiting;
            continue;
        }
        for (const auto& e : fix) taken.emplace(e.begin, &e);
        ++chosen;
        // Identical fixes come from findings at one place: only the last few taken are compared.
        previous.push_back(&fix);
        if (previous.size() > 8) previous.erase(previous.begin());
    }
    std::vector<Edit> out;
    out.reserve(taken.size());
    for (const auto& [begin, e] : taken) out.push_back(*e);
    std::stable_sort(out.begin(), out.end(), edit_less);
    return out;
}

bool compose_edits(ByteSource& original, const std::vector<Edit>& earlier, const std::vector<Edit>& later,
                   std::vector<Edit>& out, std::string& error) {
    out.clear();
    // Where each earlier edit's text lies in the intermediate text.
    struct Span {
        uint64_t begin, end;  // in the intermediate text
    };
    std::vector<Span> spans;
    spans.reserve(earlier.size());
    int64_t delta = 0;  // intermediate offset minus original offset, after the edits so far
    for (const auto& e : earlier) {
        const uint64_t b = static_cast<uint64_t>(static_cast<int64_t>(e.begin) + delta);
        spans.push_back({b, b + e.text.size()});
        delta += static_cast<int64_t>(e.text.size()) - static_cast<int64_t>(e.end - e.begin);
    }
    size_t i = 0, k = 0;
    int64_t shift = 0;  // delta of the earlier edits before the current position
    while (i < earlier.size() || k < later.size()) {
        // An earlier edit that no later edit touches stays as it is.
        if (k == later.size() || (i < earlier.size() && spans[i].end < later[k].begin)) {
            out.push_back(earlier[i]);
            shift += static_cast<int64_t>(earlier[i].text.size()) - static_cast<int64_t>(earlier[i].end - earlier[i].begin);
            ++i;
            continue;
        }
        // A cluster: later edit k and every earlier or later edit that touches
        // what the cluster covers, in intermediate coordinates [lo, hi].
        uint64_t lo = later[k].begin, hi = later[k].end;
        const size_t first_i = i;
        const size_t first_k = k;
        for (bool grew = true; grew;) {
            grew = false;
            while (i < earlier.size() && spans[i].begin <= hi && spans[i].end >= lo) {
                lo = std::min(lo, spans[i].begin);
                hi = std::max(hi, spans[i].end);
                ++i;
                grew = true;
            }
            while (k < later.size() && later[k].begin <= hi) {
                hi = std::max<uint64_t>(hi, later[k].end);
                ++k;
                grew = true;
            }
        }
        // The intermediate text of [lo, hi): original bytes between earlier texts.
        std::string text;
        int64_t d = shift;  // delta in effect at the current intermediate position
        uint64_t pos = lo;
        uint64_t orig_lo = 0, orig_hi = 0;
        bool lo_set = false;
        for (size_t j = first_i; j < i; ++j) {
            if (pos < spans[j].begin) {  // original bytes before this earlier edit
                const uint64_t ob = static_cast<uint64_t>(static_cast<int64_t>(pos) - d);
                if (!lo_set) orig_lo = ob, lo_set = true;
                if (!read_range(original, ob, ob + (spans[j].begin - pos), text, error)) return false;
                pos = spans[j].begin;
            }
            if (!lo_set) orig_lo = earlier[j].begin, lo_set = true;
            text += earlier[j].text;
            pos = spans[j].end;
            orig_hi = earlier[j].end;
            d += static_cast<int64_t>(earlier[j].text.size()) - static_cast<int64_t>(earlier[j].end - earlier[j].begin);
        }
        if (pos < hi || !lo_set) {
            const uint64_t ob = static_cast<uint64_t>(static_cast<int64_t>(pos) - d);
            if (!lo_set) orig_lo = ob, lo_set = true;
            if (pos < hi && !read_range(original, ob, ob + (hi - pos), text, error)) return false;
            orig_hi = ob + (hi > pos ? hi - pos : 0);
        }
        shift = d;
        // The later edits, applied to the cluster's text from its end.
        for (size_t j = k; j-- > first_k;) {
            const size_t b = static_cast<size_t>(later[j].begin - lo);
            const size_t e = static_cast<size_t>(later[j].end - lo);
            text.replace(b, e - b, later[j].text);
        }
        out.push_back({static_cast<uint32_t>(orig_lo), static_cast<uint32_t>(orig_hi), std::move(text)});
    }
    return true;
}

bool apply_edits(ByteSource& original, const std::vector<Edit>& edits, const ByteSink& put, std::string& error) {
    std::vector<char> buf(size_t(1) << 20);
    uint64_t pos = 0;
    size_t next = 0;
    while (true) {
        // Copy up to the next edit (or the end), then the edit's text.
        const uint64_t stop = next < edits.size() ? edits[next].begin : UINT64_MAX;
        while (pos < stop) {
            const size_t want = static_cast<size_t>(std::min<uint64_t>(buf.size(), stop - pos));
            const int64_t r = original.read(pos, buf.data(), want);
            if (r < 0) {
                error = original.error();
                return false;
            }
            if (r == 0) break;
            if (!put(std::string_view(buf.data(), static_cast<size_t>(r)))) {
                error = "write error";
                return false;
            }
            pos += static_cast<uint64_t>(r);
        }
        if (next == edits.size()) return true;
        if (pos < stop) {
            error = "the file became shorter while it was being fixed";
            return false;
        }
        if (!put(edits[next].text)) {
            error = "write error";
            return false;
        }
        pos = edits[next].end;
        ++next;
    }
}

FixPlan plan_fixes(const std::string& path, ByteSource& original, const Config& config,
                   const AnalysisOptions& options, bool unsafe) {
    // A program left as it is because something went wrong: no edits.
    auto failed = [](std::string why) {
        FixPlan p;
        p.refused = std::move(why);
        p.failed = true;
        return p;
    };
    FixPlan plan;
    AnalysisOptions every = options;
    every.fold = 0;  // every finding carries its fix
    FixCollector first(unsafe);
    check_source(path, original, config, every, first);
    plan.rounds = 1;
    if (!first.io_error().empty()) return failed(first.io_error());
    uint64_t chosen = 0, waiting = 0;
    plan.edits = first.choose(chosen, waiting);
    plan.fixes = chosen;
    if (first.syntax_errors() && !plan.edits.empty()) {
        plan = FixPlan{};
        plan.refused = fmt::format("it has syntax errors (the first on line {}): fix them first, a fix next to "
                                   "them could not be trusted",
                                   first.first_syntax_error_line());
        return plan;
    }
    if (plan.edits.empty()) return plan;
    // Further rounds check the fixed text in a temporary file: the fixes
    // taken must leave the program parsing, and may make others possible
    // (those that waited because they touched a fix taken).
    while (true) {
        std::FILE* f = std::tmpfile();
        if (!f) return failed(std::string("cannot create a temporary file: ") + std::strerror(errno));
        std::string error;
        uint64_t size = 0;
        const bool written = apply_edits(original, plan.edits, [&](std::string_view piece) {
            size += piece.size();
            return std::fwrite(piece.data(), 1, piece.size(), f) == piece.size();
        }, error) && std::fflush(f) == 0;
        if (!written || size > kMaxInputSize) {
            std::fclose(f);
            return failed(!written ? error : fmt::format("the {} fixes would make it larger than 4 GiB", plan.fixes));
        }
        FdSource fixed(fileno(f), size);
        FixCollector again(unsafe);
        check_source(path, fixed, config, every, again);
        std::fclose(f);
        ++plan.rounds;
        if (!again.io_error().empty()) return failed(again.io_error());
        if (again.syntax_errors())
            return failed(fmt::format("a fix would break its syntax (line {} of the fixed program); nothing was "
                                      "changed. Please report this with the program",
                                      again.first_syntax_error_line()));
        std::vector<Edit> later = again.choose(chosen, waiting);
        if (later.empty()) return plan;
        if (plan.rounds > kMaxFixRounds)
            return failed(fmt::format("the fixes did not settle after {} rounds; nothing was changed. Please report "
                                      "this with the program",
                                      kMaxFixRounds));
        std::vector<Edit> composed;
        if (!compose_edits(original, plan.edits, later, composed, error)) return failed(error);
        plan.edits = std::move(composed);
        plan.fixes += chosen;
    }
}

bool write_fixes(const std::string& target, const FileStamp& read, ByteSource& original,
                 const std::vector<Edit>& edits, std::string& error) {
    const std::optional<FileStamp> now = file_stamp(target);
    if (!now || *now != read) {
        error = "it changed while it was being checked";
        return false;
    }
    return write_file_atomically(
        target, [&](const PieceWriter& put) { return apply_edits(original, edits, put, error); }, error);
}

}  // namespace osplint
