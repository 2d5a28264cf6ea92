// OSP201 g60-with-ncyl: G60 modal and NCYL on one block where the back-counterbore
// or long-slot keyway macros are in use (the manuals forbid the combination).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP201",
    .name = "g60-with-ncyl",
    .severity = Severity::Error,
    .summary = "G60 and NCYL together in a program using the OG87*/OZAGR/OM100/OKYOX macros",
    .category = RuleCategory::WrongMotion,
    .reports_may = true,
};

// Where the macro's manual forbids the combination.
std::string forbidding_source(const Catalog& catalog, const MacroSpec& s) {
    return macro::note_ref(catalog, s, "G60");
}

class G60WithNcyl final : public RuleBase<G60WithNcyl> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a repeated block has no NCYL, and the macro that may collide is known by then.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }

    void begin_program(RuleContext&, const ProgramView&) override {
        pending_.clear();
        user_ = nullptr;
        user_range_ = {};
    }

    // Only a call of a macro that G60 and NCYL hurt, or an NCYL.
    uint8_t block_needs() const override { return kStatement | kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        if (c && c->spec && c->spec->has(Hazard::G60NcylCollision) && !user_ &&
            (macro::is_invocation(*c) || c->kind == CallKind::ModinPositioning)) {
            user_ = c->spec;
            user_range_ = macro::call_range(*c, v.block);
            flush(ctx);  // the blocks before it, in program order
        }
        const Statement* ncyl = v.block.statement(StmtKind::Ncyl);
        if (!ncyl) return;
        // G60 on every path, or (a "may" finding) on some of them only.
        std::optional<Origin> may;
        if (!v.after.motion.is(60)) {
            if (v.after.motion.known) return;
            const Origin* g60 = v.after.g60_from.find();
            if (!g60) return;
            may = *g60;
        }
        if (const ActiveModin* m = active_modin(v.before)) {
            const MacroSpec* spec = ctx.catalog().find(m->macro);
            if (spec && spec->has(Hazard::G60NcylCollision)) {
                report(ctx, {ncyl->keyword_range, macro::mode_from_subprogram(v.after, "G60"), may}, *spec,
                       "MODIN " + spec->name + " is active (line " + std::to_string(m->line) + ")", std::nullopt);
                return;
            }
        }
        // Elsewhere in a program that uses these macros. Under a fixed cycle
        // (G114 above all, "NCYL/G60 are also OK" in the tap cycle manual) the combination
        // is the control's own business: only blocks known to be outside any
        // MODIN of such a macro and outside any cycle are kept.
        if (!v.before.modin.known || !v.after.cycle.known || v.after.cycle.value) return;
        Ncyl n{ncyl->keyword_range, macro::mode_from_subprogram(v.after, "G60"), may};
        // Once the program has used such a macro, the block is reported at
        // once; before, it waits for one (kept only until the first use).
        if (user_) report(ctx, n, *user_, "this program uses " + user_->name, user_range_);
        else pending_.push_back(std::move(n));
    }

    void end_program(RuleContext& ctx, const ProgramView&) override { flush(ctx); }

    bool same_as(const G60WithNcyl& o) const {
        return pending_ == o.pending_ && user_ == o.user_ && user_range_ == o.user_range_;
    }
    template <class Move>
    bool each_range(Move&& move) {
        for (Ncyl& n : pending_)
            if (!move(n.range) || (n.may && (!move(n.may->range) || !move(n.may->via_range)))) return false;
        return move(user_range_);
    }

private:
    void flush(RuleContext& ctx) {
        if (!user_) return;
        for (const auto& p : pending_) report(ctx, p, *user_, "this program uses " + user_->name, user_range_);
        pending_.clear();
    }

    struct Ncyl {
        ByteRange range;            // the NCYL keyword
        std::string from;           // where G60 came from, when a subprogram set it
        std::optional<Origin> may;  // G60 on some paths only: where it is set
        friend bool operator==(const Ncyl&, const Ncyl&) = default;
    };

    void report(RuleContext& ctx, const Ncyl& n, const MacroSpec& spec, const std::string& context,
                std::optional<ByteRange> call) {
        std::string src = forbidding_source(ctx.catalog(), spec);
        const std::string consequence = ": under G60 the control ignores NCYL, so the cycle runs here and the tool "
                                        "hits the workpiece (" + src + "); end G60 with G0 or G1 before this block, "
                                        "or drop NCYL and position without the macro";
        Diagnostic* found = nullptr;
        if (n.may) {
            found = report_may(ctx, kMeta, n.range,
                               "G60 may be modal where NCYL is on this block while " + context + " (" +
                                   macro::may_path(*n.may, "G60", "this block") + ", while other paths end it)" +
                                   consequence);
        } else {
            found = &ctx.report(kMeta, n.range, "G60 is modal and NCYL is on this block while " + context + consequence);
        }
        if (!found) return;
        Diagnostic& d = *found;
        if (n.may) macro::add_may_notes(ctx, d, *n.may, "G60");
        d.notes.push_back({"\"While using these programs, never use G60 together with NCYL. During G60, NCYL is "
                           "ignored and the tool collides with the workpiece.\" (" + src + ")",
                           std::nullopt});
        if (call) d.notes.push_back({spec.name + " is used here", ctx.resolve(*call)});
        if (!n.from.empty()) d.notes.push_back({n.from, std::nullopt});
    }

    std::vector<Ncyl> pending_;
    const MacroSpec* user_ = nullptr;
    ByteRange user_range_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP201() { return std::make_unique<G60WithNcyl>(); }

}  // namespace osplint
