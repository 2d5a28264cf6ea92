// OSP203 modal-call-left-open: MODIN without MODOUT before the program ends, or
// a MODIN while another one is active.
#include <map>
#include <string>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP203",
    .name = "modal-call-left-open",
    .severity = Severity::Warning,
    .summary = "MODIN without MODOUT before the program ends, or MODIN while another MODIN is active",
    .category = RuleCategory::WrongMotion,
    .reports_may = true,
};

class ModalCallLeftOpen final : public RuleBase<ModalCallLeftOpen> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a MODIN line is never one (it changes the state or is reported).
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }

    void begin_program(RuleContext&, const ProgramView&) override { modins_.clear(); }

    // Only a MODIN, or a call of a subprogram that leaves one open.
    uint8_t block_needs() const override { return kStatement | kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const Statement* st = v.block.statement(StmtKind::Modin);
        if (!st) {
            // A subprogram this CALL runs leaves a MODIN open: it opens here, for this program.
            if (const ActiveModin* m = active_modin(v.after); m && !m->via.empty() && m->line == v.block.line && v.call)
                modins_[v.block.line] = {v.call->name_range, m->macro};
            return;
        }
        const ByteRange where = st->head_range();
        modins_[v.block.line] = {where, st->name};
        const ActiveModin* open = active_modin(v.before);
        if (!open) {
            if (!v.before.modin.known)
                if (const Origin* o = v.before.modin_from.find()) report_may_open(ctx, *st, where, *o);
            return;
        }
        auto& d = ctx.report(kMeta, where,
                             "MODIN " + st->name + " while MODIN " + open->macro + " (line " +
                                 std::to_string(open->line) + ") is still active: the new modal call replaces it "
                                 "without a MODOUT, so it is easy to lose track of which macro runs after each "
                                 "positioning block (MODIN turns the call-after-positioning mode on until MODOUT); "
                                 "write MODOUT before this line");
        if (auto it = modins_.find(open->line); it != modins_.end())
            d.notes.push_back({"MODIN " + open->macro + " is opened here", ctx.resolve(it->second.range)});
    }

    void end_program(RuleContext& ctx, const ProgramView& p) override {
        if (!p.final_state) return;
        const ActiveModin* open = active_modin(*p.final_state);
        if (!open) {
            if (!p.final_state->modin.known)
                if (const Origin* o = p.final_state->modin_from.find()) report_may_left_open(ctx, p, *o);
            return;
        }
        auto it = modins_.find(open->line);
        if (it == modins_.end()) return;
        ctx.report(kMeta, it->second.range,
                   "MODIN " + open->macro + (open->via.empty() ? std::string() : ", which the subprogram " + open->via +
                   " opens and leaves open,") + " is never closed: there is no MODOUT before the program ends, so every "
                   "positioning block after the last hole still runs " + open->macro + (p.is_subprogram ?
                   " (including the caller's blocks after the return)" : std::string()) +
                   " (MODIN turns the call-after-positioning mode on until MODOUT); write MODOUT after the last hole "
                   "of this pattern");
    }

    bool same_as(const ModalCallLeftOpen& o) const { return modins_ == o.modins_; }
    template <class Move>
    bool each_range(Move&& move) {
        for (auto& [line, opened] : modins_)
            if (!move(opened.range)) return false;
        return true;
    }

private:
    struct Opened {
        ByteRange range;  // "MODIN OG87C"
        std::string macro;
        friend bool operator==(const Opened&, const Opened&) = default;
    };

    // The macro the MODIN at `o` opened ("a MODIN" when it is not in sight).
    std::string opened(const Origin& o) const {
        auto it = modins_.find(o.line);
        return it == modins_.end() ? std::string("a MODIN") : "MODIN " + it->second.macro;
    }

    // A MODIN where the paths that reach it disagree on whether another one is
    // open: a loop's jump brings the MODIN of the last pass back to it.
    void report_may_open(RuleContext& ctx, const Statement& st, ByteRange where, const Origin& o) const {
        const std::string mode = opened(o);
        const bool again = o.range == where;  // this MODIN, opened on the previous pass
        const std::string how =
            (again ? "the one this line opened on the previous pass" : mode + ", opened at line " + std::to_string(o.line) + ",") +
            (o.via_line ? std::string(again ? " comes back" : " reaches this line") + " through the jump at line " +
                              std::to_string(o.via_line)
                        : std::string(" reaches this line")) +
            " with no MODOUT on the way";
        Diagnostic* d = report_may(ctx, kMeta, where,
                                   "MODIN " + st.name + " while " + mode + " may still be active: " + how +
                                       "; write MODOUT before this line (or after the last hole of each pass)");
        if (!d) return;
        if (!o.range.empty() && !again) d->notes.push_back({mode + " is opened here", ctx.resolve(o.range)});
        if (o.via_line && !o.via_range.empty())
            d->notes.push_back({"the path with " + mode + " open jumps here", ctx.resolve(o.via_range)});
    }

    // Where the program ends, a MODIN is open on some paths only.
    void report_may_left_open(RuleContext& ctx, const ProgramView& p, const Origin& o) const {
        if (!o.line || o.range.empty()) return;
        const std::string mode = opened(o);
        Diagnostic* d = report_may(ctx, kMeta, o.range,
                                   mode + " may never be closed: on the path " +
                                       (o.via_line ? "through the jump at line " + std::to_string(o.via_line)
                                                   : std::string("from this line")) +
                                       " no MODOUT comes before the program " + (p.is_subprogram ? "returns" : "ends") +
                                       ", so positioning blocks after it still run the macro; write MODOUT on "
                                       "every path after the last hole");
        if (d && o.via_line && !o.via_range.empty())
            d->notes.push_back({"the path without MODOUT jumps here", ctx.resolve(o.via_range)});
    }

    std::map<uint32_t, Opened> modins_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP203() { return std::make_unique<ModalCallLeftOpen>(); }

}  // namespace osplint
