// OSP203 modal-call-left-open: MODIN without MODOUT before the program ends, or
// a MODIN while another one is active.
#include <map>
#include <string>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP203",
    .name = "modal-call-left-open",
    .severity = Severity::Warning,
    .summary = "MODIN without MODOUT before the program ends, or MODIN while another MODIN is active",
    .category = RuleCategory::WrongMotion,
};

class ModalCallLeftOpen final : public RuleBase<ModalCallLeftOpen> {
public:
    const RuleMeta& meta() const override { return kMeta; }

    void begin_program(RuleContext&, const ProgramView&) override { modins_.clear(); }

    void check_block(RuleContext& ctx, const BlockView& v) override {
        const Statement* st = v.block.statement(StmtKind::Modin);
        if (!st) return;
        ByteRange where{st->keyword_range.begin, st->name_range.empty() ? st->keyword_range.end : st->name_range.end};
        modins_[v.block.line] = where;
        const ActiveModin* open = active_modin(v.before);
        if (!open) return;
        auto& d = ctx.report(kMeta, where,
                             "MODIN " + st->name + " while MODIN " + open->macro + " (line " +
                                 std::to_string(open->line) + ") is still active: the new modal call replaces it "
                                 "without a MODOUT, so it is easy to lose track of which macro runs after each "
                                 "positioning block (MODIN turns the call-after-positioning mode on until MODOUT); "
                                 "write MODOUT before this line");
        if (auto it = modins_.find(open->line); it != modins_.end())
            d.notes.push_back({"MODIN " + open->macro + " is opened here", ctx.resolve(it->second)});
    }

    void end_program(RuleContext& ctx, const ProgramView& p) override {
        if (!p.final_state) return;
        const ActiveModin* open = active_modin(*p.final_state);
        if (!open) return;
        auto it = modins_.find(open->line);
        if (it == modins_.end()) return;
        ctx.report(kMeta, it->second,
                   "MODIN " + open->macro + " is never closed: there is no MODOUT before the program ends, so every "
                   "positioning block after the last hole still runs " + open->macro + (p.is_subprogram ?
                   " (including the caller's blocks after the return)" : std::string()) +
                   " (MODIN turns the call-after-positioning mode on until MODOUT); write MODOUT after the last hole "
                   "of this pattern");
    }

private:
    std::map<uint32_t, ByteRange> modins_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP203() { return std::make_unique<ModalCallLeftOpen>(); }

}  // namespace osplint
