// OSP301 cycle-axis-out-of-travel: a macro call, a fixed-cycle hole or a
// positioning move takes an axis outside `[machine.travel]`.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>

#include "semantics/config.h"
#include "semantics/motion.h"
#include "rules/macro_support.h"

namespace osplint {

namespace {

constexpr RuleMeta kMeta{
    .id = "OSP301",
    .name = "cycle-axis-out-of-travel",
    .severity = Severity::Error,
    .summary = "A macro call, a fixed-cycle hole or a positioning move goes beyond [machine.travel]",
    .category = RuleCategory::WrongMotion,
};

std::string travel_text(const Config& c, char axis) {
    auto it = c.travel.find(axis);
    if (it == c.travel.end()) return "";
    return "[machine.travel] " + std::string(1, static_cast<char>(std::tolower(axis))) + " = [" +
           motion_number(it->second.min) + ", " + motion_number(it->second.max) + "]";
}

// The word that sets the point: an argument of the expression written on the
// call line, the cycle's R or depth word on the block.
ByteRange where_for(const BlockView& v, const Envelope& env, const MotionPoint& p) {
    if (const auto* terms = catalog_expr(p.expr)) {
        for (const auto& t : *terms) {
            if (t.name.empty()) continue;
            if (env.source == MotionSource::Macro && v.call) {
                if (const MacroArg* a = v.call->arg(t.name); a && a->word) return a->word->range;
            } else if (t.name != "I") {  // the I point is no word (I is a BHC/G88 address)
                std::string addr = t.name == "Z" ? std::string(1, env.axis) : t.name;
                if (const Word* w = v.block.find(addr)) return w->range;
            }
        }
    }
    if (v.call) return macro::call_range(*v.call, v.block);
    return v.block.range;
}

class CycleAxisOutOfTravel final : public RuleBase<CycleAxisOutOfTravel> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat). Only without travel limits: with them, the position in the plane is what it checks.
    bool quiet_on_repeat(const Config& config, const MacroSpec*) const override {
        return config.travel.empty();
    }
    // Plain moves are checked against the travel limits, when there are any.
    bool sees_plain_moves(const Config& config) const override { return !config.travel.empty(); }
    void check_block(RuleContext& ctx, const BlockView& v) override {
        const Config& config = ctx.config();
        made_for_ = {};
        decided_ = {};
        if (config.travel.empty()) return;
        // A block that calls nothing, in no fixed cycle, and moves no axis
        // has no envelope and positions nothing (M5, S600 M3, T31 M6).
        if (!v.call && !(v.after.cycle.known && v.after.cycle.value) &&
            std::none_of(v.block.words.begin(), v.block.words.end(), [](const Word& w) { return moved_axis(w) != 0; }))
            return;
        // A macro call with the action-step points of the last quiet one:
        // only the positioning plane is left to look at.
        if (QuietCall* q = v.plain_move ? nullptr : axis_quiet_.find(v, config.travel)) {
            // Its other arguments as that call's too: the plane is the one
            // that call reached, moved with the position arguments.
            if (q->reach.decides(v, config)) {
                decided_ = {made_for(v), true, q->reach.axes(), q->reach.reaches()};
                return;
            }
            const std::optional<Envelope>& plane = envelope(v, config, EnvelopeDetail::Plane);
            if (plane) q->reach.remember(v, *plane);
            if (plane && travel_violations(*plane, config).empty()) return;
            report_envelope(ctx, v, config);
            return;
        }
        // So with a hole of the cycle whose points on the cycle axis are
        // those of the last quiet hole.
        if (!v.plain_move && hole_quiet_.same(v, config)) {
            if (const std::optional<Envelope>& plane = envelope(v, config, EnvelopeDetail::Plane)) {
                if (!travel_violations(*plane, config).empty()) report_envelope(ctx, v, config);
                return;
            }
        }
        // A plain move runs no macro and drills no hole: no envelope.
        if (v.plain_move) {
            report_positions(ctx, config, axes_past_travel(v.block.words, v.before, v.after, ctx.axis_limits()));
            return;
        }
        // Nor does a block that calls nothing, with no fixed cycle known to
        // be modal after it (G0 Z100., G56 Z50. H31): cycle_envelope would
        // find none.
        if (!v.call && !(v.after.cycle.known && v.after.cycle.value)) {
            report_positions(ctx, config, positioning_violations(v, config));
            return;
        }
        const std::optional<Envelope>& env = envelope(v, config, EnvelopeDetail::Values);
        if (!env) {
            report_positions(ctx, config, positioning_violations(v, config));
            return;
        }
        // The values decide; the text of a finding needs the envelope in full.
        const std::vector<TravelViolation> past = travel_violations(*env, config);
        if (std::none_of(past.begin(), past.end(), [](const TravelViolation& t) { return t.point >= 0; })) {
            if (QuietCall* q = axis_quiet_.remember(v, config.travel)) q->reach.remember(v, *env);
            hole_quiet_.remember(v, config);
        }
        if (past.empty()) return;
        report_envelope(ctx, v, config);
    }

    // A repeat of a quiet CALL or hole in absolute mode, whose points on the
    // cycle axis the memo holds (its steps read neither position argument):
    // check_block looks at the positioning plane only, where every point and
    // span of the envelope is the position words' values plus an offset that
    // the repeat does not change. The offsets of `v` are kept, per axis.
    bool repeat_values_decide(const Config& config, const BlockView& v, const std::array<char, 2>& axes,
                              uint8_t count, std::array<QuietRange, 2>& quiet) override {
        if (config.travel.empty() || v.plain_move || count != 2 || !v.before.plane.known ||
            !v.before.distance.is(Distance::Absolute))
            return false;
        const Plane plane = v.before.plane.value;
        std::array<double, 2> at{};
        // The values: a CALL's positioning arguments, else the block's words.
        const auto word_values = [&] {
            for (size_t i = 0; i < 2; ++i) {
                const Word* w = v.block.find(std::string_view(&axes[i], 1));
                if (!w || !w->number) return false;
                at[i] = *w->number;
            }
            return true;
        };
        if (v.call) {
            // A CALL, or a positioning block of an open MODIN (its words position it).
            const CallKind kind = v.call->kind;
            if ((kind != CallKind::Call && kind != CallKind::ModinPositioning) || !v.call->spec ||
                !axis_quiet_.same(v, config.travel))
                return false;
            const MacroSpec& spec = *v.call->spec;
            const std::vector<uint16_t>& reads = *spec.action_args();  // listed: the memo holds the call
            for (size_t i = 0; i < 2; ++i) {
                const ArgSpec* a = spec.position_arg(plane_number(plane), axes[i]);
                if (a && std::find(reads.begin(), reads.end(), static_cast<uint16_t>(a - spec.args.data())) != reads.end())
                    return false;
                if (kind == CallKind::ModinPositioning) continue;
                const MacroArg* m = a ? v.call->given(*a) : nullptr;
                if (!m || !m->value.known) return false;
                at[i] = m->value.value;
            }
            if (kind == CallKind::ModinPositioning && !word_values()) return false;
        } else if (!hole_quiet_.same(v, config) || !word_values()) {
            return false;
        }
        // Where check_block found the plane from a quiet call's reach, the
        // reach holds the offsets; else the plane points and spans of a
        // Values envelope are those of a Plane one.
        const bool decided = decided_.holds && decided_.block == made_for(v);
        const Envelope* env = nullptr;
        if (!decided) {
            const std::optional<Envelope>& plane = envelope(v, config, EnvelopeDetail::Plane);
            if (!plane) return false;
            env = &*plane;
        }
        // Inside the travel with a margin that the offsets' rounding cannot cross.
        for (size_t i = 0; i < 2; ++i) {
            quiet[i] = QuietRange{};
            const auto it = config.travel.find(axes[i]);
            if (it == config.travel.end()) continue;
            const Reach r = env ? reach_of(*env, axes[i], at[i]) : decided_.on(axes[i]);
            if (!r.any) continue;
            quiet[i] = {it->second.min + kMargin - r.lo, it->second.max - kMargin - r.hi};
        }
        return true;
    }

    // A plain move read without its block: the same check as check_block's.
    bool takes_plain_values() const override { return true; }
    // A plain move in absolute mode moves each axis to its word's value, and
    // in an unknown mode to no known position: a value inside the travel on
    // both sides of 0 is nothing to report. An axis without limits is never
    // past them; one whose travel does not hold 0 inside has no such bound.
    std::optional<std::array<double, 3>> quiet_below(const Config& config) const override {
        std::array<double, 3> below;
        for (size_t i = 0; i < 3; ++i) {
            const auto it = config.travel.find(static_cast<char>('X' + i));
            if (it == config.travel.end()) {
                below[i] = std::numeric_limits<double>::infinity();
                continue;
            }
            below[i] = std::min(-it->second.min, it->second.max);
            if (!(below[i] > 0)) return std::nullopt;
        }
        return below;
    }
    void check_plain_move(RuleContext& ctx, const PlainMoveView& v) override {
        const Config& config = ctx.config();
        if (config.travel.empty()) return;
        report_positions(ctx, config, axes_past_travel(v.move, v.before, v.after, ctx.axis_limits()));
    }

private:
    // The findings of the envelope of `v` (a macro call or a hole), in full.
    static void report_envelope(RuleContext& ctx, const BlockView& v, const Config& config) {
        const std::optional<Envelope> env = cycle_envelope(v, config);
        if (!env) return;
        for (const auto& t : travel_violations(*env, config)) {
            ByteRange where = v.call ? macro::call_range(*v.call, v.block) : v.block.range;
            if (t.point >= 0) {
                where = where_for(v, *env, env->points[static_cast<size_t>(t.point)]);
            } else if (v.call && v.call->arg(t.name) && v.call->arg(t.name)->word) {
                where = v.call->arg(t.name)->word->range;
            } else if (const Word* w = v.block.find(t.name)) {
                where = w->range;
            }
            const std::string key = env->title() + ' ' + t.axis + (t.below ? '-' : '+');
            if (ctx.folded(kMeta, key, where)) continue;
            double by = std::fabs(t.value - t.limit);
            std::string msg = env->title() + " takes " + std::string(1, t.axis) + " to " + motion_number(t.value) + ", " +
                              motion_number(by) + (t.below ? " below" : " above") + " the " + std::string(1, t.axis) +
                              " travel " + (t.below ? "minimum " : "maximum ") + motion_number(t.limit) + ": " + t.what;
            auto& d = ctx.report(kMeta, where, std::move(msg));
            d.notes.push_back({travel_text(config, t.axis), std::nullopt});
            if (!t.note.empty()) d.notes.push_back({t.note, std::nullopt});
            else if (t.inferred)
                d.notes.push_back({"this step's target is inferred from the action sequence, not printed in the manual",
                                   std::nullopt});
            if (env->call_kind == CallKind::ModinPositioning)
                d.notes.push_back({"the macro runs here because MODIN " + env->name + " (line " +
                                       std::to_string(env->origin_line) + ") is open",
                                   std::nullopt});
            for (const auto& n : env->notes) d.notes.push_back({n, std::nullopt});
        }
    }
    // The axes a positioning block moves past the travel, each on its word.
    static void report_positions(RuleContext& ctx, const Config& config, const AxesPastTravel& past) {
        for (const auto& t : past) {
            // A wrong offset puts every move out of travel: after the first
            // few of a kind, the others are only counted (engine/fold.h).
            const char key[] = {'P', t.axis, t.below ? '-' : '+'};
            if (ctx.folded(kMeta, std::string_view(key, sizeof key), t.word)) continue;
            auto& d = ctx.report(kMeta, t.word,
                                 fmt_move(t) + " the " + std::string(1, t.axis) + " travel " +
                                     (t.below ? "minimum " : "maximum ") + motion_number(t.limit));
            d.notes.push_back({travel_text(config, t.axis), std::nullopt});
        }
    }
    static std::string fmt_move(const AxisPastTravel& t) {
        return "this block moves " + std::string(1, t.axis) + " to " + motion_number(t.value) + ", " +
               motion_number(std::fabs(t.value - t.limit)) + (t.below ? " below" : " above");
    }
    // Where an envelope reaches on a positioning-plane axis, from the value
    // `at` of the position argument or word: its points (not the current
    // position) and its spans that go one way (travel_violations reports
    // only those), as offsets from `at`.
    struct Reach {
        bool any = false;
        double lo = 0, hi = 0;
    };
    static Reach reach_of(const Envelope& env, char axis, double at) {
        Reach r;
        const auto take = [&](double lo, double hi) {
            r.lo = r.any ? std::min(r.lo, lo - at) : lo - at;
            r.hi = r.any ? std::max(r.hi, hi - at) : hi - at;
            r.any = true;
        };
        for (const auto& p : env.plane_points)
            if (p.axis == axis && p.what.rfind("current", 0) != 0) take(p.value, p.value);
        for (const auto& s : env.plane_spans)
            if (s.axis == axis && !s.either_way) take(s.range.lo, s.range.hi);
        return r;
    }
    // Inside the travel with a margin that the offsets' rounding cannot
    // cross (PlaneReach::decides, repeat_values_decide).
    static constexpr double kMargin = 1e-6;
    static bool inside(const Reach& r, double at, const TravelLimit& t) {
        return !r.any || (at + r.lo >= t.min + kMargin && at + r.hi <= t.max - kMargin);
    }

    // Where a CALL in absolute mode that gives both position arguments
    // reaches in the plane, as offsets from their values, with every other
    // argument as it gave them. A call of the same macro in the same plane
    // that gives the same other arguments has the same points and spans,
    // moved by its position values (plane_centre, add_plane_spans): only
    // those values are left to compare with the travel.
    class PlaneReach {
    public:
        bool holds = false;
        // Of the call `v`, whose envelope (Values or Plane) is `env`.
        void remember(const BlockView& v, const Envelope& env) {
            holds = false;
            std::array<double, 2> at{};
            if (!key(v, at)) return;
            const MacroSpec& spec = *v.call->spec;
            args_.resize(spec.args.size());
            for (size_t j = 0; j < spec.args.size(); ++j)
                args_[j] = j == position_[0] || j == position_[1] ? ArgSeen{} : ArgSeen::of(v.call->given(spec.args[j]));
            for (size_t i = 0; i < 2; ++i) reach_[i] = reach_of(env, axes_[i], at[i]);
            holds = true;
        }
        // Whether `v`, a call the memo holds, stays inside the travel in the
        // plane with the margin (false: not known so; work it out).
        bool decides(const BlockView& v, const Config& config) const {
            if (!holds || !v.before.plane.is(plane_)) return false;
            std::array<double, 2> at{};
            if (!values(v, at)) return false;
            const MacroSpec& spec = *v.call->spec;
            if (args_.size() != spec.args.size()) return false;
            for (size_t j = 0; j < args_.size(); ++j)
                if (j != position_[0] && j != position_[1] && !(ArgSeen::of(v.call->given(spec.args[j])) == args_[j]))
                    return false;
            for (size_t i = 0; i < 2; ++i) {
                const auto it = config.travel.find(axes_[i]);
                if (it != config.travel.end() && !inside(reach_[i], at[i], it->second)) return false;
            }
            return true;
        }
        const std::array<char, 2>& axes() const { return axes_; }
        const std::array<Reach, 2>& reaches() const { return reach_; }

    private:
        // The plane, its axes and the position arguments' indexes, of a CALL that gives both.
        bool key(const BlockView& v, std::array<double, 2>& at) {
            if (!v.call || !v.call->spec || v.call->kind != CallKind::Call || !v.before.plane.known) return false;
            plane_ = v.before.plane.value;
            const PlaneAxes pa = plane_axes(plane_);
            axes_ = {pa.first, pa.second};
            const MacroSpec& spec = *v.call->spec;
            for (size_t i = 0; i < 2; ++i) {
                const ArgSpec* a = spec.position_arg(plane_number(plane_), axes_[i]);
                if (!a) return false;
                position_[i] = static_cast<size_t>(a - spec.args.data());
            }
            return values(v, at);
        }
        // The position arguments' values, of a CALL in absolute mode.
        bool values(const BlockView& v, std::array<double, 2>& at) const {
            if (v.call->kind != CallKind::Call || !v.before.distance.is(Distance::Absolute)) return false;
            const MacroSpec& spec = *v.call->spec;
            for (size_t i = 0; i < 2; ++i) {
                if (position_[i] >= spec.args.size()) return false;
                const MacroArg* m = v.call->given(spec.args[position_[i]]);
                if (!m || !m->value.known) return false;
                at[i] = m->value.value;
            }
            return true;
        }
        Plane plane_{};
        std::array<char, 2> axes_{};
        std::array<size_t, 2> position_{};
        std::vector<ArgSeen> args_;
        std::array<Reach, 2> reach_{};
    };

    // The last few quiet calls, each with its cycle-axis points inside the
    // travel (a posted program goes back to a tool, and its calls, after
    // others), and the last quiet hole. Not state: what the rule reports is
    // the same without them (so same_as leaves them out).
    struct QuietCall {
        MacroAxisMemo memo;
        PlaneReach reach;  // of the last call it decided that gave a plane (PlaneReach::remember)
    };
    struct QuietCalls {
        std::array<QuietCall, 16> calls;
        size_t next = 0;
        QuietCall* find(const BlockView& v, const TravelLimits& travel) {
            if (!v.call || !v.call->spec) return nullptr;
            for (QuietCall& q : calls)
                if (q.memo.spec() == v.call->spec && q.memo.same(v, travel)) return &q;
            return nullptr;
        }
        bool same(const BlockView& v, const TravelLimits& travel) { return find(v, travel) != nullptr; }
        // Takes the place of the oldest, when `v` is one to remember; the
        // entry that holds it (nullptr: not one to remember).
        QuietCall* remember(const BlockView& v, const TravelLimits& travel) {
            if (QuietCall* q = find(v, travel)) return q;
            MacroAxisMemo m;
            m.remember(v, travel);
            if (!m.holds()) return nullptr;
            QuietCall& q = calls[next];
            q.memo = std::move(m);
            q.reach.holds = false;
            next = (next + 1) % calls.size();
            return &q;
        }
    };
    QuietCalls axis_quiet_;
    HoleAxisMemo hole_quiet_;
    // The envelope check_block made of the block it saw last (in the plane,
    // or with the values), kept for repeat_values_decide, which the walk
    // asks right after about the same block (Walk::check); check_block
    // forgets it first thing, and the block's line, range and states must
    // be those it was made for.
    struct MadeFor {
        const Block* block = nullptr;
        uint32_t line = 0;
        ByteRange range;
        const ModalState* before = nullptr;
        const ModalState* after = nullptr;
        bool operator==(const MadeFor&) const = default;
    };
    static MadeFor made_for(const BlockView& v) { return {&v.block, v.block.line, v.block.range, &v.before, &v.after}; }
    MadeFor made_for_;
    std::optional<Envelope> envelope_;
    // The block check_block found inside the travel from a quiet call's
    // reach, with that reach (for repeat_values_decide, as made_for_).
    struct Decided {
        MadeFor block;
        bool holds = false;
        std::array<char, 2> axes{};
        std::array<Reach, 2> reach{};
        Reach on(char axis) const { return axis == axes[0] ? reach[0] : axis == axes[1] ? reach[1] : Reach{}; }
    };
    Decided decided_;
    // The envelope of `v` to `detail`, or, for Plane, the one made for it with the values.
    const std::optional<Envelope>& envelope(const BlockView& v, const Config& config, EnvelopeDetail detail) {
        const MadeFor key = made_for(v);
        if (detail != EnvelopeDetail::Plane || !(made_for_ == key)) {
            envelope_ = cycle_envelope(v, config, detail);
            made_for_ = key;
        }
        return envelope_;
    }

public:
    bool same_as(const CycleAxisOutOfTravel&) const { return true; }
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP301() { return std::make_unique<CycleAxisOutOfTravel>(); }

}  // namespace osplint
