#include "output/sideview.h"

#include <fmt/format.h>

#include "output/svg.h"

namespace osplint {

void SideViews::put(const std::string& path, std::vector<SideView> views) {
    if (views.empty()) return;
    std::lock_guard lock(m_);
    files_[path] = std::move(views);
}

std::vector<SideView> SideViews::take(const std::string& path) {
    std::lock_guard lock(m_);
    auto it = files_.find(path);
    if (it == files_.end()) return {};
    std::vector<SideView> views = std::move(it->second);
    files_.erase(it);
    return views;
}

void SideViewTap::program(const Program& program, bool) { programs_.push_back({program.name, {}, 0}); }

bool SideViewTap::block(const BlockView& view, const LineRef&) {
    if (!view.reachable) return true;
    std::optional<Envelope> env = cycle_envelope(view, config_);
    if (!env) return true;
    if (programs_.empty()) programs_.push_back({});
    if (kept_ >= kMaxCalls) {
        ++programs_.back().omitted;
        return true;
    }
    ++kept_;
    programs_.back().envelopes.push_back(std::move(*env));
    return true;
}

void SideViewTap::begin_file(const std::string& path) {
    programs_.clear();
    kept_ = 0;
    next_.begin_file(path);
}

namespace {

// FNV-1a: the ids of a file's pictures do not depend on the order files end in.
std::string path_key(std::string_view path) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : path) {
        h ^= c;
        h *= 1099511628211ull;
    }
    return fmt::format("{:012x}", h & 0xffffffffffffull);
}

std::string envelope_text(const Envelope& e) {
    if (!e.plane) return "plane not known";
    auto end = [](const std::optional<EnvelopeEnd>& x, bool bounded) {
        return bounded && x ? motion_number(x->value) : std::string("?");
    };
    std::string high = end(e.highest, e.bounded_high);
    if (e.limit_point && !e.points[*e.limit_point].value.known && e.bounded_high) high = "+limit";
    return fmt::format("{} {} .. {}", e.axis, end(e.lowest, e.bounded_low), high);
}

}  // namespace

SideView make_side_view(std::string program, const std::vector<Envelope>& envelopes, const Config& config,
                        const std::string& title, const std::string& id_prefix) {
    SideView v;
    v.program = std::move(program);
    SvgOptions o;
    o.standalone = false;
    o.id_prefix = id_prefix;
    v.svg = render_motion_svg(envelopes, config, title, o).svg;
    for (const auto& e : envelopes) {
        SideView::Call c{e.line, e.title(), envelope_text(e), {}};
        for (const auto& t : travel_violations(e, config)) {
            if (!c.travel.empty()) c.travel += "; ";
            c.travel += fmt::format("{} {} the travel {} {}", t.what, t.below ? "below" : "above",
                                    t.below ? "minimum" : "maximum", motion_number(t.limit));
        }
        v.calls.push_back(std::move(c));
    }
    return v;
}

void SideViewTap::end_file(const std::string& path, const std::string& io_error) {
    std::vector<SideView> views;
    const std::string key = path_key(path);
    for (size_t i = 0; i < programs_.size(); ++i) {
        Collected& p = programs_[i];
        if (p.envelopes.empty() && !p.omitted) continue;
        const std::string title = p.name.empty() ? path : p.name;
        SideView v = make_side_view(p.name, p.envelopes, config_, title, fmt::format("sv{}-{}-", key, i));
        v.omitted = p.omitted;
        views.push_back(std::move(v));
    }
    programs_.clear();
    kept_ = 0;
    views_.put(path, std::move(views));
    next_.end_file(path, io_error);
}

}  // namespace osplint
