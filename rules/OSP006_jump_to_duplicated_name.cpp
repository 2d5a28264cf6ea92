// OSP006 jump-to-duplicated-name: a GOTO or IF names a sequence name that
// the program defines more than once.
//
// Only the names some jump or N word references are kept (the engine knows
// them from the outline before the walk), so a posted program that numbers
// every block, and restarts its numbers, costs no memory here.
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "engine/rule.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP006",
    .name = "jump-to-duplicated-name",
    .severity = Severity::Warning,
    .summary = "A GOTO or IF jumps to a sequence name the program defines more than once",
    .category = RuleCategory::Suspicious,
    .blocks = RuleBlocks::Named,
};

// Definitions kept per name for the notes; the rest are only counted.
constexpr size_t kNotedDefinitions = 8;

class JumpToDuplicatedName final : public RuleBase<JumpToDuplicatedName> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a repeated block has no sequence name and no jump.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line has no sequence name and no jump
    void begin_program(RuleContext&, const ProgramView&) override {
        defs_.clear();
        jumps_.clear();
        set_wants_plain_moves(false);  // a definition has a sequence name (RuleBlocks::Named)
    }
    // Only sequence names and jumps (GOTO, IF) are kept.
    uint8_t block_needs() const override { return kStatement | kNamed; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        if (v.block.sequence) definition(ctx, v.block.sequence->name, v.block.sequence->range);
        for (const auto& st : v.block.statements)
            if ((st.kind == StmtKind::Goto || st.kind == StmtKind::If) && !st.name.empty())
                jumps_.push_back({st.name, st.name_range});
    }
    bool takes_plain_values() const override { return true; }
    void check_plain_move(RuleContext& ctx, const PlainMoveView& v) override {
        if (!v.move.sequence.empty()) definition(ctx, v.move.sequence, v.move.sequence_range);
    }
    void end_program(RuleContext& ctx, const ProgramView&) override {
        for (const Jump& j : jumps_) {
            auto it = defs_.find(j.name);
            if (it == defs_.end() || it->second.count < 2) continue;
            const Defs& d = it->second;
            std::string lines;
            for (size_t i = 0; i < d.places.size(); ++i) {
                if (i) lines += i + 1 == d.places.size() && d.count == d.places.size() ? " and " : ", ";
                lines += std::to_string(d.places[i].start.line);
            }
            if (d.count > d.places.size()) lines += " and " + std::to_string(d.count - d.places.size()) + " more";
            auto& diag = ctx.report(kMeta, j.range,
                                    "jump target " + j.name + " is defined " + std::to_string(d.count) +
                                        " times in this program (lines " + lines +
                                        "): the manuals do not say which of them the control reaches, so "
                                        "osplint follows the jump to every one of them");
            for (const SourceRange& r : d.places) diag.notes.push_back({j.name + " defined here", r});
            diag.notes.push_back({"give each block a name of its own, or jump to a name defined once", std::nullopt});
        }
        jumps_.clear();
        defs_.clear();
    }

    bool same_as(const JumpToDuplicatedName& o) const { return defs_ == o.defs_ && jumps_ == o.jumps_; }
    template <class Move>
    bool each_range(Move&& move) {
        for (auto& [name, d] : defs_)
            for (SourceRange& r : d.places)
                if (!move(r.bytes)) return false;
        for (Jump& j : jumps_)
            if (!move(j.range)) return false;
        return true;
    }

private:
    void definition(RuleContext& ctx, std::string_view name, ByteRange range) {
        if (!ctx.is_jump_target(name)) return;
        Defs& d = defs_[std::string(name)];
        // Resolved now, while the block is in hand: at the program's end the
        // engine would have to read back to it for each note.
        if (d.places.size() < kNotedDefinitions) d.places.push_back(ctx.resolve(range));
        ++d.count;
    }
    struct Defs {
        std::vector<SourceRange> places;  // the first kNotedDefinitions
        size_t count = 0;
        friend bool operator==(const Defs& a, const Defs& b) {
            return a.count == b.count && a.places.size() == b.places.size() &&
                   std::equal(a.places.begin(), a.places.end(), b.places.begin(), [](const SourceRange& x, const SourceRange& y) {
                       return x.bytes == y.bytes && x.start == y.start && x.end == y.end;
                   });
        }
    };
    struct Jump {
        std::string name;
        ByteRange range;
        friend bool operator==(const Jump&, const Jump&) = default;
    };
    std::unordered_map<std::string, Defs> defs_;  // names jumped to: the program's structure
    std::vector<Jump> jumps_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP006() { return std::make_unique<JumpToDuplicatedName>(); }

}  // namespace osplint
