// OSP219 cycle-missing-address: a fixed cycle started without an address its
// format requires (Z, R, and Q/K where the cycle has them).
#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP219",
    .name = "cycle-missing-address",
    .severity = Severity::Error,
    .summary = "A fixed cycle started without an address its command format requires",
    .category = RuleCategory::Alarm,
};

bool is_plane_axis_name(std::string_view n) { return n == "X" || n == "Y" || n == "Z"; }

class CycleMissingAddress final : public RuleBase<CycleMissingAddress> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): the same words, the cycle started before.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // no fixed cycle is modal on a plain call line
    // check_block returns at once unless a fixed cycle is modal after the block.
    uint8_t block_needs() const override { return kCycleAfter; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const ActiveCycle* c = active_cycle(v.after);
        // Only a cycle started afresh: after G80 (or at the program start) no
        // modal cycle values remain to fall back on.
        if (!c || !c->macro.empty() || c->start_line != v.block.line || !no_cycle(v.before)) return;
        const CycleSpec* spec = ctx.catalog().find_cycle(c->code);
        if (!spec || !spec->args_documented) return;
        // A bare `G81` (lathe contour definition `NAT3 G81`, or nothing to
        // machine at all) is not a drilling cycle with addresses left out.
        bool addresses = false;
        for (const auto& w : v.block.words)
            if (w.address != "G" && w.address != "M" && w.address != "F" && w.address != "S" && w.address != "N")
                addresses = true;
        if (!addresses) return;
        const char axis = cycle_axis(v.after);
        std::string missing, details, source;
        for (const ArgSpec& a : spec->args) {
            // The feed is modal (any earlier F counts): not checked here.
            if (!a.required() || a.role == ArgRole::Feed) continue;
            std::string address = a.name;
            if (a.role == ArgRole::Cycle && is_plane_axis_name(a.name)) {
                if (!axis) return;  // which word is the depth needs the plane
                address = std::string(1, axis);
            }
            bool present = v.block.find(address) != nullptr;
            for (const auto& alias : a.aliases)
                if (v.block.find(alias)) present = true;
            if (present) continue;
            missing += (missing.empty() ? "" : ", ") + address;
            details += (details.empty() ? "" : "; ") + address + ": " + a.meaning;
            if (source.empty() && !a.source.empty()) source = a.source;
        }
        if (missing.empty()) return;
        std::string format = spec->formats.empty() ? std::string() : spec->formats.front().text;
        auto& d = ctx.report(kMeta, c->start_range.empty() ? v.block.range : c->start_range,
                             fmt::format("G{} starts without {}: {} required by the cycle's command format{} and no "
                                         "earlier value is modal after G80, so the control cannot run the cycle as "
                                         "written; add {} to this block",
                                         c->code, missing, missing.find(',') == std::string::npos ? "it is" : "they are",
                                         format.empty() ? std::string() : " `" + format + "`",
                                         missing.find(',') == std::string::npos ? "it" : "them"));
        d.notes.push_back({details + " (" + macro::source_ref(*spec, source) + ")", std::nullopt});
    }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP219() { return std::make_unique<CycleMissingAddress>(); }

}  // namespace osplint
