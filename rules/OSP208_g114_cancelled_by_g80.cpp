// OSP208 g114-cancelled-by-g80: the G114 (OG84L) mode ended with G80, which
// leaves the spindle and feed overrides disabled.
#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP208",
    .name = "g114-cancelled-by-g80",
    .severity = Severity::Warning,
    .summary = "G114 (OG84L) cancelled by G80: the spindle and feed overrides stay disabled",
    .category = RuleCategory::WrongMotion,
    .fix = FixSafety::Unsafe,
};

class G114CancelledByG80 final : public RuleBase<G114CancelledByG80> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same G words under the same cycle.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // no fixed cycle is modal on a plain call line
    // check_block returns at once unless a fixed cycle is modal before the block.
    uint8_t block_needs() const override { return kCycleBefore; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const ActiveCycle* c = active_cycle(v.before);
        if (!c || c->macro.empty()) return;
        const MacroSpec* spec = ctx.catalog().find(c->macro);
        if (!spec || spec->cancel.empty()) return;
        const Word* g80 = nullptr;
        for (const auto& w : v.block.words)
            if (w.address == "G" && w.number && *w.number == 80) g80 = &w;
        if (!g80) return;
        // The cancel macro on the same block restores the overrides anyway.
        if (v.call && v.call->kind == CallKind::MCode && v.call->spec && v.call->spec->name == spec->cancel) return;
        std::string code;
        for (const auto& [c_code, macro] : ctx.catalog().registrations())
            if (macro == spec->cancel && c_code.size() > 1 && c_code[0] == 'M') code = c_code;
        const std::string g = fmt::format("G{}", c->code);
        std::string instead = code.empty() ? "the cancel M-code macro " + spec->cancel +
                                                 " (register it to an M code, M204 in the manual)"
                                           : code + " (" + spec->cancel + ")";
        auto& d = ctx.report(kMeta, g80->range,
                             "G80 ends the " + g + " (" + c->macro + ") mode but cannot undo what " + c->macro +
                                 " did: the spindle override and the cutting-feed override stay disabled for "
                                 "everything that follows (" + cite("tap-cycle/cautions-8") + "); cancel with " + instead +
                                 " instead");
        d.notes.push_back({"\"After this program is used, spindle override and cutting-feed override become invalid. "
                           "G80 naturally cannot undo this. If possible, cancel not with G80 but with the cancel "
                           "M-code macro.\" (" + cite("tap-cycle/cautions-8") + ")",
                           std::nullopt});
        if (!c->start_range.empty()) d.notes.push_back({g + " mode starts here", ctx.resolve(c->start_range)});
        if (code.empty()) return;
        // Replace G80 by the cancel code; when the block already has other
        // words, the cancel code takes G80's place on it. Unsafe: the cancel
        // macro does more than G80 (it restores the overrides), which is the
        // point, but it changes what the machine does.
        Fix fix;
        fix.title = "Replace G80 by " + code;
        fix.edits.push_back({ctx.resolve(g80->range), code});
        d.fixes.push_back(std::move(fix));
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP208() { return std::make_unique<G114CancelledByG80>(); }

}  // namespace osplint
