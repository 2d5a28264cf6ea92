// OSP001 syntax-error: every place the grammar cannot parse.
#include "engine/rule.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = kSyntaxErrorRule,
    .name = "syntax-error",
    .severity = Severity::Error,
    .summary = "The block does not parse as OSP part-program syntax",
    .category = RuleCategory::Alarm,
    .suppressible = false,
    .selected_by_prefix = false,
};

class SyntaxErrorRule final : public RuleBase<SyntaxErrorRule> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a repeated block has no syntax error.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line has no syntax error
    // Only a block with a syntax error reports.
    uint8_t block_needs() const override { return kError; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        for (const auto& e : v.block.errors) ctx.report(kMeta, e.range, e.message);
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP001() { return std::make_unique<SyntaxErrorRule>(); }

}  // namespace osplint
