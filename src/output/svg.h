// The side-view picture of the cycle-axis envelopes (`osplint trace --svg`).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "semantics/config.h"
#include "semantics/motion.h"

namespace osplint {

// The side-view picture of `osplint trace --svg`: one column per cycle (holes
// of the same cycle with the same envelope share a column), the envelope as a
// bar, R/Z/A/T/I marks, travel limits, violations in red, a legend.
struct SvgPanelScale {
    char axis = 0;
    double v_top = 0;          // axis value at the top of the plot area
    double y_top = 0;          // pixel row of the top of the plot area
    double px_per_unit = 1;    // pixels per axis unit (down = lower value)
    double y(double v) const { return y_top + (v_top - v) * px_per_unit; }
};
struct SvgPicture {
    std::string svg;
    std::vector<SvgPanelScale> panels;
    std::size_t columns = 0;
};
// How the picture is embedded: a file of its own (the XML prologue, a title
// naming the trace), or inline in an HTML page beside other pictures (no
// prologue; the ids of its patterns and gradients prefixed so that they stay
// unique in the page).
struct SvgOptions {
    bool standalone = true;
    std::string id_prefix;
};
SvgPicture render_motion_svg(const std::vector<Envelope>& envelopes, const Config& config, std::string_view title,
                             const SvgOptions& options = {});


}  // namespace osplint
