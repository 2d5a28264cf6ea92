// OSP002 undefined-jump-target: GOTO / IF / a LAP-style N reference names a
// sequence name that the program does not define.
//
// A name may be defined after the jump, so the references are collected as
// the program is walked and checked once the walk has seen all of it.
#include <vector>

#include "engine/rule.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP002",
    .name = "undefined-jump-target",
    .severity = Severity::Error,
    .summary = "GOTO, IF or an N reference names a sequence name the program does not define",
    .category = RuleCategory::Alarm,
};

class UndefinedJumpTarget final : public RuleBase<UndefinedJumpTarget> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    bool sees_plain_calls() const override { return false; }  // a plain call line holds no jump and no N word
    // A repeat of a block with no jump and no N word adds no reference.
    bool quiet_on_repeat_of(const BlockView& v) const override {
        for (const auto& st : v.block.statements)
            if (st.kind == StmtKind::Goto || st.kind == StmtKind::If) return false;
        for (const auto& w : v.block.words)
            if (w.address == "N") return false;
        return true;
    }
    void begin_program(RuleContext&, const ProgramView&) override { refs_.clear(); }
    // Only jumps (GOTO, IF) and N words refer to a name.
    uint8_t block_needs() const override { return kStatement | kNamed; }
    void check_block(RuleContext&, const BlockView& v) override {
        for (const auto& st : v.block.statements) {
            if (st.kind != StmtKind::Goto && st.kind != StmtKind::If) continue;
            if (!st.name.empty()) refs_.push_back({st.name, st.name_range, true});
        }
        // LAP-style references inside a block: G85 N0207 / G87 NAT3.
        for (const auto& w : v.block.words)
            if (w.address == "N" && !w.value_text.empty()) refs_.push_back({"N" + w.value_text, w.range, false});
    }
    void end_program(RuleContext& ctx, const ProgramView&) override {
        for (const Ref& r : refs_) {
            if (ctx.has_label(r.name)) continue;
            if (r.jump) {
                auto& d = ctx.report(kMeta, r.range,
                                     "jump target " + r.name + " is not a sequence name of this program: the control "
                                     "stops with an alarm when it executes this jump");
                d.notes.push_back({"sequence names are local to each program (O name); define " + r.name +
                                       " in this program or correct the name",
                                   std::nullopt});
            } else {
                ctx.report(kMeta, r.range, "sequence name " + r.name +
                                               " referenced here is not defined in this program: the cycle cannot "
                                               "find its contour and the control stops with an alarm");
            }
        }
        refs_.clear();
    }

    bool same_as(const UndefinedJumpTarget& o) const { return refs_ == o.refs_; }
    template <class Move>
    bool each_range(Move&& move) {
        for (Ref& r : refs_)
            if (!move(r.range)) return false;
        return true;
    }

private:
    struct Ref {
        std::string name;
        ByteRange range;
        bool jump;
        friend bool operator==(const Ref&, const Ref&) = default;
    };
    std::vector<Ref> refs_;  // one per jump or N reference of the program: its structure, not its size
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP002() { return std::make_unique<UndefinedJumpTarget>(); }

}  // namespace osplint
