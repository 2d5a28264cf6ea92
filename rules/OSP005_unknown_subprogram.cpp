// OSP005 unknown-subprogram: CALL/MODIN of a program osplint cannot find.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP005",
    .name = "unknown-subprogram",
    .severity = Severity::Info,
    .summary = "CALL/MODIN names a program that is neither in the catalog nor in the checked files",
    .category = RuleCategory::Alarm,
};

class UnknownSubprogram final : public RuleBase<UnknownSubprogram> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a repeated block runs a catalog macro or none.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line calls a macro of the catalog
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        if (!c || (c->kind != CallKind::Call && c->kind != CallKind::Modin)) return;
        if (c->spec || c->name.empty() || ctx.has_program(c->name)) return;
        auto& d = ctx.report(kMeta, c->name_range,
                             c->name + " is neither a macro osplint knows nor a program of the checked files: its "
                                       "arguments are not checked, and the control alarms if it cannot find it");
        // Suggest a catalog macro with a close name (a typo such as OZAGA for OZAGR).
        for (const auto& m : ctx.catalog().macros())
            if (macro::edit_distance(m.name, c->name) == 1) {
                d.notes.push_back({"did you mean " + m.name + "?", std::nullopt});
                break;
            }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP005() { return std::make_unique<UnknownSubprogram>(); }

}  // namespace osplint
