// OSP004 missing-program-end: a main program without M02/M30, a subprogram without RTS.
#include <cctype>

#include <filesystem>

#include "engine/rule.h"
#include "semantics/summary.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP004",
    .name = "missing-program-end",
    .severity = Severity::Warning,
    .summary = "A main program without M02/M30, or a subprogram without RTS",
    .category = RuleCategory::Alarm,
    .blocks = RuleBlocks::All,
};

std::string upper_extension(std::string_view path) {
    auto dot = path.rfind('.');
    auto slash = path.find_last_of("/\\");
    if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) return {};
    std::string ext;
    for (char c : path.substr(dot + 1)) ext += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return ext;
}

class MissingProgramEnd final : public RuleBase<MissingProgramEnd> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a repeat has the words of the block before it, whose M02/M30 and place are known by then.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    void begin_program(RuleContext&, const ProgramView&) override {
        has_end_ = has_rts_ = false;
        anchor_.reset();
        set_wants_plain_moves(true);
    }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const Block& b = v.block;
        if (v.call && v.call->summary && !v.call->summary->returns) report_no_return(ctx, *v.call);
        if (!anchor_ && b.kind == LineKind::Block && !b.is_empty())
            anchor_ = b.program_name ? b.program_name->range : b.range;
        if (b.statement(StmtKind::Rts)) has_rts_ = true;
        for (const auto& w : b.words)
            if (w.address.size() == 1 && w.address[0] == 'M' && w.number && (*w.number == 2 || *w.number == 30))
                has_end_ = true;
        // A plain move has neither M02/M30 nor RTS: once the anchor is known,
        // plain moves do not matter here.
        set_wants_plain_moves(!anchor_);
    }

    // A CALL of a subprogram (analysed from its file) that no path ends with RTS.
    static void report_no_return(RuleContext& ctx, const MacroCall& c) {
        const SubprogramSummary& s = *c.summary;
        const std::string file = std::filesystem::path(s.file).filename().string();
        ctx.report(kMeta, c.name_range,
                   s.name + " (" + file + ", line " + std::to_string(s.line) +
                       ") has no RTS on any path: it ends the program (M02/M30) or runs off its end, so control "
                       "never returns here and the blocks after this CALL do not run; end " + s.name + " with RTS");
    }
    void end_program(RuleContext& ctx, const ProgramView& p) override {
        if (!anchor_) return;  // nothing but comments and tape marks
        std::string ext = upper_extension(ctx.path());
        if (ext == "SDF") return;  // schedule programs end with END
        bool main_program = !p.is_subprogram;
        std::string name = p.program.name.empty() ? std::string("this program") : p.program.name;
        if (main_program && !has_end_) {
            ctx.report(kMeta, *anchor_,
                       name + " has no M02 or M30: the program runs off its end and the control stops with an alarm "
                              "instead of ending the cycle");
        } else if (!main_program && !has_rts_ && !has_end_) {
            ctx.report(kMeta, *anchor_,
                       name + " is a subprogram without RTS: control never returns to the caller");
        }
    }

    bool same_as(const MissingProgramEnd& o) const {
        return has_end_ == o.has_end_ && has_rts_ == o.has_rts_ && anchor_ == o.anchor_;
    }
    template <class Move>
    bool each_range(Move&& move) {
        return !anchor_ || move(*anchor_);
    }

private:
    bool has_end_ = false;
    bool has_rts_ = false;
    std::optional<ByteRange> anchor_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP004() { return std::make_unique<MissingProgramEnd>(); }

}  // namespace osplint
