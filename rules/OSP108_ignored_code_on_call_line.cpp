// OSP108 ignored-code-on-call-line: spindle/coolant codes the macro may ignore.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP108",
    .name = "ignored-code-on-call-line",
    .severity = Severity::Warning,
    .summary = "M3/M4/M7/M8/M12 on a CALL/MODIN line, or M7/M8/M12 on the G114 block, may be ignored",
    .category = RuleCategory::Suspicious,
};

class IgnoredCode final : public RuleBase<IgnoredCode> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same M words.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line has no M word
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec) return;
        if (c->m_codes.empty()) return;
        std::vector<int> codes;
        std::string what;
        bool subprogram = false;
        if ((c->kind == CallKind::Call || c->kind == CallKind::Modin) && macro::is_subprogram_macro(*spec)) {
            codes = {3, 4, 7, 8, 12};
            what = "the subprogram call block";
            subprogram = true;
        } else if (c->kind == CallKind::GCode && !spec->cancel.empty()) {
            codes = {7, 8, 12};
            what = "the declaration block";
        } else {
            return;
        }
        auto source = [&] {
            return subprogram ? macro::common_ref(ctx.catalog(), *spec, "M7/M8/M12") : cite("tap-cycle/cautions-4");
        };
        for (int code : codes) {
            const Word* w = macro::m_code(*c, code);
            if (!w) continue;
            bool spindle = code == 3 || code == 4;
            auto& d = ctx.report(kMeta, w->range,
                                 "M" + std::to_string(code) + " on " + what + " of " + spec->name +
                                     " may be ignored: " +
                                     (spindle ? "the spindle direction may not be what you expect"
                                              : "the cut may run without coolant") +
                                     "; command it on the block before");
            d.notes.push_back({"\"M3/4 and M7/8/12 codes commanded in the subprogram call block may be ignored\" (" +
                                   source() + ")",
                               std::nullopt});
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP108() { return std::make_unique<IgnoredCode>(); }

}  // namespace osplint
