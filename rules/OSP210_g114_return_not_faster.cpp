// OSP210 g114-return-not-faster: the G114 (OG84L) return rate FA is not faster
// than the feed F (FA omitted means FA = F).
#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP210",
    .name = "g114-return-not-faster",
    .severity = Severity::Warning,
    .summary = "G114 (OG84L) return rate FA omitted or not faster than F",
    .category = RuleCategory::WrongMotion,
};

class G114ReturnNotFaster final : public RuleBase<G114ReturnNotFaster> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same FA and F under the same feed.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // a plain call runs a CALL or MODIN macro, not a G-code one
    // check_block returns at once without a call.
    uint8_t block_needs() const override { return kCall; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const MacroCall* c = v.call;
        if (!c || c->kind != CallKind::GCode || !c->spec || c->spec->cancel.empty() || !c->spec->tapping) return;
        const MacroSpec& spec = *c->spec;
        const ArgSpec* fa_spec = spec.arg("FA");
        const ArgSpec* f_spec = spec.arg("F");
        if (!fa_spec || !f_spec) return;
        const MacroArg* fa = macro::given(*c, *fa_spec);
        const MacroArg* f = macro::given(*c, *f_spec);
        // F omitted: the current feed is used (the argument list).
        Val<double> feed = f ? f->value : v.before.feed;
        const std::string g(ctx.text(c->name_range));
        std::string msg;
        ByteRange where = c->name_range;
        if (!fa) {
            msg = g + " has no FA: the return rate defaults to F (" + cite("tap-cycle/args") + ")" +
                  (feed.known ? " = " + macro::format_number(feed.value) : std::string()) +
                  ", and a return exactly at the tapping feed makes the tapper's reverse clutch slip, runs unsteadily "
                  "and wears the clutch (" + cite("tap-cycle/tappers") + "); give FA slightly faster than F";
        } else {
            // Both written: OSP103 checks the relation FA > F of the catalog.
            if (f || !fa->value.known || !feed.known || fa->value.value > feed.value) return;
            where = fa->word ? fa->word->range : where;
            const bool equal = fa->value.value == feed.value;
            msg = fmt::format("FA{} is {} the current feed F{} that {} uses (no F on this line): {} ({}); "
                              "give FA slightly faster than F",
                              macro::format_number(fa->value.value), equal ? "equal to" : "slower than",
                              macro::format_number(feed.value), g,
                              equal ? "a return exactly at the tapping feed makes the reverse clutch slip"
                                    : "a return slower than the pitch makes the reverse clutch engage and "
                                      "disengage repeatedly",
                              cite("tap-cycle/tappers"));
        }
        auto& d = ctx.report(kMeta, where, std::move(msg));
        d.notes.push_back({"\"The return speed is then set slightly faster than the pitch.\" (" +
                               cite("tap-cycle/tappers") +
                               "); the manual's own default FA = F (" + cite_heading("tap-cycle/args") +
                               ") is the very case it warns against",
                           std::nullopt});
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP210() { return std::make_unique<G114ReturnNotFaster>(); }

}  // namespace osplint
