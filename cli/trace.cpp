// `osplint trace`: the modal state the analyzer sees, block by block, and for
// every macro call and fixed-cycle hole the cycle-axis envelope with the
// action-sequence steps behind it. `--svg OUT.svg` also draws the side view.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "support/text.h"

#include <fmt/format.h>

#include "api/check.h"
#include "api/config.h"
#include "cli/commands.h"
#include "engine/summaries.h"
#include "output/svg.h"
#include "rules/registry.h"
#include "support/io.h"
#include "semantics/motion.h"
#include "semantics/summary.h"

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

// Prints each block as the engine walks it (the same walk as `osplint check`,
// without the rules): nothing is held but the envelopes of the picture.
class TracePrinter final : public BlockObserver {
public:
    TracePrinter(std::ostream& out, const Config& config, const TraceOptions& o, bool keep_envelopes)
        : out_(out), config_(config), o_(o), keep_(keep_envelopes) {}

    bool block(const BlockView& view, const LineRef& line) override {
        const Block& b = view.block;
        std::optional<Envelope> env;
        if (view.reachable) env = cycle_envelope(view, config_);
        if (b.is_empty() || (o_.envelopes_only && !env)) return true;
        std::string text(line.text);
        if (text.size() > 60) text = abbreviate(text, 60);
        out_ << fmt::format("{:>6}  {:<60}  {}\n", b.line, text,
                            view.reachable ? describe_state(view.after) : std::string("(unreachable)"));
        if (const MacroCall* call = view.call) {
            std::string extra = call->kind == CallKind::ModinPositioning
                                    ? " (MODIN of line " + std::to_string(call->modin_line) + ")"
                                    : "";
            if (call->summary)
                extra += " (" + fs::path(call->summary->file).filename().string() + ", line " +
                         std::to_string(call->summary->line) + ": " +
                         (call->summary->changes_anything() ? call->summary->describe() : "leaves the modes as they were") +
                         ")";
            out_ << fmt::format("{:>6}  -> {} {}{}\n", "", call_kind_name(call->kind), call->name, extra);
        }
        if (env) {
            print_envelope(out_, *env, config_);
            if (keep_) envelopes.push_back(std::move(*env));
        }
        return true;
    }
    std::vector<Envelope> envelopes;

private:
    std::ostream& out_;
    const Config& config_;
    const TraceOptions& o_;
    bool keep_;
};

}  // namespace

int run_trace(const TraceOptions& o) {
    Config config;
    if (!o.config.empty()) config = load_config(o.config);
    else if (auto f = find_config(fs::path(o.path).parent_path().empty() ? fs::path(".") : fs::path(o.path).parent_path()))
        config = load_config(*f);
    TracePrinter printer(std::cout, config, o, !o.svg.empty());
    AnalysisOptions options;
    options.observer = &printer;
    options.run_rules = false;  // the states are what is wanted, not the findings
    // The states after a CALL, as `check` sees them: with what the
    // subprograms beside the file leave behind.
    SubprogramDirectories directories;
    SubprogramSummaries summaries(builtin_rules(), directories);
    if (o.path != "-") options.summaries = &summaries;
    DiscardFindings sink;  // the trace reports the states, not findings
    const std::string error = check_path(o.path, config, options, sink);
    std::cout.flush();
    if (!error.empty()) {
        std::cerr << "osplint: " << o.path << ": " << error << "\n";
        return 2;
    }
    if (!o.svg.empty()) {
        SvgPicture pic = render_motion_svg(printer.envelopes, config, fs::path(o.path).filename().string());
        std::string write_error;
        if (!write_file_atomically(o.svg, pic.svg, write_error)) {
            std::cerr << "osplint: " << o.svg << ": not written: " << write_error << "\n";
            return 2;
        }
        std::cerr << "osplint: wrote " << o.svg << " (" << pic.columns << " column" << (pic.columns == 1 ? "" : "s")
                  << ")\n";
    }
    return 0;
}

}  // namespace osplint::cli
