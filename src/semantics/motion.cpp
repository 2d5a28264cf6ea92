// The cycle-axis motion evaluator (see motion.h): the envelope types, the
// finishing of an envelope from its points, and which blocks run a macro or
// a fixed-cycle hole. The envelopes themselves are worked out in
// motion_macro.cpp and motion_hole.cpp (motion_internal.h lists the files).
#include "semantics/motion.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "semantics/motion_internal.h"
#include "semantics/transfer.h"

namespace osplint {

std::string motion_number(double v) {
    if (!std::isfinite(v)) return "?";  // never "inf" or "nan" in a message
    const double scaled = std::round(v * 10000.0);
    // Below 1e9 the double nearest to k/10000 prints with four decimals as
    // k itself: the digits are written from k, without a formatting call (a
    // point of an envelope is shown by the hundred thousand).
    if (std::fabs(v) < 1e9) {
        const long long k = static_cast<long long>(scaled);
        unsigned long long m = static_cast<unsigned long long>(k < 0 ? -k : k);
        char buf[32];
        char* e = buf + sizeof buf;
        char* p = e;
        unsigned frac = static_cast<unsigned>(m % 10000);
        m /= 10000;
        int digits = 4;
        while (digits > 0 && frac % 10 == 0) {  // no trailing zeros, no bare point
            frac /= 10;
            --digits;
        }
        for (int i = 0; i < digits; ++i, frac /= 10) *--p = static_cast<char>('0' + frac % 10);
        if (digits > 0) *--p = '.';
        do {
            *--p = static_cast<char>('0' + m % 10);
            m /= 10;
        } while (m);
        if (k < 0) *--p = '-';
        return std::string(p, e);
    }
    double r = std::fabs(v) < 1e15 ? scaled / 10000.0 : v;
    if (r == 0) r = 0;  // no "-0"
    std::string s = fmt::format("{:.4f}", r);
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
}

// --- Blocks and the configuration -------------------------------------------

namespace motion_detail {

bool has_code(const Block& b, char address, int code) {
    for (const auto& w : b.words)
        if (w.address.size() == 1 && w.address[0] == address)
            if (auto c = code_of(w); c && *c == code) return true;
    return false;
}

// G codes whose axis words are not a move of the tool tip (the same list the
// transfer function uses, plus the coordinate-system selections).
bool non_motion_block(const Block& b) {
    for (const auto& w : b.words) {
        if (w.address.size() != 1 || w.address[0] != 'G') continue;
        const auto c = code_of(w);
        if (!c) continue;
        switch (*c) {
            case 4: case 10: case 11: case 15: case 16: case 20: case 22: case 23: case 30: case 50: case 71: case 92:
                return true;
            default: break;
        }
    }
    return false;
}

bool is_cycle_macro(const MacroSpec& spec) { return spec.has_form(MacroForm::GCode) && !spec.cancel.empty(); }

bool is_any_axis(std::string_view a) {
    return a.size() == 1 && std::string_view("XYZABCUVW").find(a[0]) != std::string_view::npos;
}

std::optional<double> travel_max(const Config& c, char axis) {
    if (auto it = c.travel.find(axis); it != c.travel.end()) return it->second.max;
    return std::nullopt;
}

// The plane point a word of the block moves to (G90/G91).
std::optional<double> block_axis_target(const Block& b, char axis, const ModalState& before) {
    for (const auto& w : b.words) {
        if (w.address.size() != 1 || w.address[0] != axis) continue;
        auto v = word_value(b, w, before);
        if (!v || !before.distance.known) return std::nullopt;
        if (before.distance.value == Distance::Absolute) return v;
        Val<double> old = before.axis(axis);
        if (!old.known) return std::nullopt;
        return old.value + *v;
    }
    return std::nullopt;
}

bool block_has_axis(const Block& b, char axis) {
    for (const auto& w : b.words)
        if (w.address.size() == 1 && w.address[0] == axis) return true;
    return false;
}

// --- Finishing an envelope ----------------------------------------------------

void finish(Envelope& env) {
    env.lowest.reset();
    env.highest.reset();
    env.may_low.reset();
    env.may_high.reset();
    env.bounded_low = env.bounded_high = env.plane.has_value();
    for (size_t i = 0; i < env.points.size(); ++i) {
        const MotionPoint& p = env.points[i];
        if (!p.possible) {
            if (p.value.known) {
                double v = p.value.value;
                if (!env.lowest || v < env.lowest->value) env.lowest = EnvelopeEnd{v, i};
                if (!env.highest || v > env.highest->value) env.highest = EnvelopeEnd{v, i};
            } else if (!p.limit) {
                env.bounded_low = env.bounded_high = false;
            }
            if (p.limit) env.limit_point = i;
        } else if (p.reach) {
            if (!env.may_low || p.reach->lo < env.may_low->value) env.may_low = EnvelopeEnd{p.reach->lo, i};
            if (!env.may_high || p.reach->hi > env.may_high->value) env.may_high = EnvelopeEnd{p.reach->hi, i};
        }
    }
    if (!env.lowest && !env.limit_point) env.bounded_low = env.bounded_high = false;
    if (env.may_low && env.lowest && env.may_low->value >= env.lowest->value) env.may_low.reset();
    if (env.may_high && env.highest && env.may_high->value <= env.highest->value) env.may_high.reset();
    if (env.limit_point && env.may_high) {
        const MotionPoint& lp = env.points[*env.limit_point];
        if (lp.value.known && env.may_high->value <= lp.value.value) env.may_high.reset();
    }
}

}  // namespace motion_detail

using motion_detail::finish;
using motion_detail::has_code;
using motion_detail::hole_envelope;
using motion_detail::is_any_axis;
using motion_detail::is_cycle_macro;
using motion_detail::macro_end_point;
using motion_detail::macro_envelope;
using motion_detail::runs_macro;

std::string MotionPoint::describe() const {
    std::string out = label.empty() ? "step " + step : label;
    out += ": ";
    out += expr;
    if (!worked.empty()) out += " = " + worked;
    if (inferred) out += " [inferred]";
    return out;
}

std::vector<const MotionPoint*> Envelope::unknown_points() const {
    std::vector<const MotionPoint*> out;
    for (const auto& p : points)
        if (!p.possible && !p.limit && !p.value.known) out.push_back(&p);
    return out;
}

std::string Envelope::title() const {
    switch (source) {
        case MotionSource::FixedCycle: return name + " hole";
        case MotionSource::CycleMacro: return code + " hole (" + name + ")";
        case MotionSource::Macro: break;
    }
    switch (call_kind) {
        case CallKind::Call: return name + " (CALL)";
        case CallKind::ModinPositioning: return name + " (MODIN, line " + std::to_string(origin_line) + ")";
        case CallKind::GCode: return name + " (" + code + ")";
        default: return name;
    }
}

bool is_cycle_hole(const Block& b, const ModalState& before, const ModalState& after, const MacroCall* call) {
    (void)before;
    if (b.kind != LineKind::Block) return false;
    if (!after.cycle.known || !after.cycle.value) return false;
    // Positioning only: NCYL, G100, NOEX (one-shots of the block), G80 (unless
    // the block starts a new cycle after it: `G80 G83 X.. Z.. R..`).
    if (after.ncyl || after.g100 || after.noex) return false;
    if (has_code(b, 'G', 80) && after.cycle.value->start_line != b.line) return false;
    if (b.statement(StmtKind::Ncyl) || b.statement(StmtKind::Noex) || has_code(b, 'G', 100)) return false;
    for (int c : {4, 71, 92, 50, 22, 23})
        if (has_code(b, 'G', c)) return false;
    // The declaration block of a G-code macro cycle positions only (003:L86-88);
    // a CALL, a MODIN or a modal macro call inside a cycle is not a hole.
    if (call && call->kind != CallKind::MCode) return false;
    if (b.statement(StmtKind::Call) || b.statement(StmtKind::Modin)) return false;
    if (b.statement(StmtKind::CoordCalc) || b.find("R")) return true;
    for (const auto& w : b.words)
        if (is_any_axis(w.address)) return true;
    // The block that starts the cycle drills where the tool stands.
    const ActiveCycle& c = *after.cycle.value;
    return c.start_line == b.line && !c.start_range.empty() && b.range.begin <= c.start_range.begin &&
           c.start_range.end <= b.range.end;
}

bool motion_detail::runs_macro(const Block& b, const MacroCall* call) {
    if (b.kind != LineKind::Block || !call || !call->spec || call->spec->kind != SpecKind::Macro ||
        call->spec->action.empty())
        return false;
    return call->kind == CallKind::Call ||
           (call->kind == CallKind::ModinPositioning && !b.statement(StmtKind::Ncyl)) ||
           (call->kind == CallKind::GCode && !is_cycle_macro(*call->spec));
}

std::optional<Envelope> cycle_envelope(const Block& b, const ModalState& before, const ModalState& after,
                                       const MacroCall* call, const Config& config, EnvelopeDetail detail) {
    if (b.kind != LineKind::Block) return std::nullopt;
    if (runs_macro(b, call))
        return macro_envelope(b, before, after, *call, *call->spec, &config, detail == EnvelopeDetail::Full,
                              detail != EnvelopeDetail::Plane);
    if (is_cycle_hole(b, before, after, call))
        return hole_envelope(b, before, after, config, detail == EnvelopeDetail::Full,
                             detail != EnvelopeDetail::Plane);
    return std::nullopt;
}

bool motion_detail::steps_read_plane(const MacroSpec& spec, Plane plane) {
    const int number = plane_number(plane);
    const PlaneAxes pa = plane_axes(plane);
    return spec.action_reads_axis(number, pa.first) || spec.action_reads_axis(number, pa.second);
}

namespace {
// What a repeat reads of the state and the macro to take the memo's end point.
bool takes_end_on_repeat(const MacroSpec& spec, const ModalState& before) {
    return before.plane.known && !motion_detail::steps_read_plane(spec, before.plane.value);
}
}  // namespace

bool macro_end_repeats(const MacroEndMemo& memo, const MacroSpec& spec, const ModalState& before) {
    return memo.fresh && takes_end_on_repeat(spec, before);
}

std::optional<std::pair<char, double>> macro_end(const Block& b, const ModalState& before, const ModalState& after,
                                                 const MacroCall* call, MacroEndMemo* memo, bool repeat) {
    const bool fresh = memo && memo->fresh;
    if (memo) memo->fresh = false;
    if (!runs_macro(b, call)) return std::nullopt;
    const MacroSpec& spec = *call->spec;
    // Under G91 a macro that does not support it moves elsewhere; in inch a
    // mm-only macro takes the values as mm: the envelope is a reading then.
    if (before.distance.is(Distance::Incremental) && spec.g91 == G91Mode::Unsupported) return std::nullopt;
    if (!before.distance.known && spec.g91 == G91Mode::Unsupported) return std::nullopt;
    if (!before.units.is(Units::Mm) && spec.units == MacroUnits::MmOnly) return std::nullopt;
    if (!memo) return macro_end_point(b, before, after, *call, spec);
    static const TravelLimits kNoTravel;  // macro_end_point knows no travel limits
    const BlockView v{b, before, after, call};
    if ((repeat && fresh && takes_end_on_repeat(spec, before)) || memo->call.same(v, kNoTravel)) {
        memo->fresh = true;
        return memo->end;
    }
    memo->end = macro_end_point(b, before, after, *call, spec);
    memo->call.remember(v, kNoTravel);
    memo->fresh = memo->call.holds();
    return memo->end;
}

std::optional<Envelope> cycle_envelope(const BlockView& v, const Config& config, EnvelopeDetail detail) {
    return cycle_envelope(v.block, v.before, v.after, v.call, config, detail);
}

}  // namespace osplint
