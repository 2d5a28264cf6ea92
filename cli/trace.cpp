// `osplint trace`: the modal state the analyzer sees, block by block, and for
// every macro call and fixed-cycle hole the cycle-axis envelope with the
// action-sequence steps behind it. `--svg OUT.svg` also draws the side view.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <fmt/format.h>

#include "syntax/frontend.h"
#include "semantics/motion.h"
#include "cli/commands.h"
#include "osplint/osplint.h"

namespace fs = std::filesystem;

namespace osplint::cli {

void add_trace_options(CLI::App& cmd, TraceOptions& o) {
    cmd.add_option("path", o.path, "Program file")->required();
    cmd.add_option("--config", o.config, "Configuration file (default: nearest osplint.toml)");
    cmd.add_option("--svg", o.svg, "Also write the cycle-axis side view as an SVG picture to this file");
    cmd.add_flag("--envelopes", o.envelopes_only, "Print only the blocks that run a macro or a fixed-cycle hole");
}

namespace {

std::string limits(const Config& config, char axis) {
    auto it = config.travel.find(axis);
    if (it == config.travel.end()) return "no [machine.travel] for " + std::string(1, static_cast<char>(std::tolower(axis)));
    return "travel [" + motion_number(it->second.min) + ", " + motion_number(it->second.max) + "]";
}

void print_envelope(std::ostream& out, const Envelope& env, const Config& config) {
    const std::string pad(8, ' ');
    if (!env.plane) {
        out << pad << env.title() << ": plane not known, cycle axis not known\n";
        return;
    }
    std::string ax(1, env.axis);
    auto end = [&](const std::optional<EnvelopeEnd>& e, bool bounded) {
        if (!bounded) return std::string("?");
        return e ? motion_number(e->value) : std::string("?");
    };
    std::string high = end(env.highest, env.bounded_high);
    if (env.limit_point && !env.points[*env.limit_point].value.known && env.bounded_high) high = "+limit";
    out << pad << ax << " envelope [" << end(env.lowest, env.bounded_low) << ", " << high << "]  " << env.title() << "  ("
        << limits(config, env.axis) << (env.incremental ? ", G91" : "") << ")\n";
    if (env.lowest)
        out << pad << "  lowest  " << fmt::format("{:>9}", motion_number(env.lowest->value)) << "  "
            << env.points[env.lowest->point].describe() << "\n";
    if (env.highest)
        out << pad << "  highest " << fmt::format("{:>9}", motion_number(env.highest->value)) << "  "
            << env.points[env.highest->point].describe() << "\n";
    if (env.may_low)
        out << pad << "  may go down to " << motion_number(env.may_low->value) << ": "
            << env.points[env.may_low->point].describe() << "\n";
    if (env.may_high)
        out << pad << "  may go up to " << motion_number(env.may_high->value) << ": "
            << env.points[env.may_high->point].describe() << "\n";
    for (const auto* p : env.unknown_points()) out << pad << "  not known: " << p->describe() << "\n";
    std::string steps;
    for (const auto& p : env.points) {
        std::string v = p.value.known ? motion_number(p.value.value)
                        : p.reach    ? motion_number(p.reach->lo) + ".." + motion_number(p.reach->hi)
                        : p.limit    ? std::string("+limit")
                                     : std::string("?");
        std::string name = p.expr.empty() || p.expr == p.step ? p.step : p.step + " " + p.expr;
        steps += (steps.empty() ? "" : " | ") + name + "=" + v +
                 (p.possible ? " (may)" : "") + (p.inferred ? " (inferred)" : "");
    }
    out << pad << "  points: " << steps << "\n";
    for (const auto& pp : env.plane_points)
        out << pad << "  at " << pp.axis << motion_number(pp.value) << " (" << pp.what << ")\n";
    for (const auto& s : env.plane_spans)
        out << pad << "  spans " << s.axis << " " << motion_number(s.range.lo) << " .. " << motion_number(s.range.hi)
            << ": " << s.why << "\n";
    for (const auto& n : env.notes) out << pad << "  note: " << n << "\n";
    for (const auto& v : travel_violations(env, config))
        out << pad << "  !! " << (v.below ? "below the " : "above the ") << v.axis << " travel "
            << (v.below ? "minimum " : "maximum ") << motion_number(v.limit) << ": " << v.what << "\n";
}

}  // namespace

int run_trace(const TraceOptions& o) {
    std::ifstream in(o.path, std::ios::binary);
    if (!in || fs::is_directory(o.path)) {
        std::cerr << "osplint: " << o.path << ": cannot read\n";
        return 2;
    }
    std::ostringstream ss;
    ss << in.rdbuf();
    Config config;
    if (!o.config.empty()) config = load_config(o.config);
    else if (auto f = find_config(fs::path(o.path).parent_path().empty() ? fs::path(".") : fs::path(o.path).parent_path()))
        config = load_config(*f);
    ProgramFile file = parse_program_file(o.path, ss.str());
    AnalysisOptions options;
    options.keep_states = true;
    options.only_rules = {"OSP001"};  // the states are what is wanted, not the findings
    AnalysisResult r = analyze(file, config, options);

    std::vector<Envelope> all;
    for (size_t i = 0; i < file.blocks.size(); ++i) {
        const Block& b = file.blocks[i];
        const BlockInfo& info = r.blocks[i];
        const MacroCall* call = info.call ? &*info.call : nullptr;
        std::optional<Envelope> env;
        if (info.reachable) env = cycle_envelope(b, info.before, info.after, call, config);
        if (b.is_empty() || (o.envelopes_only && !env)) continue;
        std::string text(file.source.line_text(b.line));
        if (text.size() > 60) text = text.substr(0, 57) + "...";
        std::cout << fmt::format("{:>6}  {:<60}  {}\n", b.line, text,
                                 info.reachable ? describe_state(info.after) : std::string("(unreachable)"));
        if (call) {
            std::string extra =
                call->kind == CallKind::ModinPositioning ? " (MODIN of line " + std::to_string(call->modin_line) + ")" : "";
            std::cout << fmt::format("{:>6}  -> {} {}{}\n", "", call_kind_name(call->kind), call->name, extra);
        }
        if (env) {
            print_envelope(std::cout, *env, config);
            all.push_back(std::move(*env));
        }
    }
    if (!o.svg.empty()) {
        SvgPicture pic = render_motion_svg(all, config, fs::path(o.path).filename().string());
        std::ofstream out(o.svg, std::ios::binary);
        if (!out) {
            std::cerr << "osplint: " << o.svg << ": cannot write\n";
            return 2;
        }
        out << pic.svg;
        std::cerr << "osplint: wrote " << o.svg << " (" << pic.columns << " column" << (pic.columns == 1 ? "" : "s")
                  << ")\n";
    }
    return 0;
}

}  // namespace osplint::cli
