// OSP109 unsupported-call-mode: a macro used in a way its manual says does not work.
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP109",
    .name = "unsupported-call-mode",
    .severity = Severity::Error,
    .summary = "A macro is invoked in a form or mode its manual does not support",
    .category = RuleCategory::WrongMotion,
    .reports_may = true,
};

constexpr std::string_view kG91Quote =
    "\"This program cannot be used with MODIN. It cannot be used in G91 mode either ... In either case no alarm "
    "results; the motion is executed but is incorrect\" (";

std::string documented_forms(const MacroSpec& s) {
    std::string out;
    for (MacroForm f : s.forms) {
        std::string name;
        switch (f) {
            case MacroForm::Call: name = "CALL"; break;
            case MacroForm::Modin: name = "MODIN"; break;
            case MacroForm::GCode:
            case MacroForm::MCode: {
                name = f == MacroForm::GCode ? "its G-code macro" : "its M-code macro";
                for (const auto& code : s.codes) name += " " + code;
                break;
            }
        }
        out += (out.empty() ? "" : " or ") + name;
    }
    return out;
}

class UnsupportedCallMode final : public RuleBase<UnsupportedCallMode> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same macro and kind of call, under the same G90/G91.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls_of(const MacroSpec&, CallKind kind) const override {
        return kind != CallKind::ModinPositioning;  // about the CALL or MODIN line
    }
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        const MacroSpec* spec = macro::shop_macro(c);
        if (!spec || (c->kind != CallKind::Call && c->kind != CallKind::Modin)) return;
        MacroForm form = c->kind == CallKind::Call ? MacroForm::Call : MacroForm::Modin;
        if (!spec->has_form(form)) {
            std::string used(macro::call_kind_name_short(c->kind));
            std::string consequence = spec->g91 == G91Mode::Unsupported
                                          ? "no alarm results, but the motion is wrong (positions are shifted)"
                                          : "the manual documents no such use, so the motion is not defined";
            auto& d = ctx.report(kMeta, c->name_range,
                                 spec->name + " cannot be used with " + used + ": " + consequence +
                                     "; use " + documented_forms(*spec));
            d.notes.push_back({"the manual documents " + spec->name + " only as " + documented_forms(*spec) +
                                   " (" + macro::format_ref(*spec) + ")",
                               std::nullopt});
            return;
        }
        if (spec->g91 == G91Mode::Unsupported && v.before.distance.is(Distance::Incremental)) {
            auto& d = ctx.report(kMeta, c->name_range,
                                 spec->name + " cannot be used in G91 mode: its cutter path is not closed internally, "
                                              "so no alarm results but the slot is cut at shifted positions; "
                                              "command G90 before the call");
            d.notes.push_back({std::string(kG91Quote) + macro::source_ref(*spec, "") + ")", std::nullopt});
            if (auto from = macro::mode_from_subprogram(v.before, "G91"); !from.empty())
                d.notes.push_back({from, std::nullopt});
            return;
        }
        if (spec->g91 == G91Mode::Unsupported && !v.before.distance.known)
            if (const Origin* g91 = v.before.g91_from.find()) report_may_g91(ctx, *spec, *c, *g91);
    }

private:
    // The paths that reach the call disagree on G90/G91, and on one of them
    // G91 is in effect: a loop's jump or a branch brings it.
    static void report_may_g91(RuleContext& ctx, const MacroSpec& spec, const MacroCall& c, const Origin& g91) {
        Diagnostic* d = report_may(ctx, kMeta, c.name_range,
                                   spec.name + " may run in G91 mode here: " + macro::may_path(g91, "G91", "this call") +
                                       ", while other paths reach it in G90; under G91 no alarm results but the slot "
                                       "is cut at shifted positions; command G90 before the call");
        if (!d) return;
        macro::add_may_notes(ctx, *d, g91, "G91");
        d->notes.push_back({std::string(kG91Quote) + macro::source_ref(spec, "") + ")", std::nullopt});
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP109() { return std::make_unique<UnsupportedCallMode>(); }

}  // namespace osplint
