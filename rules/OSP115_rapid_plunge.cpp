// OSP115 rapid-plunge: the macro plunges to the Z point at rapid unless a feed
// argument is given (OKYLX/OKYLY step 4 without PFA).
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP115",
    .name = "rapid-plunge",
    .severity = Severity::Warning,
    .summary = "The macro plunges to the Z point at rapid because its plunge feed is omitted",
    .category = RuleCategory::WrongMotion,
};

// The action step that reaches PZ at rapid unless a feed argument is given:
// its feed reads "rapid; G1 F=<ARG> when <ARG> is given".
std::optional<std::pair<const ActionStep*, std::string>> rapid_plunge(const MacroSpec& s) {
    for (const auto& st : s.action) {
        if (st.target != "PZ" || st.feed.rfind("rapid", 0) != 0) continue;
        auto f = st.feed.find("F=");
        if (f == std::string::npos) continue;
        std::string arg;
        for (size_t i = f + 2; i < st.feed.size() && std::isalnum(static_cast<unsigned char>(st.feed[i])); ++i)
            arg += st.feed[i];
        if (!arg.empty() && s.arg(arg)) return std::make_pair(&st, arg);
    }
    return std::nullopt;
}

class RapidPlunge final : public RuleBase<RapidPlunge> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same arguments given.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // Only a macro that plunges at rapid without a feed argument, on the line that calls it.
    bool sees_plain_calls_of(const MacroSpec& spec, CallKind kind) const override {
        return kind != CallKind::ModinPositioning && rapid_plunge(spec).has_value();
    }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || !macro::is_invocation(*c)) return;
        if (spec != plunge_of_) {
            plunge_of_ = spec;
            plunge_ = rapid_plunge(*spec);
            feed_ = plunge_ ? spec->arg(plunge_->second) : nullptr;
        }
        if (!plunge_) return;
        const auto& plunge = plunge_;
        const ArgSpec* feed = feed_;
        if (macro::given(*c, *feed)) return;
        auto& d = ctx.report(kMeta, macro::call_range(*c, v.block),
                             spec->name + " without " + feed->name + " plunges to the Z point at rapid (step " +
                                 plunge->first->step + ": " + plunge->first->text + ", " + plunge->first->feed +
                                 "): a rapid plunge into the slot start breaks the cutter if anything is in the "
                                 "way; give " + feed->name + "=<feed> for a G1 plunge");
        d.notes.push_back({macro::source_ref(*spec, plunge->first->source) + "; " + feed->name + ": " + feed->meaning, std::nullopt});
        // The manual's own caution about this plunge, where the catalog has it.
        for (const auto& n : spec->notes)
            if (n.text.find(feed->name) != std::string::npos)
                d.notes.push_back({n.text + " (" + macro::source_ref(*spec, n.source) + ")", std::nullopt});
    }
    // What the last macro's steps say, read once per macro and not per call: not state.
    bool same_as(const RapidPlunge&) const { return true; }

private:
    const MacroSpec* plunge_of_ = nullptr;
    std::optional<std::pair<const ActionStep*, std::string>> plunge_;
    const ArgSpec* feed_ = nullptr;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP115() { return std::make_unique<RapidPlunge>(); }

}  // namespace osplint
