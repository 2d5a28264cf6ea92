// The side-view picture of `osplint trace --svg` (see svg.h): the layout of
// the picture, one panel per cycle axis with its scale, grid and travel
// limits, one column per group of alike envelopes (bar, marks, labels), and
// the legend.
#include "output/svg.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>

namespace osplint {

// --- The side-view picture ------------------------------------------------------

namespace {

std::string num(double v) { return motion_number(v); }

std::string esc(std::string_view s) {
    std::string out;
    for (char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') out += ' ';
                else out += c;
        }
    }
    return out;
}

std::string px(double v) { return fmt::format("{:.2f}", v); }

// A reference to a pattern or gradient of the head.
std::string url(const std::string& prefix, std::string_view name) { return "url(#" + esc(prefix) + std::string(name) + ")"; }

struct Column {
    std::vector<const Envelope*> members;
    std::vector<TravelViolation> violations;
    const Envelope& env() const { return *members.front(); }
};

std::string column_key(const Envelope& e, const std::vector<TravelViolation>& v) {
    auto end = [](const std::optional<EnvelopeEnd>& x) { return x ? num(x->value) : std::string("-"); };
    std::string marks;
    for (const auto& p : e.points)
        if (!p.mark.empty() && !p.possible) marks += p.mark + "=" + (p.value.known ? num(p.value.value) : "?") + ",";
    // Holes of one cycle and positioning blocks of one MODIN share their origin;
    // CALLs of the same macro with the same motion count as alike.
    return fmt::format("{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}", e.name, static_cast<int>(e.source), e.origin_line, e.axis, end(e.lowest), end(e.highest), e.bounded_low,
                       e.bounded_high, end(e.may_low), end(e.may_high), e.limit_point.has_value(), marks, v.size());
}

// 1, 2, 5 x 10^k, about `target` ticks over `span`.
double nice_step(double span, int target) {
    double raw = span / std::max(1, target);
    double mag = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (raw <= m * mag) return m * mag;
    return 10 * mag;
}

std::string line_label(const Column& c) {
    uint32_t first = c.members.front()->line, last = c.members.back()->line;
    if (c.members.size() == 1) return fmt::format("L{}", first);
    return fmt::format("L{}-{} x{}", first, last, c.members.size());
}

std::string column_name(const Envelope& e) {
    if (e.source == MotionSource::CycleMacro) return e.code;
    return e.name;
}

// --- Layout ---------------------------------------------------------------------

// Columns: consecutive envelopes of the same cycle with the same shape share
// one. Envelopes with an unknown plane (no axis) are counted in `undrawn`.
std::vector<Column> make_columns(const std::vector<Envelope>& envelopes, const Config& config, size_t& undrawn) {
    std::vector<Column> columns;
    for (const auto& e : envelopes) {
        if (!e.axis) {
            ++undrawn;
            continue;
        }
        auto v = travel_violations(e, config);
        std::string key = column_key(e, v);
        if (!columns.empty() && column_key(columns.back().env(), columns.back().violations) == key &&
            columns.back().env().axis == e.axis) {
            columns.back().members.push_back(&e);
            continue;
        }
        columns.push_back(Column{{&e}, std::move(v)});
    }
    return columns;
}

// Where things go: the margins, the size of a column and of a panel, and
// the size of the whole picture.
struct Layout {
    static constexpr double left = 78, col_w = 66, right = 190, plot_h = 340, panel_gap = 96, top = 64;
    static constexpr double legend_h = 196;
    std::vector<char> axes;  // one panel per cycle axis, in order of appearance
    double width = 0, height = 0;
};

Layout make_layout(const std::vector<Column>& columns) {
    Layout l;
    for (const auto& c : columns)
        if (std::find(l.axes.begin(), l.axes.end(), c.env().axis) == l.axes.end()) l.axes.push_back(c.env().axis);
    size_t max_cols = 0;
    for (char a : l.axes) {
        size_t n = 0;
        for (const auto& c : columns)
            if (c.env().axis == a) ++n;
        max_cols = std::max(max_cols, n);
    }
    l.width = std::max(720.0, Layout::left + Layout::col_w * static_cast<double>(std::max<size_t>(max_cols, 1)) +
                                  Layout::right);
    const double panels_h =
        l.axes.empty() ? 60 : static_cast<double>(l.axes.size()) * (Layout::plot_h + Layout::panel_gap);
    l.height = Layout::top + panels_h + Layout::legend_h;
    return l;
}

// The XML prologue (of a picture of its own), the patterns and gradients,
// the background and the titles.
void draw_head(std::string& s, const Layout& l, std::string_view title, const SvgOptions& o) {
    const double left = Layout::left;
    const std::string& id = o.id_prefix;
    if (o.standalone) s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    s += fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" "
        "font-family=\"DejaVu Sans, Arial, Helvetica, sans-serif\" font-size=\"11\">\n",
        px(l.width), px(l.height), px(l.width), px(l.height));
    s += "<title>" + esc(o.standalone ? "osplint trace: " + std::string(title) : std::string(title)) + "</title>\n";
    s += fmt::format(
        "<defs>\n"
        "  <pattern id=\"{0}may\" width=\"6\" height=\"6\" patternUnits=\"userSpaceOnUse\" "
        "patternTransform=\"rotate(45)\">"
        "<line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"6\" stroke=\"#7a9cc6\" stroke-width=\"2\"/></pattern>\n"
        "  <linearGradient id=\"{0}fade-down\" x1=\"0\" y1=\"0\" x2=\"0\" y2=\"1\"><stop offset=\"0\" "
        "stop-color=\"#4a78b5\" stop-opacity=\"0.85\"/><stop offset=\"1\" stop-color=\"#4a78b5\" "
        "stop-opacity=\"0\"/></linearGradient>\n"
        "  <linearGradient id=\"{0}fade-up\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\"><stop offset=\"0\" "
        "stop-color=\"#4a78b5\" stop-opacity=\"0.85\"/><stop offset=\"1\" stop-color=\"#4a78b5\" "
        "stop-opacity=\"0\"/></linearGradient>\n"
        "</defs>\n",
        esc(id));
    s += fmt::format("<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"#ffffff\"/>\n", px(l.width), px(l.height));
    s += fmt::format("<text x=\"{}\" y=\"26\" font-size=\"16\" font-weight=\"bold\">{}</text>\n", px(left - 60),
                     esc(std::string(title)));
    s += fmt::format("<text x=\"{}\" y=\"44\" fill=\"#555555\">Side view of the cycle axis: one bar per macro call "
                     "or fixed-cycle hole, lowest to highest point</text>\n",
                     px(left - 60));
    if (l.axes.empty())
        s += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"#555555\">No macro call and no fixed-cycle hole in this "
                         "program.</text>\n",
                         px(left - 60), px(Layout::top + 30));
}

// --- One panel: a cycle axis -------------------------------------------------------

// A panel's columns, its scale and the travel limits of its axis.
struct Panel {
    char axis = 0;
    std::vector<const Column*> cols;
    SvgPanelScale scale;
    double v_top = 0, v_bot = 0;  // axis values at the top and the bottom of the plot area
    double y_top = 0, y_bot = 0;  // pixel rows of the plot area
    double plot_right = 0;
    const TravelLimit* travel = nullptr;
    bool show_min = false, show_max = false;  // the travel limit is near enough to be drawn to scale
    std::string id;  // prefix of the ids of the patterns and gradients (SvgOptions)
};

Panel make_panel(const std::vector<Column>& columns, const Config& config, char axis, double panel_top) {
    Panel p;
    p.axis = axis;
    for (const auto& c : columns)
        if (c.env().axis == axis) p.cols.push_back(&c);
    // The value range: every known end, then the travel limits when they are near.
    double lo = INFINITY, hi = -INFINITY;
    auto take = [&](double v) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    };
    for (const Column* c : p.cols)
        for (const Envelope* e : c->members) {
            if (e->lowest) take(e->lowest->value);
            if (e->highest) take(e->highest->value);
            if (e->may_low) take(e->may_low->value);
            if (e->may_high) take(e->may_high->value);
            for (const auto& pt : e->points)
                if (!pt.possible && pt.value.known) take(pt.value.value);
        }
    if (!std::isfinite(lo)) {
        lo = -10;
        hi = 10;
    }
    if (auto it = config.travel.find(axis); it != config.travel.end()) p.travel = &it->second;
    double span = std::max(hi - lo, 10.0);
    if (p.travel) {
        p.show_min = p.travel->min >= lo - 1.5 * span;
        p.show_max = p.travel->max <= hi + 1.5 * span;
        if (p.show_min) take(p.travel->min);
        if (p.show_max) take(p.travel->max);
    }
    span = std::max(hi - lo, 10.0);
    double pad = span * 0.08;
    p.v_top = hi + pad;
    p.v_bot = lo - pad;
    p.y_top = panel_top + 24;
    const double ppu = Layout::plot_h / (p.v_top - p.v_bot);
    p.scale = SvgPanelScale{axis, p.v_top, p.y_top, ppu};
    p.y_bot = p.y_top + Layout::plot_h;
    p.plot_right = Layout::left + Layout::col_w * static_cast<double>(p.cols.size());
    return p;
}

// The panel's group, its heading, the frame, the shading of every other
// column and the grid with its ticks.
void draw_panel_frame(std::string& s, const Panel& p, double panel_top) {
    const double left = Layout::left, col_w = Layout::col_w, plot_h = Layout::plot_h;
    s += fmt::format("<g class=\"panel\" data-axis=\"{}\" data-v-top=\"{}\" data-y-top=\"{}\" "
                     "data-px-per-unit=\"{}\">\n",
                     p.axis, fmt::format("{:.6f}", p.v_top), fmt::format("{:.6f}", p.y_top),
                     fmt::format("{:.9f}", p.scale.px_per_unit));
    s += fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"13\" font-weight=\"bold\">{} axis (cycle axis{})</text>\n",
                     px(left - 60), px(panel_top + 12), p.axis,
                     p.axis == 'Z' ? ", G17" : p.axis == 'Y' ? ", G18" : ", G19");
    // Frame, grid and ticks.
    s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#f7f8fa\" stroke=\"#c8ccd2\"/>\n",
                     px(left), px(p.y_top), px(p.plot_right - left), px(plot_h));
    for (size_t i = 1; i < p.cols.size(); i += 2)  // every other column shaded, under the grid
        s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#eceef2\"/>\n",
                         px(left + col_w * static_cast<double>(i)), px(p.y_top + 0.5), px(col_w), px(plot_h - 1));
    double step = nice_step(p.v_top - p.v_bot, 7);
    for (double t = std::ceil(p.v_bot / step) * step; t <= p.v_top + 1e-9; t += step) {
        double y = p.scale.y(t);
        s += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"1\"/>\n",
                         px(left - 5), px(y), px(p.plot_right), px(y), std::fabs(t) < 1e-9 ? "#9aa0a8" : "#e3e6ea");
        s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\" fill=\"#444444\">{}</text>\n", px(left - 8),
                         px(y + 4), num(t));
    }
}

// The travel limits of the axis: a dashed line when near, else a note that
// the limit is off scale.
void draw_travel_limits(std::string& s, const Panel& p) {
    const double left = Layout::left;
    if (!p.travel) {
        s += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"#777777\">no [machine.travel] for {}</text>\n",
                         px(p.plot_right + 18), px(p.y_top + 14), static_cast<char>(std::tolower(p.axis)));
        return;
    }
    auto limit_line = [&](double v, const char* which) {
        double y = p.scale.y(v);
        s += fmt::format("<line class=\"travel\" x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#c62828\" "
                         "stroke-width=\"1.5\" stroke-dasharray=\"8 4\"/>\n",
                         px(left), px(y), px(p.plot_right + 14), px(y));
        s += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"#c62828\">{} travel {} {}</text>\n", px(p.plot_right + 18),
                         px(y + 4), p.axis, which, num(v));
    };
    auto off_scale = [&](double v, const char* which, bool below) {
        double y = below ? p.y_bot - 6 : p.y_top + 14;
        s += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"#c62828\">{} travel {} {}</text>\n", px(p.plot_right + 18),
                         px(y - 12), p.axis, which, num(v));
        s += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"#c62828\" font-size=\"9\">(off scale, {})</text>\n",
                         px(p.plot_right + 18), px(y), below ? "further down" : "further up");
    };
    if (p.show_max) limit_line(p.travel->max, "max");
    else off_scale(p.travel->max, "max", false);
    if (p.show_min) limit_line(p.travel->min, "min");
    else off_scale(p.travel->min, "min", true);
}

// --- One column ---------------------------------------------------------------------

// Where a column's bar goes: the column's left edge, the bar's left edge and width.
struct ColumnBox {
    double cx, bx, bw;
};

// The tooltip: the envelope, its lines, its extremes and why it is not bounded.
std::string column_tooltip(const Column& c, const std::string& lines) {
    const Envelope& e = c.env();
    std::string tip = e.title() + ", line" + (c.members.size() > 1 ? "s " : " ") + lines;
    if (e.lowest) tip += "\nlowest " + num(e.lowest->value) + ": " + e.points[e.lowest->point].describe();
    if (e.highest) tip += "\nhighest " + num(e.highest->value) + ": " + e.points[e.highest->point].describe();
    for (const auto* u : e.unknown_points()) tip += "\nnot known: " + u->describe();
    for (const auto& v : c.violations)
        tip += fmt::format("\n{} the travel limit {}: {}", v.below ? "below" : "above", num(v.limit), v.what);
    return tip;
}

// The envelope bar, with what it may reach beyond its ends (hatched); an
// unbounded one faded toward the side that cannot be bounded.
void draw_bar(std::string& s, const Panel& p, const Envelope& e, const ColumnBox& box) {
    const double bx = box.bx, bw = box.bw;
    const SvgPanelScale& scale = p.scale;
    // Possible reach (dashed, hatched).
    auto may_rect = [&](double a, double b) {
        double y1 = scale.y(std::max(a, b)), y2 = scale.y(std::min(a, b));
        s += fmt::format("<rect class=\"may\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{}\" "
                         "stroke=\"#4a78b5\" stroke-dasharray=\"4 3\"/>\n",
                         px(bx + 3), px(y1), px(bw - 6), px(std::max(0.0, y2 - y1)), url(p.id, "may"));
    };
    if (e.may_low && e.lowest) may_rect(e.may_low->value, e.lowest->value);
    if (e.may_high && e.highest) may_rect(e.highest->value, e.may_high->value);
    // The envelope bar.
    double top_v = e.highest ? e.highest->value : (e.lowest ? e.lowest->value : 0);
    double bot_v = e.lowest ? e.lowest->value : top_v;
    bool has_bar = e.lowest || e.highest;
    if (has_bar && e.bounded_low && e.bounded_high) {
        double y1 = scale.y(top_v), y2 = scale.y(bot_v);
        s += fmt::format("<rect class=\"envelope\" data-low=\"{}\" data-high=\"{}\" x=\"{}\" y=\"{}\" "
                         "width=\"{}\" height=\"{}\" fill=\"#4a78b5\" fill-opacity=\"0.85\" stroke=\"#2b4f80\"/>\n",
                         num(bot_v), num(top_v), px(bx), fmt::format("{:.4f}", y1), px(bw),
                         fmt::format("{:.4f}", std::max(0.0, y2 - y1)));
        return;
    }
    // Unbounded: the known part, faded toward the side that cannot be bounded.
    double y1 = has_bar ? scale.y(top_v) : p.y_top + Layout::plot_h * 0.35;
    double y2 = has_bar ? scale.y(bot_v) : p.y_top + Layout::plot_h * 0.65;
    s += fmt::format("<rect class=\"unbounded\" data-low=\"?\" data-high=\"?\" x=\"{}\" y=\"{}\" width=\"{}\" "
                     "height=\"{}\" fill=\"#4a78b5\" fill-opacity=\"0.35\" stroke=\"#2b4f80\" "
                     "stroke-dasharray=\"3 3\"/>\n",
                     px(bx), px(y1), px(bw), px(std::max(2.0, y2 - y1)));
    s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{}\"/>\n", px(bx),
                     px(y2), px(bw), px(std::max(0.0, p.y_bot - y2)), url(p.id, "fade-down"));
    s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{}\"/>\n", px(bx),
                     px(p.y_top), px(bw), px(std::max(0.0, y1 - p.y_top)), url(p.id, "fade-up"));
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\" "
                     "fill=\"#2b4f80\">?</text>\n",
                     px(bx + bw / 2), px((y1 + y2) / 2 + 5));
}

// The part beyond a travel limit, in red; a trip to the + limit without a
// configured travel, as an arrow up.
void draw_beyond(std::string& s, const Panel& p, const Column& c, const ColumnBox& box) {
    const Envelope& e = c.env();
    const double bx = box.bx, bw = box.bw;
    for (const auto& v : c.violations) {
        if (v.axis != p.axis) continue;
        double y1 = p.scale.y(v.below ? v.limit : v.value), y2 = p.scale.y(v.below ? v.value : v.limit);
        s += fmt::format("<rect class=\"violation\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#d32f2f\" "
                         "stroke=\"#8e0000\"/>\n",
                         px(bx - 2), px(y1), px(bw + 4), px(std::max(2.0, y2 - y1)));
    }
    // Trip to the + limit without a configured travel: an arrow up.
    if (e.limit_point && !e.points[*e.limit_point].value.known && e.highest) {
        double y1 = p.scale.y(e.highest->value);
        s += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"#2b4f80\" stroke-width=\"2\"/>"
                         "<path d=\"M {3} {2} L {0} {4} L {5} {2} Z\" fill=\"#2b4f80\"/>\n",
                         px(bx + bw / 2), px(y1), px(p.y_top + 8), px(bx + bw / 2 - 5), px(p.y_top),
                         px(bx + bw / 2 + 5));
    }
}

// Marks (R, Z, A, T, I, G71) with labels stacked so they do not overlap.
void draw_marks(std::string& s, const Panel& p, const Envelope& e, const ColumnBox& box) {
    const double bx = box.bx, bw = box.bw;
    struct Lab {
        double y;
        std::string text;
    };
    std::vector<Lab> labs;
    std::set<std::string> done;
    for (const auto& pt : e.points) {
        if (pt.mark.empty() || pt.possible || !pt.value.known) continue;
        std::string key = pt.mark + "@" + num(pt.value.value);
        if (!done.insert(key).second) continue;
        double y = p.scale.y(pt.value.value);
        s += fmt::format("<line class=\"mark\" x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#1b1b1b\" "
                         "stroke-width=\"1.5\"/>\n",
                         px(bx - 4), px(y), px(bx + bw + 4), px(y));
        labs.push_back({y, pt.mark});
    }
    std::sort(labs.begin(), labs.end(), [](const Lab& a, const Lab& b) { return a.y < b.y; });
    double last = -1e9;
    for (auto& l : labs) {
        double y = std::max(l.y + 3.5, last + 10);
        last = y;
        s += fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"9\" fill=\"#1b1b1b\">{}</text>\n", px(bx + bw + 6),
                         px(y), esc(l.text));
    }
}

// The end values (outside any "may reach" part), and under the plot the
// macro or cycle, the lines and TRAVEL when a limit is passed.
void draw_column_labels(std::string& s, const Panel& p, const Column& c, const ColumnBox& box) {
    const Envelope& e = c.env();
    const double cx = box.cx, bx = box.bx, bw = box.bw, col_w = Layout::col_w;
    const bool bad = !c.violations.empty();
    if (e.highest) {
        double v_hi = e.may_high ? std::max(e.may_high->value, e.highest->value) : e.highest->value;
        s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"9\" fill=\"{}\">{}</text>\n",
                         px(bx + bw / 2), px(std::max(p.y_top + 9, p.scale.y(v_hi) - 4)), bad ? "#b71c1c" : "#1b1b1b",
                         num(e.highest->value));
    }
    if (e.lowest && e.highest && e.lowest->value != e.highest->value) {
        double v_lo = e.may_low ? std::min(e.may_low->value, e.lowest->value) : e.lowest->value;
        s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"9\" fill=\"{}\">{}</text>\n",
                         px(bx + bw / 2), px(std::min(p.y_bot - 3, p.scale.y(v_lo) + 11)), bad ? "#b71c1c" : "#1b1b1b",
                         num(e.lowest->value));
    }
    // Labels under the plot.
    const char* colour = bad ? "#c62828" : "#1b1b1b";
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-weight=\"bold\" fill=\"{}\">{}</text>\n",
                     px(cx + col_w / 2), px(p.y_bot + 16), colour, esc(column_name(e)));
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"9\" fill=\"{}\">{}</text>\n",
                     px(cx + col_w / 2), px(p.y_bot + 29), colour, esc(line_label(c)));
    if (bad)
        s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"9\" font-weight=\"bold\" "
                         "fill=\"#c62828\">TRAVEL</text>\n",
                         px(cx + col_w / 2), px(p.y_bot + 41));
}

// Column `i` of a panel: a group with its tooltip, the bar, the marks and the labels.
void draw_column(std::string& s, const Panel& p, size_t i) {
    const Column& c = *p.cols[i];
    const double cx = Layout::left + Layout::col_w * static_cast<double>(i);
    const ColumnBox box{cx, cx + 17, Layout::col_w - 34};
    std::string lines;
    for (const Envelope* m : c.members) lines += fmt::format("{}{}", lines.empty() ? "" : ",", m->line);
    s += fmt::format("<g class=\"column\" data-lines=\"{}\">\n<title>{}</title>\n", lines, esc(column_tooltip(c, lines)));
    draw_bar(s, p, c.env(), box);
    draw_beyond(s, p, c, box);
    draw_marks(s, p, c.env(), box);
    draw_column_labels(s, p, c, box);
    s += "</g>\n";
}

// A panel: frame and grid, travel limits, the columns, the axis line.
void draw_panel(std::string& s, const Panel& p, double panel_top) {
    draw_panel_frame(s, p, panel_top);
    draw_travel_limits(s, p);
    for (size_t i = 0; i < p.cols.size(); ++i) draw_column(s, p, i);
    // Axis line.
    s += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"#444444\" stroke-width=\"1.2\"/>\n",
                     px(Layout::left), px(p.y_top), px(p.y_bot));
    s += "</g>\n";
}

// --- Legend --------------------------------------------------------------------------

void draw_legend(std::string& s, const Layout& layout, double panel_top, size_t undrawn, const std::string& id) {
    double ly = panel_top + (layout.axes.empty() ? 30 : 0);
    double lx = Layout::left - 60;
    s += fmt::format("<g class=\"legend\">\n<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#ffffff\" "
                     "stroke=\"#c8ccd2\"/>\n",
                     px(lx), px(ly - 6), px(layout.width - lx - 12), px(Layout::legend_h - 14));
    auto legend = [&](double x, double y, const std::string& swatch, const std::string& text) {
        s += swatch;
        s += fmt::format("<text x=\"{}\" y=\"{}\">{}</text>\n", px(x + 30), px(y + 10), esc(text));
    };
    double x1 = lx + 12;
    double row = ly + 4;
    auto next = [&]() {
        double r = row;
        row += 21;
        return r;
    };
    double y = next();
    legend(x1, y,
           fmt::format("<rect x=\"{}\" y=\"{}\" width=\"20\" height=\"12\" fill=\"#4a78b5\" fill-opacity=\"0.85\" "
                       "stroke=\"#2b4f80\"/>\n", px(x1), px(y)),
           "cycle-axis envelope: from the lowest to the highest point the call or hole reaches");
    y = next();
    legend(x1, y,
           fmt::format("<rect x=\"{}\" y=\"{}\" width=\"20\" height=\"12\" fill=\"#d32f2f\" stroke=\"#8e0000\"/>\n",
                       px(x1), px(y)),
           "beyond the travel limit (OSP301); the column label says TRAVEL");
    y = next();
    legend(x1, y,
           fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#c62828\" stroke-width=\"1.5\" "
                       "stroke-dasharray=\"8 4\"/>\n", px(x1), px(y + 6), px(x1 + 20), px(y + 6)),
           "[machine.travel] limit of the axis");
    y = next();
    legend(x1, y,
           fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#1b1b1b\" stroke-width=\"1.5\"/>\n",
                       px(x1), px(y + 6), px(x1 + 20), px(y + 6)),
           "marks: R = R point, Z = Z point, A = PA, T = PT, I = initial point, G71 = M53 level, +lim = M52/PM=52");
    y = next();
    legend(x1, y,
           fmt::format("<rect x=\"{}\" y=\"{}\" width=\"20\" height=\"12\" fill=\"{}\" stroke=\"#4a78b5\" "
                       "stroke-dasharray=\"4 3\"/>\n", px(x1), px(y), url(id, "may")),
           "may reach: a stroke of unprinted direction, or a step whose condition is not known");
    y = next();
    legend(x1, y,
           fmt::format("<rect x=\"{}\" y=\"{}\" width=\"20\" height=\"12\" fill=\"{}\" stroke=\"#2b4f80\" "
                       "stroke-dasharray=\"3 3\"/>\n", px(x1), px(y), url(id, "fade-down")),
           "? = cannot be bounded: an argument or the start position is not known");
    y = next();
    legend(x1, y, "", "under each column: macro or cycle, line numbers (x4 = four blocks with the same motion)");
    if (undrawn)
        s += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"#777777\">{} call(s) with an unknown plane are not drawn.</text>\n",
                         px(x1), px(row + 10), undrawn);
    s += "</g>\n";
}

}  // namespace

SvgPicture render_motion_svg(const std::vector<Envelope>& envelopes, const Config& config, std::string_view title,
                             const SvgOptions& options) {
    SvgPicture pic;
    size_t undrawn = 0;
    const std::vector<Column> columns = make_columns(envelopes, config, undrawn);
    pic.columns = columns.size();
    const Layout layout = make_layout(columns);

    std::string s;
    draw_head(s, layout, title, options);
    double panel_top = Layout::top;
    for (char axis : layout.axes) {
        Panel panel = make_panel(columns, config, axis, panel_top);
        panel.id = options.id_prefix;
        pic.panels.push_back(panel.scale);
        draw_panel(s, panel, panel_top);
        panel_top += Layout::plot_h + Layout::panel_gap;
    }
    draw_legend(s, layout, panel_top, undrawn, options.id_prefix);
    s += "</svg>\n";
    pic.svg = std::move(s);
    return pic;
}

}  // namespace osplint
