// `osplint check`: the batch path for CAM pre-flight and CI.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>

#include "analyzer/errors.h"
#include "analyzer/report.h"
#include "cli/commands.h"
#include "osplint/osplint.h"
#include "rules/registry.h"

namespace fs = std::filesystem;

namespace osplint::cli {

void add_check_options(CLI::App& cmd, CheckOptions& o) {
    cmd.add_option("paths", o.paths, "Files, directories (.MIN .SSB .SUB .SDF .LIB .NC) or - for stdin")->required();
    cmd.add_option("--format", o.format, "Output format")->check(CLI::IsMember({"text", "json"}));
    cmd.add_option("--config", o.config, "Configuration file (default: nearest osplint.toml of each file)");
    cmd.add_option("--fail-on", o.fail_on, "Lowest severity that makes the exit code 1")
        ->check(CLI::IsMember({"error", "warning", "info", "never"}));
    cmd.add_option("--select", o.select, "Only these rules (IDs or prefixes such as OSP2)")->delimiter(',');
    cmd.add_option("--ignore", o.ignore, "Not these rules (IDs or prefixes)")->delimiter(',');
    cmd.add_option("--stdin-filename", o.stdin_filename, "Path to report for the program read from stdin");
    cmd.add_option("--color", o.color, "Color in text output")->check(CLI::IsMember({"auto", "always", "never"}));
}

namespace {

// --select / --ignore on top of the configuration's [rules]. OSP001 always
// stays on: a file that does not parse is never passed over silently.
void apply_selection(Config& c, const CheckOptions& o) {
    for (const auto& m : all_rules()) {
        if (m.id == "OSP001") continue;
        bool selected = o.select.empty();
        for (const auto& p : o.select)
            if (rule_matches(m.id, p)) selected = true;
        for (const auto& p : o.ignore)
            if (rule_matches(m.id, p)) selected = false;
        if (!selected) {
            c.rule_severity[std::string(m.id)] = std::nullopt;
        } else if (!o.select.empty() && !c.severity_of(m.id, m.severity, m.enabled_by_default)) {
            // Explicitly selected rules run even when off by default.
            bool explicit_id = false;
            for (const auto& p : o.select)
                if (p == m.id) explicit_id = true;
            if (explicit_id) c.rule_severity[std::string(m.id)] = m.severity;
        }
    }
}

void validate_selection(const CheckOptions& o) {
    for (const auto* list : {&o.select, &o.ignore})
        for (const auto& p : *list) {
            bool any = false;
            for (const auto& m : all_rules())
                if (rule_matches(m.id, p)) any = true;
            if (!any) throw std::runtime_error("no rule matches '" + p + "' (see `osplint rules`)");
        }
}

bool read_stdin(std::string& out) {
    out.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
    return !std::cin.bad();
}

}  // namespace

int run_check(const CheckOptions& o) {
    validate_selection(o);
    std::vector<std::string> errors;
    std::vector<std::string> files = expand_paths(o.paths, errors);

    // Configuration: one file for everything (--config), else the nearest osplint.toml per directory.
    std::map<std::string, std::shared_ptr<Config>> configs;
    std::shared_ptr<Config> fixed;
    if (!o.config.empty()) {
        fixed = std::make_shared<Config>(load_config(o.config));
        apply_selection(*fixed, o);
    }
    auto config_for = [&](const std::string& file) -> std::shared_ptr<Config> {
        if (fixed) return fixed;
        fs::path dir = file == "-" ? fs::current_path() : fs::path(file).parent_path();
        if (dir.empty()) dir = ".";
        std::string key = dir.string();
        if (auto it = configs.find(key); it != configs.end()) return it->second;
        auto c = std::make_shared<Config>();
        if (auto f = find_config(dir)) *c = load_config(*f);
        apply_selection(*c, o);
        configs[key] = c;
        return c;
    };

    // Program names defined by the checked files and by the subprogram files
    // (.SSB/.SUB/.LIB/.MSB) beside them, for unknown-subprogram checks.
    std::string stdin_text;
    bool have_stdin = false;
    ProgramNames names;
    std::map<std::string, bool> scanned_dirs;
    for (const auto& f : files) {
        if (f == "-") {
            if (!have_stdin) {
                read_stdin(stdin_text);
                have_stdin = true;
            }
            collect_program_names(stdin_text, names);
            continue;
        }
        fs::path dir = fs::path(f).parent_path();
        if (dir.empty()) dir = ".";
        if (!scanned_dirs[dir.string()]) {
            scanned_dirs[dir.string()] = true;
            std::error_code ec;
            for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
                std::string ext = it->path().extension().string();
                for (auto& c : ext) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
                if (ext != ".SSB" && ext != ".SUB" && ext != ".LIB" && ext != ".MSB") continue;
                std::error_code e2;
                if (!it->is_regular_file(e2) || it->file_size(e2) > (64u << 20)) continue;
                std::ifstream in(it->path(), std::ios::binary);
                std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
                collect_program_names(text, names);
            }
        }
        std::error_code ec;
        if (fs::is_regular_file(f, ec) && fs::file_size(f, ec) < (1ull << 32)) {
            std::ifstream in(f, std::ios::binary);
            std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            collect_program_names(text, names);
        }
    }

    AnalysisOptions options;
    options.known_programs = &names;
    std::vector<FileResult> results;
    bool io_failed = !errors.empty();
    for (const auto& f : files) {
        auto config = config_for(f);
        FileResult r;
        if (f == "-") {
            std::string name = o.stdin_filename.empty() ? std::string("<stdin>") : o.stdin_filename;
            r = check_text(name, stdin_text, *config, options);
        } else {
            r = check_file(f, *config, options);
        }
        if (!r.io_error.empty()) {
            errors.push_back(r.path + ": " + r.io_error);
            io_failed = true;
        }
        results.push_back(std::move(r));
    }

    bool color = false;
    if (o.color == "always") color = true;
    else if (o.color == "auto") color = isatty(STDOUT_FILENO) && !std::getenv("NO_COLOR");
    if (o.color == "always" && std::getenv("NO_COLOR")) color = false;

    if (o.format == "json") {
        std::cout << render_json(results);
    } else {
        std::cout << render_text(results, TextOptions{color});
    }
    std::cout.flush();
    for (const auto& e : errors) std::cerr << "osplint: " << e << "\n";

    if (io_failed) return 2;
    if (o.fail_on == "never") return 0;
    Severity threshold = *parse_severity(o.fail_on);
    for (const auto& r : results)
        for (const auto& d : r.diagnostics)
            if (d.severity >= threshold) return 1;
    return 0;
}

}  // namespace osplint::cli
