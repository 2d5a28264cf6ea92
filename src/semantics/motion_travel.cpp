// Points outside `[machine.travel]` (see motion.h): the definite points of an
// envelope, and the axes a plain positioning block moves to.
#include <map>
#include <utility>

#include "semantics/motion_internal.h"

namespace osplint {

using motion_detail::is_cycle_macro;
using motion_detail::non_motion_block;
using motion_detail::num;

namespace {

// The cycle axis: the lowest point below the minimum and the highest above
// the maximum (not the start point, not a trip to the + limit).
void cycle_axis_violations(const Envelope& env, const TravelLimit& t, std::vector<TravelViolation>& out) {
    const MotionPoint *below = nullptr, *above = nullptr;
    for (const auto& p : env.points) {
        if (p.possible || p.limit || p.start || !p.value.known) continue;
        if (p.value.value < t.min && (!below || p.value.value < below->value.value)) below = &p;
        if (p.value.value > t.max && (!above || p.value.value > above->value.value)) above = &p;
    }
    auto index = [&](const MotionPoint* p) { return static_cast<int>(p - env.points.data()); };
    if (below)
        out.push_back({env.axis, below->value.value, t.min, true, below->describe(), below->inferred, "",
                       index(below), ""});
    if (above)
        out.push_back({env.axis, above->value.value, t.max, false, above->describe(), above->inferred, "",
                       index(above), ""});
}

// What a span past a limit rests on, stated with the finding.
std::string span_note(const PlaneSpan& s) {
    std::string out;
    if (s.inferred) out = "this extent rests on a reading of the manual, not on what it prints";
    if (s.compensated)
        out += std::string(out.empty() ? "" : "; ") +
               "the contour is cut with cutter-radius compensation: the spindle centre runs inside it by the tool "
               "radius, so it passes the limit only if it goes beyond it by more than that radius";
    return out;
}

// The plane spans past a limit: the farthest per axis and direction, unless a
// plane point of the envelope is already past that limit.
void plane_span_violations(const Envelope& env, const Config& config, std::vector<TravelViolation>& out) {
    std::map<std::pair<char, bool>, TravelViolation> farthest;
    for (const auto& s : env.plane_spans) {
        if (s.either_way) continue;
        auto it = config.travel.find(s.axis);
        if (it == config.travel.end()) continue;
        const TravelLimit& t = it->second;
        for (bool below : {true, false}) {
            const double v = below ? s.range.lo : s.range.hi;
            const double limit = below ? t.min : t.max;
            if (below ? v >= limit : v <= limit) continue;
            auto found = farthest.find({s.axis, below});
            if (found != farthest.end() && (below ? v >= found->second.value : v <= found->second.value)) continue;
            TravelViolation tv;
            tv.axis = s.axis;
            tv.value = v;
            tv.limit = limit;
            tv.below = below;
            tv.what = s.why + ": " + std::string(1, s.axis) + " " + num(s.range.lo) + " .. " + num(s.range.hi);
            tv.inferred = s.inferred || s.compensated;
            tv.name = s.arg;
            tv.note = span_note(s);
            farthest[{s.axis, below}] = std::move(tv);
        }
    }
    for (auto& [key, tv] : farthest) {
        bool point_past = false;
        for (const auto& o : out)
            if (o.point < 0 && o.axis == key.first && o.below == key.second) point_past = true;
        if (!point_past) out.push_back(std::move(tv));
    }
}

}  // namespace

std::vector<TravelViolation> travel_violations(const Envelope& env, const Config& config) {
    std::vector<TravelViolation> out;
    if (env.axis)
        if (auto it = config.travel.find(env.axis); it != config.travel.end())
            cycle_axis_violations(env, it->second, out);
    for (const auto& pp : env.plane_points) {
        if (pp.what.rfind("current", 0) == 0) continue;  // where the tool already is: not a move of this block
        auto it = config.travel.find(pp.axis);
        if (it == config.travel.end()) continue;
        if (pp.value < it->second.min)
            out.push_back({pp.axis, pp.value, it->second.min, true, "positioning to " + pp.what + " = " + num(pp.value), false,
                           pp.what, -1, ""});
        else if (pp.value > it->second.max)
            out.push_back({pp.axis, pp.value, it->second.max, false, "positioning to " + pp.what + " = " + num(pp.value),
                           false, pp.what, -1, ""});
    }
    plane_span_violations(env, config, out);
    return out;
}

AxesPastTravel positioning_violations(const BlockView& v, const Config& config) {
    const Block& b = v.block;
    const ModalState& before = v.before;
    const ModalState& after = v.after;
    const MacroCall* call = v.call;
    AxesPastTravel none;  // what every early exit returns
    if (b.kind != LineKind::Block || config.travel.empty()) return none;
    // A plain move calls nothing, is no hole (no cycle is modal) and moves.
    if (!v.plain_move) {
        if (call && call->kind != CallKind::GCode) return none;  // macros: see their envelopes
        if (call && call->spec && !is_cycle_macro(*call->spec)) return none;
        if (is_cycle_hole(b, before, after, call)) return none;  // holes: see their envelopes
        if (non_motion_block(b) || b.statement(StmtKind::Call) || b.statement(StmtKind::Modin)) return none;
    }
    return axes_past_travel(b.words, before, after, config);
}

}  // namespace osplint
