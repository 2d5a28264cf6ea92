// OSP003 duplicate-sequence-name: a sequence name defined twice in one program.
#include <map>

#include "analyzer/rule.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{"OSP003", "duplicate-sequence-name", Severity::Warning,
                         "A sequence name is defined twice in one program"};

class DuplicateSequenceName final : public Rule {
public:
    const RuleMeta& meta() const override { return kMeta; }
    void begin_program(RuleContext&, const ProgramView&) override {
        first_.clear();
        set_wants_plain_moves(false);  // only those with a sequence name, which come anyway
    }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        if (!v.block.sequence) return;
        const Label& l = *v.block.sequence;
        auto [it, inserted] = first_.emplace(l.name, l.range);
        if (inserted) return;
        auto& d = ctx.report(kMeta, l.range,
                             "sequence name " + l.name + " is already defined in this program: a GOTO or IF to it "
                             "may land on the other block");
        d.notes.push_back({"first defined here", ctx.resolve(it->second)});
    }

private:
    std::map<std::string, ByteRange> first_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP003() { return std::make_unique<DuplicateSequenceName>(); }

}  // namespace osplint
