// OSP003 duplicate-sequence-name: a sequence name defined twice in one program.
// Off by default: posts restart or wrap their numbers, and a duplicate only
// matters when a jump names it, which OSP006 reports.
#include <array>
#include <functional>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/rule.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP003",
    .name = "duplicate-sequence-name",
    .severity = Severity::Warning,
    .summary = "A sequence name is defined twice in one program",
    .category = RuleCategory::Suspicious,
    .enabled_by_default = false,
    .blocks = RuleBlocks::Named,
};

// The first definition of each name is kept, for the note, for the first
// kKeepFirst names of a program. Beyond that, names of the form N<digits>
// with up to kMaxDigits digits are kept in one bitmap per digit count, so
// that a posted program with a sequence number on each of millions of blocks
// is checked in bounded memory (at most 12.5 MB for the eight-digit names):
// their duplicates are still reported, without the first definition's place.
constexpr size_t kKeepFirst = 100000;
constexpr size_t kMaxDigits = 8;

class DuplicateSequenceName final : public RuleBase<DuplicateSequenceName> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a repeated block has no sequence name.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call line has no sequence name
    void begin_program(RuleContext&, const ProgramView&) override {
        first_.clear();
        for (auto& b : seen_) b.clear();
        set_wants_plain_moves(false);  // only those with a sequence name (RuleBlocks::Named)
    }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        if (v.block.sequence) check_name(ctx, v.block.sequence->name, v.block.sequence->range);
    }
    bool takes_plain_values() const override { return true; }
    void check_plain_move(RuleContext& ctx, const PlainMoveView& v) override {
        if (!v.move.sequence.empty()) check_name(ctx, v.move.sequence, v.move.sequence_range);
    }

    bool same_as(const DuplicateSequenceName& o) const { return first_ == o.first_ && seen_ == o.seen_; }
    template <class Move>
    bool each_range(Move&& move) {
        for (auto& [name, range] : first_)
            if (!move(range)) return false;
        return true;
    }

private:
    void check_name(RuleContext& ctx, std::string_view name, ByteRange range) {
        if (auto it = first_.find(name); it != first_.end()) {
            report(ctx, name, range, ctx.resolve(it->second));
            return;
        }
        if (first_.size() < kKeepFirst || !set_bit(name)) {
            if (first_.size() < kKeepFirst || !numeric(name)) first_.emplace(name, range);
            return;
        }
        report(ctx, name, range, std::nullopt);
    }
    static void report(RuleContext& ctx, std::string_view name, ByteRange range, std::optional<SourceRange> first) {
        auto& d = ctx.report(kMeta, range,
                             "sequence name " + std::string(name) +
                                 " is already defined in this program: a GOTO or IF to it may land on the other block");
        if (first)
            d.notes.push_back({"first defined here", first});
        else
            d.notes.push_back({"first defined earlier in this program (its place is kept for the first " +
                                   std::to_string(kKeepFirst) + " sequence names of a program only)",
                               std::nullopt});
    }
    // N followed by 1..kMaxDigits digits.
    static bool numeric(std::string_view name) {
        if (name.size() < 2 || name.size() > kMaxDigits + 1 || name[0] != 'N') return false;
        for (size_t i = 1; i < name.size(); ++i)
            if (name[i] < '0' || name[i] > '9') return false;
        return true;
    }
    // For a numeric name: marks it seen; true when it was seen before. False
    // (nothing marked) for other names.
    bool set_bit(std::string_view name) {
        if (!numeric(name)) return false;
        const size_t digits = name.size() - 1;
        uint64_t value = 0;
        uint64_t count = 1;
        for (size_t i = 1; i < name.size(); ++i) {
            value = value * 10 + static_cast<uint64_t>(name[i] - '0');
            count *= 10;
        }
        auto& bits = seen_[digits];
        if (bits.empty()) bits.assign((count + 63) / 64, 0);
        const uint64_t mask = uint64_t(1) << (value % 64);
        const bool was = (bits[value / 64] & mask) != 0;
        bits[value / 64] |= mask;
        return was;
    }

    std::map<std::string, ByteRange, std::less<>> first_;
    std::array<std::vector<uint64_t>, kMaxDigits + 1> seen_;  // by digit count
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP003() { return std::make_unique<DuplicateSequenceName>(); }

}  // namespace osplint
