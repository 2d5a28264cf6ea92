// OSP002 undefined-jump-target: GOTO / IF / a LAP-style N reference names a
// sequence name that the program does not define.
#include "engine/rule.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{"OSP002", "undefined-jump-target", Severity::Error,
                         "GOTO, IF or an N reference names a sequence name the program does not define"};

class UndefinedJumpTarget final : public Rule {
public:
    const RuleMeta& meta() const override { return kMeta; }
    bool sees_plain_moves(const Config&) const override { return false; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        for (const auto& st : v.block.statements) {
            if (st.kind != StmtKind::Goto && st.kind != StmtKind::If) continue;
            if (st.name.empty() || ctx.has_label(st.name)) continue;
            auto& d = ctx.report(kMeta, st.name_range,
                                 "jump target " + st.name + " is not a sequence name of this program: the control "
                                 "stops with an alarm when it executes this jump");
            d.notes.push_back({"sequence names are local to each program (O name); define " + st.name +
                                   " in this program or correct the name",
                               std::nullopt});
        }
        // LAP-style references inside a block: G85 N0207 / G87 NAT3.
        for (const auto& w : v.block.words) {
            if (w.address != "N" || w.value_text.empty()) continue;
            std::string label = "N" + w.value_text;
            if (ctx.has_label(label)) continue;
            ctx.report(kMeta, w.range, "sequence name " + label +
                                           " referenced here is not defined in this program: the cycle cannot find "
                                           "its contour and the control stops with an alarm");
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP002() { return std::make_unique<UndefinedJumpTarget>(); }

}  // namespace osplint
