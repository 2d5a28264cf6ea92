// OSP111 g91-absolute-cycle-axis: under G91 the macros' cycle-axis arguments stay absolute.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP111",
    .name = "g91-absolute-cycle-axis",
    .severity = Severity::Info,
    .summary = "A macro called under G91: its cycle-axis arguments are still absolute",
    .category = RuleCategory::WrongMotion,
    .reports_may = true,
};

class G91AbsoluteCycleAxis final : public RuleBase<G91AbsoluteCycleAxis> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same arguments given under the same G90/G91.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || spec->g91 != G91Mode::CycleAxisAbsolute) return;
        if (c->kind != CallKind::Call && c->kind != CallKind::Modin) return;
        const Origin* may = nullptr;  // G91 on some paths only
        if (!v.before.distance.known) {
            may = v.before.g91_from.find();
            if (!may) return;
        } else if (!v.before.distance.is(Distance::Incremental)) {
            return;
        }
        std::string cycle_args, plane_args;
        for (const auto& a : spec->args) {
            if (!macro::given(*c, a)) continue;
            if (a.role == ArgRole::Cycle) cycle_args += (cycle_args.empty() ? "" : ", ") + a.name;
            else if (a.role == ArgRole::Position) plane_args += (plane_args.empty() ? "" : ", ") + a.name;
        }
        std::string msg = spec->name + (may ? " may be called under G91 (" + macro::may_path(*may, "G91", "this call") +
                                                  ", while other paths reach it in G90): "
                                            : std::string(" is called under G91: "));
        msg += cycle_args.empty() ? std::string("its cycle-axis arguments") : cycle_args;
        msg += " are still measured from the work origin (absolute)";
        if (!plane_args.empty()) msg += ", while " + plane_args + " are incremental";
        msg += "; check that these values are meant that way";
        Diagnostic* found = may ? report_may(ctx, kMeta, c->name_range, std::move(msg))
                                : &ctx.report(kMeta, c->name_range, std::move(msg));
        if (!found) return;
        Diagnostic& d = *found;
        if (may) macro::add_may_notes(ctx, d, *may, "G91");
        d.notes.push_back({"\"Cycle-axis dimensions: command them as dimensions from the workpiece origin even "
                           "during G91 mode. (The positioning-plane axes follow G90/G91.)\" (" + macro::note_ref(ctx.catalog(), *spec, "Cycle-axis dimensions") + ")",
                           std::nullopt});
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP111() { return std::make_unique<G91AbsoluteCycleAxis>(); }

}  // namespace osplint
