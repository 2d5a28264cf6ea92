// OSP205 cycle-point-order: a fixed cycle (or G114) whose initial point, R point
// and Z point are not in the order I >= R > Z along the cycle axis.
#include <algorithm>
#include <optional>
#include <tuple>

#include <fmt/format.h>

#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP205",
    .name = "cycle-point-order",
    .severity = Severity::Error,
    .summary = "Fixed-cycle initial point, R and Z not in the order I >= R > Z",
    .category = RuleCategory::Alarm,
};

std::string num(double v) { return macro::format_number(v); }

// Back boring goes from below the hole upwards: its order is the other way round.
bool reversed_cycle(int code) { return code == 79 || code == 87; }

class CyclePointOrder final : public RuleBase<CyclePointOrder> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat): it reads the cycle-axis position, not the plane's, and reports a violation once.
    bool quiet_on_repeat(const Config&, const MacroSpec*) const override { return true; }
    bool sees_plain_calls() const override { return false; }  // no fixed cycle is modal on a plain call line

    void begin_program(RuleContext&, const ProgramView&) override {
        last_.reset();
        last_k_.reset();
    }

    // check_block returns at once unless a fixed cycle is modal after the block.
    uint8_t block_needs() const override { return kCycleAfter; }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const Block& b = v.block;
        const ActiveCycle* c = active_cycle(v.after);
        // G80 alone ends the cycle; `G80 G83 ...` starts the next one, checked here.
        if (!c || (b.has_code("G", 80) && c->start_line != b.line) || reversed_cycle(c->code)) return;
        const char axis = cycle_axis(v.after);
        if (!axis || !v.after.distance.known) return;
        const std::string axis_name(1, axis);
        const Word* r_word = find_address(b, "R");
        const Word* z_word = find_address(b, axis_name);
        // Blocks that command the cycle, change R or Z, or machine a hole.
        bool positions = r_word || z_word || c->start_line == b.line;
        for (const auto& w : b.words)
            if ((w.address == "G" && w.number && *w.number == c->code) ||
                ((w.address == "X" || w.address == "Y" || w.address == "Z") && !is_coord_calc_operand(b, w)))
                positions = true;
        for (const auto& st : b.statements)
            if (st.kind == StmtKind::CoordCalc) positions = true;
        if (!positions) return;
        check_g77_k(ctx, v, *c, axis);
        const bool g17 = v.after.plane.is(Plane::G17);
        const bool incremental = v.after.distance.value == Distance::Incremental;
        const std::string problem =
            incremental ? incremental_problem(c, axis_name, g17) : absolute_problem(v, c, axis, g17);
        if (problem.empty()) return;
        const std::string name = fmt::format("G{}", c->code);
        ByteRange where = r_word ? r_word->range : z_word ? z_word->range : !c->start_range.empty() &&
                                                                                  c->start_line == b.line
                                                                              ? c->start_range
                                                                              : b.range;
        auto& d = ctx.report(kMeta, where, name + ": " + problem);
        if (c->start_line != b.line && !c->start_range.empty())
            d.notes.push_back({name + " was commanded here", ctx.resolve(c->start_range)});
        if (!c->macro.empty())
            d.notes.push_back({c->macro + " follows the fixed-cycle rules for the cycle axis, also under G91 (" +
                                   cite({"tap-cycle/cautions-1", "tap-cycle/cautions-2"}) + ")",
                               std::nullopt});
    }

    // The finding's text under G91, or "" when there is none (or it was made already).
    std::string incremental_problem(const ActiveCycle* c, const std::string& axis_name, bool g17) {
        if (!c->r.known || !c->z.known) return {};
        const double r = c->r.value, z = c->z.value;
        const bool down = r <= 0 && z < 0, up = r >= 0 && z > 0;
        if (down || (!g17 && up)) {
            last_.reset();
            return {};
        }
        if (!dedupe(c, Val<double>{}, r, z, true)) return {};
        return fmt::format(
            "under G91 R is measured from the initial point and Z from the R point ({}), so R "
            "must be 0 or negative and Z negative{}; here R{} and {}{}{}",
            cite("fixed-cycles/g91"),
            g17 ? "" : " (or both positive for a cycle axis pointing the other way)", num(r), axis_name,
            num(z),
            r > 0 && z < 0 ? ": R above the initial point raises an alarm (" + cite("fixed-cycles/alarms") + ")"
            : z == 0       ? ": Z0 leaves no depth to machine"
                           : ": the hole bottom is not below the R point");
    }

    // The finding's text under G90, or "" when there is none (or it was made already).
    std::string absolute_problem(const BlockView& v, const ActiveCycle* c, char axis, bool g17) {
        const Block& b = v.block;
        const std::string axis_name(1, axis);
        const Val<double> i_point = v.before.axis(axis);
        if (!c->r.known) return {};
        const double r = c->r.value;
        const bool have_z = c->z.known;
        const double z = have_z ? c->z.value : 0;
        auto ordered = [&](double hi, double lo, bool strict) { return strict ? hi > lo : hi >= lo; };
        auto check = [&](bool downwards) {
            // downwards: I >= R > Z; upwards (G18/G19 only): I <= R < Z
            bool ok = true;
            if (i_point.known)
                ok = ok && (downwards ? ordered(i_point.value, r, false) : ordered(r, i_point.value, false));
            if (have_z) ok = ok && (downwards ? ordered(r, z, true) : ordered(z, r, true));
            return ok;
        };
        if (check(true) || (!g17 && check(false))) {
            last_.reset();
            return {};
        }
        if (!dedupe(c, i_point, r, z, have_z)) return {};
        const bool g99 = v.after.cycle_return.is(CycleReturn::R) && c->start_line != b.line;
        std::string i_text = i_point.known
                                 ? fmt::format("initial point {}{}", axis_name, num(i_point.value)) +
                                       (g99 ? " (under G99 the previous block's " + axis_name + " is the initial point)"
                                            : std::string())
                                 : std::string("initial point unknown");
        if (i_point.known && r > i_point.value && (!have_z || r > z))
            return fmt::format("R{} is above the {}: the control stops with an alarm ({}); "
                               "start the cycle from above R, or lower R",
                               num(r), i_text, cite("fixed-cycles/alarms"));
        return fmt::format("the hole bottom {}{} is not below R{} ({}): the points must be in the "
                           "order I > R > Z ({}), otherwise the cycle machines nothing "
                           "or feeds the wrong way; Z is the final depth",
                           axis_name, num(z), num(r), i_text, cite({"fixed-cycles/basic", "fixed-cycles/alarms"}));
    }

    bool same_as(const CyclePointOrder& o) const { return last_k_ == o.last_k_ && last_ == o.last_; }

private:
    // G77: K, where the step motion changes to the pick motion, is a point on
    // the way from R to the bottom (under G91 K and Z are both measured from
    // R). K equal to R or Z is left alone.
    void check_g77_k(RuleContext& ctx, const BlockView& v, const ActiveCycle& c, char axis) {
        if (c.code != 77 || !c.macro.empty()) return;
        auto it = c.words.get().find("K");
        if (it == c.words.get().end() || !it->second.known || !c.r.known || !c.z.known || !v.after.distance.known) {
            last_k_.reset();
            return;
        }
        const bool incremental = v.after.distance.value == Distance::Incremental;
        const double k = it->second.value;
        const double r = incremental ? 0.0 : c.r.value;
        const double z = c.z.value;
        if (k <= std::max(r, z) && k >= std::min(r, z)) {
            last_k_.reset();
            return;
        }
        auto key = std::make_tuple(c.start_line, k, c.r.value, z);
        if (last_k_ && *last_k_ == key) return;
        last_k_ = key;
        const std::string ax(1, axis);
        const std::string where_k =
            incremental ? fmt::format("under G91 K{} and {}{} are both measured from the R point", num(k), ax, num(z))
                        : fmt::format("K{} is not between R{} and {}{}", num(k), num(r), ax, num(z));
        const Word* k_word = find_address(v.block, "K");
        ByteRange where = k_word ? k_word->range : !c.start_range.empty() && c.start_line == v.block.line
                                                       ? c.start_range
                                                       : v.block.range;
        auto& d = ctx.report(kMeta, where,
                             fmt::format("G77: K, the {} coordinate where the step motion changes to the pick motion, "
                                         "must lie between R and the hole bottom ({}); {}",
                                         ax, cite("fixed-cycles/g77"),
                                         incremental ? where_k + ", and K is not between 0 and " + ax + num(z)
                                                     : where_k));
        d.notes.push_back({"the manual defines K as a point on the way from R to the bottom; that it must lie "
                           "between them is inferred, not stated",
                           std::nullopt});
        if (c.start_line != v.block.line && !c.start_range.empty())
            d.notes.push_back({"G77 was commanded here", ctx.resolve(c.start_range)});
    }
    std::optional<std::tuple<uint32_t, double, double, double>> last_k_;

    // The same violation is reported once, not on every hole block that repeats it.
    bool dedupe(const ActiveCycle* c, Val<double> i, double r, double z, bool have_z) {
        auto key = std::make_tuple(c->start_line, i.known, i.known ? i.value : 0.0, r, have_z ? z : 0.0, have_z);
        if (last_ && *last_ == key) return false;
        last_ = key;
        return true;
    }
    std::optional<std::tuple<uint32_t, bool, double, double, double, bool>> last_;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP205() { return std::make_unique<CyclePointOrder>(); }

}  // namespace osplint
