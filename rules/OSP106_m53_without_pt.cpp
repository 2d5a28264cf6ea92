// OSP106 m53-without-pt: M53 in effect for a macro call that gives no PT.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP106",
    .name = "m53-without-pt",
    .severity = Severity::Error,
    .summary = "M53 is in effect for a macro call without PT (the macros do not read G71)",
    .category = RuleCategory::Alarm,
};

class M53WithoutPt final : public RuleBase<M53WithoutPt> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same PT, M words and return level.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // Only a macro that returns to PT under M53.
    bool sees_plain_calls_of(const MacroSpec& spec, CallKind) const override { return spec.m53 == M53Mode::ReturnToPT; }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || spec->m53 != M53Mode::ReturnToPT) return;
        if (c->kind != CallKind::Call && c->kind != CallKind::Modin && c->kind != CallKind::ModinPositioning) return;
        const ArgSpec* pt = spec->arg("PT");
        // An argument the spec has is found by given(), by its name as written too.
        if (pt ? macro::given(*c, *pt) != nullptr : c->arg("PT") != nullptr) return;
        const Word* m53 = macro::m_code(*c, 53);
        bool in_effect = m53 != nullptr;
        if (!in_effect && !macro::m_code(*c, 52) && !macro::m_code(*c, 54)) {
            // Modal M53 from an earlier block. On positioning blocks of an open
            // MODIN it was reported on the MODIN line already.
            if (c->kind == CallKind::ModinPositioning) return;
            in_effect = v.before.return_level.is(53);
        }
        if (!in_effect) return;
        ByteRange where = m53 ? m53->range : macro::call_range(*c, v.block);
        auto& d = ctx.report(kMeta, where,
                             std::string("M53 is in effect but ") + spec->name +
                                 " has no PT: the macro returns to PT, not to the G71 level, and stops with an "
                                 "alarm when PT is missing; add PT=<return level>");
        d.notes.push_back({"\"If M53 is commanded without a PT command -> alarm\" (" +
                               macro::note_ref(ctx.catalog(), *spec, "M53") +
                               "); G71 is not read because the macro is not a fixed cycle",
                           std::nullopt});
        if (!m53) d.notes.push_back({"M53 is modal from an earlier block", std::nullopt});
        if (c->kind == CallKind::ModinPositioning)
            d.notes.push_back({"the macro runs here because MODIN " + spec->name + " (line " +
                                   std::to_string(c->modin_line) + ") is open",
                               std::nullopt});
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP106() { return std::make_unique<M53WithoutPt>(); }

}  // namespace osplint
