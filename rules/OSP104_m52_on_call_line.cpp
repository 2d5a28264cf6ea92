// OSP104 m52-on-call-line: M52 on the CALL/MODIN line of a subprogram macro.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP104",
    .name = "m52-on-call-line",
    .severity = Severity::Error,
    .summary = "M52 on the CALL/MODIN line of a macro is ignored; command PM=52",
    .category = RuleCategory::WrongMotion,
    .fix = FixSafety::Safe,
};

class M52OnCallLine final : public RuleBase<M52OnCallLine> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same M words and arguments.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line has no M word
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || (c->kind != CallKind::Call && c->kind != CallKind::Modin)) return;
        if (!macro::is_subprogram_macro(*spec)) return;
        const Word* m52 = macro::m_code(*c, 52);
        if (!m52) return;
        auto& d = ctx.report(kMeta, m52->range,
                             "M52 on the " + std::string(macro::call_kind_name_short(c->kind)) + " line of " +
                                 spec->name + " is not read by the macro: the tool does not return to the upper "
                                 "limit after the cycle; command PM=52 instead");
        d.notes.push_back({"\"M52 commanded in the CALL block has no effect, because the sub cannot read M52 "
                           "internally. In that case command PM=52.\" (" +
                               macro::common_ref(ctx.catalog(), *spec, "M52") + ")",
                           std::nullopt});
        Fix fix;
        fix.safe = true;  // what the manual asks for, with the same meaning
        if (const MacroArg* pm = c->arg("PM"); pm && pm->word) {
            // PM is already there: drop the M52 (and the blank before it).
            fix.title = "Remove M52 (PM is already given)";
            ByteRange r = m52->range;
            const std::string_view line = ctx.text(v.block.range);
            const uint32_t base = v.block.range.begin;
            while (r.begin > base && (line[r.begin - 1 - base] == ' ' || line[r.begin - 1 - base] == '\t')) --r.begin;
            fix.edits.push_back({ctx.resolve(r), ""});
        } else {
            fix.title = "Replace M52 by PM=52";
            fix.edits.push_back({ctx.resolve(m52->range), "PM=52"});
        }
        d.fixes.push_back(std::move(fix));
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP104() { return std::make_unique<M52OnCallLine>(); }

}  // namespace osplint
