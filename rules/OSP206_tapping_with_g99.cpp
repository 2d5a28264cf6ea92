// OSP206 tapping-with-g99: a tapper cycle (G84 normal tap, G114/OG84L) under G99.
#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP206",
    .name = "tapping-with-g99",
    .severity = Severity::Error,
    .summary = "G84 (with a tapper) or G114 under G99 (R-point return)",
    .category = RuleCategory::WrongMotion,
};

bool tapper_cycle(const RuleContext& ctx, const ActiveCycle& c) {
    if (!c.macro.empty()) {
        const MacroSpec* m = ctx.catalog().find(c.macro);
        return m && m->tapping;
    }
    const CycleSpec* s = ctx.catalog().find_cycle(c.code);
    return s && s->tapping;
}

const Word* g_word(const Block& b, double code) {
    for (const auto& w : b.words)
        if (w.address == "G" && w.number && *w.number == code) return &w;
    return nullptr;
}

class TappingWithG99 final : public RuleBase<TappingWithG99> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same cycle and return mode.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // no fixed cycle is modal on a plain call line
    // check_block returns at once unless a fixed cycle is modal after the block.
    uint8_t block_needs() const override { return kCycleAfter; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const ActiveCycle* c = active_cycle(v.after);
        if (!c || !v.after.cycle_return.is(CycleReturn::R) || !tapper_cycle(ctx, *c)) return;
        // Synchronised tapping (M843 ... M845) uses no tapper (the synchronized tap of the fixed cycles manual).
        if (c->macro.empty() && !v.after.sync_tap.is(false)) return;
        // Report where the combination starts: the cycle is commanded under G99,
        // or G99 is commanded while the cycle is modal.
        const ActiveCycle* was = active_cycle(v.before);
        const bool same_cycle = was && was->code == c->code && was->start_line == c->start_line;
        if (same_cycle && v.before.cycle_return.is(CycleReturn::R)) return;
        const Word* where = g_word(v.block, 99);
        if (!where) where = g_word(v.block, c->code);
        const bool macro_cycle = !c->macro.empty();
        std::string msg =
            fmt::format("G{} runs a tapper under G99 (R-point return): after each hole the tool moves on at the R "
                        "point, while the tap may still be engaged in the workpiece, which breaks the tap and the "
                        "workpiece ({}{}); use G98 (return to the initial point) for this cycle",
                        c->code, cite("fixed-cycles/g84-normal"), macro_cycle ? ", read for G114" : "");
        auto& d = ctx.report(kMeta, where ? where->range : v.block.range, std::move(msg));
        if (macro_cycle)
            d.notes.push_back({"The " + cite("tap-cycle") + " does not mention G99; " + c->macro +
                                   " is a fixed-cycle compatible tapping cycle for auto-reverse tappers, which "
                                   "return with the tap extended (" + cite("tap-cycle/cautions-7") +
                                   "), so the tapper warning for G84 is applied to it (an inference, not stated "
                                   "in the manuals)",
                               std::nullopt});
        if (!same_cycle && !c->start_range.empty() && (!where || !(c->start_range == where->range)))
            d.notes.push_back({fmt::format("G{} is commanded here", c->code), ctx.resolve(c->start_range)});
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP206() { return std::make_unique<TappingWithG99>(); }

}  // namespace osplint
