// OSP101 missing-required-argument: an argument whose omission raises an alarm is absent.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP101",
    .name = "missing-required-argument",
    .severity = Severity::Error,
    .summary = "A macro call lacks an argument the manual marks as required (alarm when omitted)",
    .category = RuleCategory::Alarm,
};

class MissingRequiredArgument final : public RuleBase<MissingRequiredArgument> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): a repeat gives the same arguments.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::documented_invocation(c);
        if (!spec) return;
        // A call of the same macro that gives the arguments the last one
        // lacking none gave (the same slots of MacroCall::given_index) lacks none.
        const bool linked = c->given_index.size() == spec->args.size();
        if (linked && spec == quiet_spec_ && c->given_index == quiet_given_) return;
        // A CALL-style use of a macro documented only in another form is OSP109's
        // finding; its required arguments are still those of the table.
        std::vector<const ArgSpec*> missing;
        for (const auto& a : spec->args)
            if (a.required() && !macro::given(*c, a)) missing.push_back(&a);
        if (missing.empty()) {
            if (linked) {
                quiet_spec_ = spec;
                quiet_given_ = c->given_index;
            }
            return;
        }
        std::string list, details;
        for (size_t i = 0; i < missing.size(); ++i) {
            const ArgSpec& a = *missing[i];
            std::string shown = a.name;
            if (c->kind == CallKind::GCode && spec->gcode_form)
                for (const auto& [addr, arg] : spec->gcode_form->address_map)
                    if (arg == a.name) shown = addr;
            list += (i ? (i + 1 == missing.size() ? " and " : ", ") : "") + shown;
            details += (i ? "; " : "") + shown + " (" + a.meaning + ")";
        }
        auto& d = ctx.report(kMeta, macro::call_range(*c, v.block),
                             spec->name + " is missing " + list +
                                 ": the macro stops the machine with an alarm (B [423]/[619]) when it runs; add " +
                                 (missing.size() == 1 ? "it" : "them"));
        d.notes.push_back({"required by the argument table (" + macro::args_ref(*spec) + "): " + details, std::nullopt});
        for (const ArgSpec* a : missing)
            if (!a->note.empty()) d.notes.push_back({a->name + ": " + a->note, std::nullopt});
    }

    // Not state: what the rule reports is the same without it.
    bool same_as(const MissingRequiredArgument&) const { return true; }

private:
    const MacroSpec* quiet_spec_ = nullptr;
    std::vector<uint16_t> quiet_given_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP101() { return std::make_unique<MissingRequiredArgument>(); }

}  // namespace osplint
