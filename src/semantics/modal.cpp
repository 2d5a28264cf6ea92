#include "semantics/modal.h"

#include <algorithm>
#include <tuple>

#include <fmt/format.h>

namespace osplint {

const char* plane_name(Plane p) {
    switch (p) {
        case Plane::G17: return "G17";
        case Plane::G18: return "G18";
        case Plane::G19: return "G19";
    }
    return "?";
}

namespace {

void merge_cycle(Val<std::optional<ActiveCycle>>& a, const Val<std::optional<ActiveCycle>>& b) {
    if (!a.known) return;
    if (!b.known) {
        a = {};
        return;
    }
    if (a.value == b.value) return;
    if (!a.value || !b.value || a.value->code != b.value->code || a.value->macro != b.value->macro) {
        a = {};
        return;
    }
    ActiveCycle& c = *a.value;
    const ActiveCycle& d = *b.value;
    if (c.start_line != d.start_line) c.start_line = 0;
    if (!(c.start_range == d.start_range)) c.start_range = {};
    if (!(c.command_range == d.command_range)) c.command_range = {};
    c.r.merge(d.r);
    c.z.merge(d.z);
    c.initial.merge(d.initial);
    // Keep the addresses given on both sides; presence is no longer exact when
    // one side has an address the other lacks.
    if (!d.words_known) c.words_known = false;
    if (c.words == d.words) return;  // the same words: merging them changes nothing
    auto& words = c.words.edit();
    const auto& other = d.words.get();
    for (auto it = words.begin(); it != words.end();) {
        auto jt = other.find(it->first);
        if (jt == other.end()) {
            c.words_known = false;
            it = words.erase(it);
        } else {
            it->second.merge(jt->second);
            ++it;
        }
    }
    for (const auto& [k, v] : other)
        if (!words.count(k)) c.words_known = false;
}

// A MODIN open on both sides, opened by the same block: it stays known as
// open, with the argument values both sides agree on (a loop's passes
// evaluate `PZ=VC1+1` each to its own value; the call is open on all of them).
void merge_modin(Val<std::optional<ActiveModin>>& a, const Val<std::optional<ActiveModin>>& b) {
    if (!a.known) return;
    if (!b.known) {
        a = {};
        return;
    }
    if (a.value == b.value) return;
    if (!a.value || !b.value || a.value->macro != b.value->macro || a.value->line != b.value->line ||
        a.value->via != b.value->via || a.value->given() != b.value->given()) {
        a = {};
        return;
    }
    const std::map<std::string, double>& theirs = b.value->values();
    const auto agreed = [&](const std::pair<const std::string, double>& v) {
        const auto jt = theirs.find(v.first);
        return jt != theirs.end() && jt->second == v.second;
    };
    const std::map<std::string, double>& values = a.value->values();
    if (std::all_of(values.begin(), values.end(), agreed)) return;
    std::map<std::string, double>& mine = a.value->args_to_edit().values;
    for (auto it = mine.begin(); it != mine.end();) it = agreed(*it) ? std::next(it) : mine.erase(it);
}

}  // namespace

bool Origin::before(const Origin& o) const {
    auto key = [](const Origin& x) {
        return std::tuple(x.line, x.range.begin, x.range.end, x.via_line, x.via_range.begin, x.via_range.end);
    };
    return key(*this) < key(o);
}

namespace {
// Calls f(a.x, b.x) on every origin field x of two states.
template <class F>
void each_origin_pair(ModalState& a, const ModalState& b, F&& f) {
    f(a.g91_from, b.g91_from);
    f(a.g20_from, b.g20_from);
    f(a.g60_from, b.g60_from);
    f(a.plane_from, b.plane_from);
    f(a.cycle_from, b.cycle_from);
    f(a.modin_from, b.modin_from);
}
}  // namespace

void ModalState::merge_jump(const ModalState& o, uint32_t line, ByteRange range) {
    // As merge, with o's origins marked by the jump: merge takes them unmarked,
    // so ours are put back and the marked ones merged in.
    ModalState own;  // only its origins are used
    each_origin_pair(own, *this, [](auto& to, const auto& from) { to = from; });
    merge(o);
    each_origin_pair(*this, own, [](auto& to, const auto& from) { to = from; });
    each_origin_pair(*this, o, [&](auto& to, auto from) {
        from.jumped(line, range);
        to.merge(from);
    });
}

void ModalState::merge(const ModalState& o) {
    if (modes_from != o.modes_from) modes_from = nullptr;
    plane.merge(o.plane);
    distance.merge(o.distance);
    g91_from.merge(o.g91_from);
    units.merge(o.units);
    g20_from.merge(o.g20_from);
    motion.merge(o.motion);
    g60_from.merge(o.g60_from);
    plane_from.merge(o.plane_from);
    cycle_from.merge(o.cycle_from);
    modin_from.merge(o.modin_from);
    work_offset.merge(o.work_offset);
    length_offset.merge(o.length_offset);
    length_offset_h.merge(o.length_offset_h);
    cutter_comp.merge(o.cutter_comp);
    cutter_comp_d.merge(o.cutter_comp_d);
    g71_level.merge(o.g71_level);
    return_level.merge(o.return_level);
    merge_cycle(cycle, o.cycle);
    uncancelled.merge(o.uncancelled);
    cycle_return.merge(o.cycle_return);
    merge_modin(modin, o.modin);
    spindle.merge(o.spindle);
    spindle_stopped_by.merge(o.spindle_stopped_by);
    spindle_speed.merge(o.spindle_speed);
    speed_commanded.merge(o.speed_commanded);
    sync_tap.merge(o.sync_tap);
    coolant.merge(o.coolant);
    feed.merge(o.feed);
    feed_commanded.merge(o.feed_commanded);
    overrides_disabled.merge(o.overrides_disabled);
    x.merge(o.x);
    y.merge(o.y);
    z.merge(o.z);
    for (auto it = vars.begin(); it != vars.end();) {
        auto jt = o.vars.find(it->first);
        if (jt == o.vars.end() || jt->second != it->second)
            it = vars.erase(it);
        else
            ++it;
    }
    ncyl = ncyl || o.ncyl;
    noex = noex || o.noex;
    g100 = g100 || o.g100;
}

namespace {
template <class T, class F>
std::string show(const Val<T>& v, F f) {
    return v.known ? f(v.value) : std::string("?");
}
std::string num(double d) { return std::isfinite(d) ? fmt::format("{:g}", d) : std::string("?"); }
}  // namespace

std::string describe_state(const ModalState& s) {
    std::string out;
    out += show(s.plane, [](Plane p) { return std::string(plane_name(p)); });
    out += " " + show(s.distance, [](Distance d) { return std::string(d == Distance::Absolute ? "G90" : "G91"); });
    out += " " + show(s.units, [](Units u) { return std::string(u == Units::Mm ? "mm" : "inch"); });
    out += " cycle=" + show(s.cycle, [](const std::optional<ActiveCycle>& c) {
        if (!c) return std::string("none");
        return c->macro.empty() ? fmt::format("G{}", c->code) : fmt::format("G{}({})", c->code, c->macro);
    });
    out += " modin=" + show(s.modin, [](const std::optional<ActiveModin>& m) {
        return m ? m->macro : std::string("none");
    });
    out += " H=" + show(s.length_offset_h, num);
    out += " D=" + show(s.cutter_comp_d, num);
    out += " pos=(" + show(s.x, num) + "," + show(s.y, num) + "," + show(s.z, num) + ")";
    out += " ret=" + show(s.cycle_return, [](CycleReturn r) { return std::string(r == CycleReturn::Initial ? "G98" : "G99"); });
    out += "/" + show(s.return_level, [](int l) { return l ? fmt::format("M{}", l) : std::string("-"); });
    out += " motion=" + show(s.motion, [](int m) { return fmt::format("G{}", m); });
    out += " S=" + show(s.spindle, [](int m) { return fmt::format("M{}", m); });
    return out;
}

}  // namespace osplint
