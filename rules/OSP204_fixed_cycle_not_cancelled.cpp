// OSP204 fixed-cycle-not-cancelled: another fixed cycle commanded while one is
// modal without G80 between, or a cycle still modal where the program ends.
#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP204",
    .name = "fixed-cycle-not-cancelled",
    .severity = Severity::Warning,
    .summary = "A fixed cycle switched without G80, or still modal at the program end",
    .category = RuleCategory::WrongMotion,
    .reports_may = true,
};

std::string cycle_name(const ActiveCycle& c) {
    std::string name = c.macro.empty() ? fmt::format("G{}", c.code) : fmt::format("G{} ({})", c.code, c.macro);
    if (!c.via.empty()) name += " (left modal by the subprogram " + c.via + ")";
    return name;
}

// How the cycle is cancelled: G80, or the registered cancel code of a macro cycle.
std::string cancel_hint(const RuleContext& ctx, const ActiveCycle& c) {
    if (c.macro.empty()) return "G80";
    const MacroSpec* spec = ctx.catalog().find(c.macro);
    if (spec && !spec->cancel.empty())
        for (const auto& [code, macro] : ctx.catalog().registrations())
            if (macro == spec->cancel) return code + " (or G80)";
    return "G80";
}

class FixedCycleNotCancelled final : public RuleBase<FixedCycleNotCancelled> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a block after an M02, M30 or RTS that ends the program is reached by no path.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line neither ends the program nor runs under a fixed cycle

    void begin_program(RuleContext&, const ProgramView&) override { end_block_.reset(); }

    // Only RTS, M02 or M30 (the end of the program), or a cycle started while one is modal.
    uint8_t block_needs() const override { return kStatement | kMWord | kCycleBefore; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const Block& b = v.block;
        if (b.statement(StmtKind::Rts) || b.has_code("M", 2) || b.has_code("M", 30)) end_block_ = b.range;
        const ActiveCycle* now = active_cycle(v.after);
        const ActiveCycle* old = active_cycle(v.before);
        if (!now || !old || now->start_line != b.line || b.has_code("G", 80)) return;
        if (now->code == old->code && now->macro == old->macro) return;
        auto& d = ctx.report(kMeta, now->start_range.empty() ? b.range : now->start_range,
                             cycle_name(*now) + " is commanded while " + cycle_name(*old) +
                                 " is still modal: addresses mean different things in each cycle, and the control "
                                 "may stop with an alarm or read the old values (" + cite("fixed-cycles/alarms") + "); command " +
                                 cancel_hint(ctx, *old) + " on the block before");
        if (!old->start_range.empty())
            d.notes.push_back({cycle_name(*old) + " was started here", ctx.resolve(old->start_range)});
    }

    void end_program(RuleContext& ctx, const ProgramView& p) override {
        if (!p.final_state) return;
        const ActiveCycle* c = active_cycle(*p.final_state);
        if (!c) {
            report_uncancelled(ctx, p);
            report_may_uncancelled(ctx, p);
            return;
        }
        ByteRange where = c->start_range.empty() ? c->command_range : c->start_range;
        if (where.empty()) {
            if (!end_block_) return;
            where = *end_block_;
        }
        ctx.report(kMeta, where,
                   cycle_name(*c) + " is still modal where the program " + (p.is_subprogram ? "returns" : "ends") +
                       ": no cancel follows it" +
                       (p.is_subprogram ? ", so the caller's next positioning block machines another hole" : "") +
                       " (\"check that the G80 cancel code is commanded\", " + cite("fixed-cycles/alarms") + "); command " +
                       cancel_hint(ctx, *c) + " after the last hole");
    }

    bool same_as(const FixedCycleNotCancelled& o) const { return end_block_ == o.end_block_; }
    template <class Move>
    bool each_range(Move&& move) {
        return !end_block_ || move(*end_block_);
    }

private:
    // No cycle is known to be modal at the end, but one was started and no G80
    // ended it: a G0/G1/G2/G3 came after it, which may or may not end a fixed
    // cycle on the control. Either way the manual asks for G80.
    void report_uncancelled(RuleContext& ctx, const ProgramView& p) const {
        const ModalState& s = *p.final_state;
        if (s.cycle.known || !s.uncancelled.known || !s.uncancelled.value) return;
        const OpenCycle& o = *s.uncancelled.value;
        if (o.start.empty()) return;
        ActiveCycle c;
        c.code = o.code;
        c.macro = o.macro;
        c.via = o.via;
        auto& d = ctx.report(kMeta, o.start,
                             cycle_name(c) + " is never cancelled before the program " +
                                 (p.is_subprogram ? "returns" : "ends") +
                                 ": a G0, G1, G2 or G3 follows it, but whether an interpolation code ends a fixed "
                                 "cycle is not documented, so the cycle may still be modal (\"check that the G80 cancel "
                                 "code is commanded\", " + cite("fixed-cycles/alarms") + "); command " +
                                 cancel_hint(ctx, c) + " after the last hole");
        d.notes.push_back({"osplint reads the cycle as perhaps still modal after the interpolation code; positioning "
                           "blocks after it may machine holes",
                           std::nullopt});
    }

    // The paths that end the program disagree on whether a cycle was
    // cancelled: a jump or a branch skips the G80 on one of them.
    void report_may_uncancelled(RuleContext& ctx, const ProgramView& p) const {
        const ModalState& s = *p.final_state;
        if (s.uncancelled.known) return;
        const Origin* o = s.cycle_from.find();
        if (!o || !o->line || o->range.empty()) return;
        Diagnostic* d = report_may(
            ctx, kMeta, o->range,
            "the fixed cycle started here may still be modal where the program " +
                std::string(p.is_subprogram ? "returns" : "ends") + ": " +
                (o->via_line ? "the path through the jump at line " + std::to_string(o->via_line)
                             : std::string("a path from this line")) +
                " reaches the end with no G80 after it (\"check that the G80 cancel code is commanded\", " +
                cite("fixed-cycles/alarms") + "); command G80 on every path after the last hole");
        if (d && o->via_line && !o->via_range.empty())
            d->notes.push_back({"the path without G80 jumps here", ctx.resolve(o->via_range)});
    }

    std::optional<ByteRange> end_block_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP204() { return std::make_unique<FixedCycleNotCancelled>(); }

}  // namespace osplint
