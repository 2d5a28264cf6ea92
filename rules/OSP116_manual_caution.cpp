// OSP116 manual-caution: a macro or fixed cycle is commanded in a situation
// its manual warns about. The situations are data: the `cautions` of the
// catalog entry (docs/catalog.md), each with a `when` condition decided from
// the call's words and the modal state at the call.
#include "rules/macro_support.h"
#include "semantics/conditions.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP116",
    .name = "manual-caution",
    .severity = Severity::Warning,
    .summary = "A macro or fixed cycle is commanded in a situation its manual warns about",
    .category = RuleCategory::Suspicious,
    .since = "0.1.0",
};

// What a caution's condition reads: the written arguments of the call (or of
// the block that starts a fixed cycle) and the modal state before it.
struct Site {
    const MacroSpec& spec;
    const MacroCall* call;  // nullptr: a fixed cycle's start block
    const BlockView& v;

    // The argument as written, or nullptr.
    const Word* word(const ArgSpec& a) const {
        if (call) {
            const MacroArg* m = macro::given(*call, a);
            return m ? m->word : nullptr;
        }
        if (const Word* w = find_address(v.block, a.name)) return w;
        for (const auto& alias : a.aliases)
            if (const Word* w = find_address(v.block, alias)) return w;
        return nullptr;
    }
    bool given(const ArgSpec& a) const {
        if (call) return macro::given(*call, a) != nullptr;
        return word(a) != nullptr;
    }
    Tri atom(const ConditionAtom& at) const {
        using K = ConditionAtom::Kind;
        switch (at.kind) {
            case K::Given: {
                const ArgSpec* a = spec.arg(at.arg);
                return a && given(*a) ? Tri::True : Tri::False;
            }
            case K::ArgEquals: {
                const ArgSpec* a = spec.arg(at.arg);
                if (!a || !given(*a)) return Tri::False;
                if (!call) return Tri::Unknown;
                const MacroArg* m = macro::given(*call, *a);
                if (!m->value.known) return Tri::Unknown;
                return m->value.value == at.value ? Tri::True : Tri::False;
            }
            case K::MCode: {
                const Val<int>& rl = v.after.return_level;
                if (!rl.known) return Tri::Unknown;
                return rl.value == at.number ? Tri::True : Tri::False;
            }
            default: return modal_atom(at, v.before);
        }
    }
    // Where to point: the first argument the condition names that is written,
    // else the call (or the cycle's G word).
    ByteRange range(const Caution& c) const {
        for (const ConditionAtom* at : c.when.atoms())
            if (!at->arg.empty())
                if (const ArgSpec* a = spec.arg(at->arg))
                    if (const Word* w = word(*a)) return w->range;
        if (call) return macro::call_range(*call, v.block);
        const ActiveCycle* cyc = active_cycle(v.after);
        if (!cyc) return v.block.range;
        return !cyc->start_range.empty() ? cyc->start_range : !cyc->command_range.empty() ? cyc->command_range : v.block.range;
    }
};

class ManualCaution final : public RuleBase<ManualCaution> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat). Unless a caution's condition reads a position in the plane.
    bool quiet_on_repeat(const Config& config, const MacroSpec* spec) const override {
        return !macro::reads_position_value(config.catalog, spec);
    }
    // A CALL whose cautions read none of the arguments its repeats change (the
    // modal state they read is the same); a hole of a cycle commanded earlier
    // (or of a G-code macro cycle): its repeats command nothing either.
    bool quiet_on_repeat_of(const BlockView& v) const override {
        if (const MacroSpec* spec = macro::shop_macro(v.call)) return macro::quiet_on_call_repeats(*spec, v);
        const ActiveCycle* c = v.call ? nullptr : active_cycle(v.after);
        return c && (!c->macro.empty() || cycle_start(*c, v.block) == CycleStart::Earlier);
    }
    // Only a macro with cautions, where it is commanded.
    bool sees_plain_calls_of(const MacroSpec& spec, CallKind kind) const override {
        return !spec.cautions.empty() && kind != CallKind::ModinPositioning;
    }
    // A macro call, or a fixed cycle modal after the block.
    uint8_t block_needs() const override { return kCall | kCycleAfter; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        if (v.call && v.call->spec && v.call->spec->kind == SpecKind::Macro) {
            // Where the macro is commanded; not each positioning block of an open MODIN.
            const CallKind k = v.call->kind;
            if (k == CallKind::Call || k == CallKind::Modin || k == CallKind::GCode || k == CallKind::MCode)
                check(ctx, Site{*v.call->spec, v.call, v});
            return;
        }
        // A fixed cycle commanded on this block (its G word is here).
        const ActiveCycle* c = active_cycle(v.after);
        if (!c || !c->macro.empty() || cycle_start(*c, v.block) == CycleStart::Earlier) return;
        if (const CycleSpec* spec = ctx.catalog().find_cycle(c->code)) check(ctx, Site{*spec, nullptr, v});
    }

private:
    static void check(RuleContext& ctx, const Site& site) {
        for (const Caution& c : site.spec.cautions) {
            if (c.when.eval([&](const ConditionAtom& at) { return site.atom(at); }) != Tri::True) continue;
            Diagnostic& d = ctx.report(kMeta, site.range(c),
                                       site.spec.name + ": " + c.text + " (" + macro::source_ref(site.spec, c.source) +
                                           ")");
            if (c.info && static_cast<int>(Severity::Info) < static_cast<int>(d.severity)) d.severity = Severity::Info;
        }
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP116() { return std::make_unique<ManualCaution>(); }

}  // namespace osplint
