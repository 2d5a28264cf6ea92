// OSP117 feed-or-speed-not-commanded: a macro leaves its feed (PF) or its
// spindle speed (PS) to the current value, or a fixed cycle starts without F,
// while no F (or S) has been commanded in the program yet.
#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP117",
    .name = "feed-or-speed-not-commanded",
    .severity = Severity::Warning,
    .summary = "A macro or fixed cycle takes the current feed or spindle speed before any was commanded",
    .category = RuleCategory::WrongMotion,
    .since = "0.1.0",
};

// The argument of `spec` with this role that takes the current value when
// omitted (PF, PS; a fixed cycle's F, modal on the control).
const ArgSpec* current_value_arg(const MacroSpec& spec, ArgRole role) {
    for (const auto& a : spec.args)
        if (a.role == role && (a.omitted == ArgOmitted::Current || spec.kind == SpecKind::FixedCycle)) return &a;
    return nullptr;
}

bool block_has(const Block& b, const ArgSpec& a) {
    if (find_address(b, a.name)) return true;
    for (const auto& alias : a.aliases)
        if (find_address(b, alias)) return true;
    return false;
}

class FeedOrSpeedNotCommanded final : public RuleBase<FeedOrSpeedNotCommanded> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same arguments given, and feed and speed commanded or not as before.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // A macro call, or a fixed cycle modal after the block.
    uint8_t block_needs() const override { return kCall | kCycleAfter; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* call = v.call;
        if (call && call->spec && call->spec->kind == SpecKind::Macro) {
            const CallKind k = call->kind;
            if (k != CallKind::Call && k != CallKind::Modin && k != CallKind::GCode && k != CallKind::MCode) return;
            const ByteRange where = macro::call_range(*call, v.block);
            check(ctx, *call->spec, where, [&](const ArgSpec& a) { return macro::given(*call, a) != nullptr; },
                  v.before);
            return;
        }
        // A fixed cycle commanded on this block: its F is the modal feed.
        const ActiveCycle* c = active_cycle(v.after);
        // A cycle that may start here is checked too: the modal F and S it
        // reads are those of the state before the block on every path.
        if (!c || !c->macro.empty() || cycle_start(*c, v.block) == CycleStart::Earlier) return;
        const CycleSpec* spec = ctx.catalog().find_cycle(c->code);
        if (!spec) return;
        // A cycle continued from an earlier block keeps that block's F.
        if (active_cycle(v.before)) return;
        check(ctx, *spec, c->start_range.empty() ? c->command_range : c->start_range,
              [&](const ArgSpec& a) { return block_has(v.block, a); }, v.before);
    }

private:
    template <class Given>
    static void check(RuleContext& ctx, const MacroSpec& spec, ByteRange where, const Given& given,
                      const ModalState& before) {
        struct Need {
            ArgRole role;
            const Val<bool>& commanded;
            const char* what;     // "feed"
            const char* address;  // "F"
        };
        for (const Need& n : {Need{ArgRole::Feed, before.feed_commanded, "feed", "F"},
                              Need{ArgRole::Speed, before.speed_commanded, "spindle speed", "S"}}) {
            if (!n.commanded.is(false)) continue;  // the cheapest test first
            const ArgSpec* a = current_value_arg(spec, n.role);
            if (!a || given(*a)) continue;
            const bool cycle = spec.kind == SpecKind::FixedCycle;
            const std::string subject =
                cycle ? fmt::format("{} has no {} and", spec.name, a->name)
                      : fmt::format("{} takes its {} from the current {} ({} is not given), but", spec.name,
                                    a->meaning, n.address, a->name);
            const std::string remedy = cycle || a->name == n.address
                                           ? fmt::format("write {} on this block", a->name)
                                           : fmt::format("give {} or command {} before it", a->name, n.address);
            ctx.report(kMeta, where,
                       fmt::format("{} no {} has been commanded in this program yet: it runs at whatever {} the "
                                   "control last had ({}); {}",
                                   subject, n.address, n.what, macro::source_ref(spec, a->source), remedy));
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP117() { return std::make_unique<FeedOrSpeedNotCommanded>(); }

}  // namespace osplint
