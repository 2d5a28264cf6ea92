// Points outside `[machine.travel]` (see motion.h): the definite points of an
// envelope, and the axes a plain positioning block moves to.
#include <array>
#include <map>
#include <utility>

#include "semantics/motion_internal.h"

namespace osplint {

using motion_detail::is_axis_letter;
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
    AxesPastTravel out;
    if (b.kind != LineKind::Block || config.travel.empty()) return out;
    // A plain move calls nothing, is no hole (no cycle is modal) and moves.
    if (!v.plain_move) {
        if (call && call->kind != CallKind::GCode) return out;  // macros: see their envelopes
        if (call && call->spec && !is_cycle_macro(*call->spec)) return out;
        if (is_cycle_hole(b, before, after, call)) return out;  // holes: see their envelopes
        if (non_motion_block(b) || b.statement(StmtKind::Call) || b.statement(StmtKind::Modin)) return out;
    }
    const bool in_cycle = after.cycle.known && after.cycle.value;
    const char cyc = in_cycle && before.plane.known ? plane_axes(before.plane.value).cycle : 0;
    // The limits of X, Y and Z, looked up once for the block.
    std::array<const TravelLimit*, 3> limits{};
    for (size_t i = 0; i < 3; ++i)
        if (auto it = config.travel.find(static_cast<char>('X' + i)); it != config.travel.end()) limits[i] = &it->second;
    unsigned seen = 0;                        // X, Y, Z: bits 0, 1, 2
    std::array<uint8_t, 3> slot{3, 3, 3};     // X, Y, Z: the place in out.axes (3: none)
    size_t count = 0;
    for (const auto& w : b.words) {
        if (!is_axis_letter(w.address)) continue;
        const char a = w.address[0];
        if (in_cycle && a == cyc) continue;  // a cycle depth, not a move
        const auto i = static_cast<size_t>(a - 'X');
        const unsigned bit = 1u << i;
        if (seen & bit) {
            if (slot[i] < 3) out.axes[slot[i]].word = w.range;
            continue;
        }
        seen |= bit;
        const TravelLimit* limit = limits[i];
        const Val<double> pos = after.axis(a);
        if (!limit || !pos.known) continue;
        if (pos.value < limit->min || pos.value > limit->max) {
            // Field by field: a braced temporary is built on the stack in
            // narrow stores and copied in wide loads, a stall on every move.
            const bool below = pos.value < limit->min;
            slot[i] = static_cast<uint8_t>(count);
            AxisPastTravel& t = out.axes[count++];
            t.axis = a;
            t.value = pos.value;
            t.limit = below ? limit->min : limit->max;
            t.below = below;
            t.word = w.range;
        }
    }
    out.count = count;
    return out;
}

}  // namespace osplint
