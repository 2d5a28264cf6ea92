// OSP211 g114-declaration-not-tapped: X/Y on the G114 (OG84L) declaration block
// only position the tool; no hole is tapped there.
#include <optional>

#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP211",
    .name = "g114-declaration-not-tapped",
    .severity = Severity::Warning,
    .summary = "X/Y on the G114 declaration block are not tapped, and no later block taps there",
    .category = RuleCategory::Suspicious,
};

bool positions_hole(const Block& b) {
    for (const auto& w : b.words)
        if (w.address == "X" || w.address == "Y" || w.address == "Z" || w.address == "R") return true;
    for (const auto& s : b.statements)
        if (s.kind == StmtKind::CoordCalc) return true;
    return false;
}

class G114DeclarationNotTapped final : public RuleBase<G114DeclarationNotTapped> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a G114
    // line starts its cycle, so it changes the state and is never one; a hole
    // only settles the G114 line just before it, which a repeat never follows.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // A pending declaration is settled on the block that ends its cycle, so
    // none is pending when a plain move runs (no cycle is modal then).

    void begin_program(RuleContext&, const ProgramView&) override { pending_.reset(); }

    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        if (c && c->kind == CallKind::GCode && c->spec && !c->spec->cancel.empty()) {
            pending_.reset();
            const Word* x = v.block.find("X");
            const Word* y = v.block.find("Y");
            if (!(x || y) || !v.after.plane.is(Plane::G17) || !v.after.x.known || !v.after.y.known) return;
            const ActiveCycle* cyc = active_cycle(v.after);
            if (!cyc) return;
            pending_ = Pending{c->name_range, x ? x->range : y->range, v.after.x.value, v.after.y.value,
                               cyc->start_line, std::string(ctx.text(c->name_range))};
            return;
        }
        if (!pending_) return;
        const ActiveCycle* cyc = active_cycle(v.after);
        if (!cyc || cyc->start_line != pending_->start_line || v.block.has_code("G", 80)) {
            // The mode ended (or is no longer known) before any hole.
            if (no_cycle(v.after)) report(ctx, true);
            pending_.reset();
            return;
        }
        if (!positions_hole(v.block) || v.after.ncyl || v.after.g100 || v.after.noex) return;
        // The first hole of the mode: is it at the declared position?
        if (v.after.x.known && v.after.y.known && v.after.x.value == pending_->x && v.after.y.value == pending_->y) {
            pending_.reset();
            return;
        }
        if (v.after.x.known && v.after.y.known) report(ctx, false);
        pending_.reset();
    }

    void end_program(RuleContext&, const ProgramView&) override { pending_.reset(); }

    bool same_as(const G114DeclarationNotTapped& o) const { return pending_ == o.pending_; }
    template <class Move>
    bool each_range(Move&& move) {
        return !pending_ || (move(pending_->g_range) && move(pending_->xy_range));
    }

private:
    struct Pending {
        ByteRange g_range, xy_range;
        double x = 0, y = 0;
        uint32_t start_line = 0;
        std::string g;
        friend bool operator==(const Pending&, const Pending&) = default;
    };

    void report(RuleContext& ctx, bool no_hole) {
        const Pending& p = *pending_;
        auto& d = ctx.report(
            kMeta, p.xy_range,
            fmt::format("X{} Y{} on the {} line only position the tool: the declaration block runs like NCYL G8*, "
                        "without the cycle axis, so no hole is tapped there ({}), and {}; if a hole "
                        "is wanted at this position, command X{} Y{} again on the block after the {} line",
                        macro::format_number(p.x), macro::format_number(p.y), p.g, cite("tap-cycle/cautions-3"),
                        no_hole ? "the mode ends before any hole" : "the next hole is elsewhere",
                        macro::format_number(p.x), macro::format_number(p.y), p.g));
        d.notes.push_back({"X/Y of the declaration block are a \"dummy positioning\" (" + cite("tap-cycle/args") + ")",
                           std::nullopt});
    }

    std::optional<Pending> pending_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP211() { return std::make_unique<G114DeclarationNotTapped>(); }

}  // namespace osplint
