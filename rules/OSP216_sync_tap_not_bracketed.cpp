// OSP216 sync-tap-not-bracketed: the synchronised-tapping mode M843 is not
// closed by M845, or M3/M4/M5 are used while it is on.
#include <optional>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP216",
    .name = "sync-tap-not-bracketed",
    .severity = Severity::Warning,
    .summary = "M843 not closed by M845 before the program ends, or M3/M4/M5 inside M843 ... M845",
    .category = RuleCategory::WrongMotion,
};

class SyncTapNotBracketed final : public RuleBase<SyncTapNotBracketed> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    bool sees_plain_calls() const override { return false; }  // a plain call line has no M word

    // A repeat of a block with no M word neither reports nor moves the M843 kept.
    bool quiet_on_repeat_of(const BlockView& v) const override { return !v.block.find("M"); }

    void begin_program(RuleContext&, const ProgramView&) override { last_m843_.reset(); }

    // Only M words: M843 starts the mode, M3, M4, M5 inside it report.
    uint8_t block_needs() const override { return kMWord; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        for (const auto& w : v.block.words) {
            if (w.address != "M" || !w.number) continue;
            const double code = *w.number;
            if (code == 843) last_m843_ = w.range;
            if ((code == 3 || code == 4 || code == 5) && v.before.sync_tap.is(true)) {
                const bool stop = code == 5;
                auto& d = ctx.report(kMeta, w.range,
                                     "M" + std::to_string(static_cast<int>(code)) +
                                         " inside synchronised tapping (after M843, before M845): for synchronised "
                                         "tapping M03 becomes M843 and M05 becomes M845 (" + cite("fixed-cycles/g84-sync") + "); " +
                                         (stop ? std::string("end the mode with M845, alone on its line, after G80")
                                               : std::string("end the mode with M845 first, or use M843")));
                if (last_m843_) d.notes.push_back({"synchronised tapping starts here", ctx.resolve(*last_m843_)});
            }
        }
    }

    void end_program(RuleContext& ctx, const ProgramView& p) override {
        if (!p.final_state || !p.final_state->sync_tap.is(true) || !last_m843_) return;
        ctx.report(kMeta, *last_m843_,
                   "M843 starts synchronised tapping, but no M845 follows it before the program " +
                       std::string(p.is_subprogram ? "returns" : "ends") +
                       ": the spindle stays in the synchronised mode; after G80 write M845, alone on its line (" +
                       cite("fixed-cycles/g84-sync") + ")");
    }

    bool same_as(const SyncTapNotBracketed& o) const { return last_m843_ == o.last_m843_; }
    template <class Move>
    bool each_range(Move&& move) {
        return !last_m843_ || move(*last_m843_);
    }
private:
    std::optional<ByteRange> last_m843_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP216() { return std::make_unique<SyncTapNotBracketed>(); }

}  // namespace osplint
