// osplint command line: check, rules, explain, config (and trace, lsp).
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "support/embedded.h"
#include "support/errors.h"
#include "api/config.h"
#include "cli/commands.h"
#include "osplint/osplint.h"
#include "support/text.h"
#include "rules/registry.h"

namespace fs = std::filesystem;
using namespace osplint;

namespace osplint::cli {

int run_lsp();  // cli/lsp.cpp

bool is_program_file(const fs::path& p) {
    std::string ext = p.extension().string();
    for (auto& c : ext) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return ext == ".MIN" || ext == ".SSB" || ext == ".SUB" || ext == ".SDF" || ext == ".LIB" || ext == ".NC" ||
           ext == ".MSB";
}

std::vector<std::string> expand_paths(const std::vector<std::string>& args, std::vector<std::string>& errors,
                                      const PathFilter& skip, bool skip_named) {
    std::vector<std::string> files;
    for (const auto& a : args) {
        if (a == "-") {
            files.push_back(a);
            continue;
        }
        std::error_code ec;
        fs::path p(a);
        if (skip && skip_named && skip(p)) continue;  // --force-exclude
        if (fs::is_directory(p, ec)) {
            std::vector<std::string> found;
            bool skipped = false;
            fs::recursive_directory_iterator it(p, fs::directory_options::skip_permission_denied, ec), end;
            if (ec) {
                errors.push_back(a + ": cannot read directory: " + ec.message());
                continue;
            }
            for (; it != end; it.increment(ec)) {
                if (ec) break;
                std::error_code e2;
                if (it->is_directory(e2)) {
                    if (skip && skip(it->path())) {
                        it.disable_recursion_pending();
                        skipped = true;
                    }
                    continue;
                }
                if (!it->is_regular_file(e2) || !is_program_file(it->path())) continue;
                if (skip && skip(it->path())) {
                    skipped = true;
                    continue;
                }
                found.push_back(it->path().string());
            }
            std::sort(found.begin(), found.end());
            if (found.empty() && !skipped)
                errors.push_back(a + ": no program files (.MIN .SSB .SUB .SDF .LIB .NC .MSB) in this directory");
            files.insert(files.end(), found.begin(), found.end());
        } else {
            files.push_back(a);  // missing files and links are reported when checked
        }
    }
    std::vector<std::string> unique;
    for (auto& f : files)
        if (std::find(unique.begin(), unique.end(), f) == unique.end()) unique.push_back(f);
    return unique;
}

}  // namespace osplint::cli

namespace {

int cmd_rules(const std::string& format) {
    if (format == "json") {
        // Every rule's metadata, for tools and editors.
        nlohmann::json out = nlohmann::json::array();
        for (const auto& m : all_rules()) {
            const char* fix = m.fix == FixSafety::Safe ? "safe" : m.fix == FixSafety::Unsafe ? "unsafe" : "none";
            out.push_back({{"id", m.id},
                           {"name", m.name},
                           {"severity", severity_name(m.severity)},
                           {"category", category_name(m.category)},
                           {"summary", m.summary},
                           {"enabled_by_default", m.enabled_by_default},
                           {"fix", fix},
                           {"suppressible", m.suppressible},
                           {"status", status_name(m.status)},
                           {"since", m.since},
                           {"blocks", m.blocks == RuleBlocks::All ? "all" : "statements"},
                           {"analysis_switch", m.analysis_switch},
                           {"selected_by_prefix", m.selected_by_prefix},
                           {"reports_may", m.reports_may}});
        }
        std::cout << out.dump(2) << "\n";
        return 0;
    }
    for (const auto& m : all_rules()) {
        const char* fix = m.fix == FixSafety::Safe ? " [fix]" : m.fix == FixSafety::Unsafe ? " [unsafe fix]" : "";
        std::cout << fmt::format("{}  {:<32} {:<8} {:<13} {}{}{}{}\n", m.id, m.name, severity_name(m.severity),
                                 category_name(m.category), m.summary, m.enabled_by_default ? "" : " (off by default)",
                                 m.status == RuleStatus::Preview ? " (preview)" : "", fix);
    }
    return 0;
}

int cmd_explain(const std::string& what_in) {
    std::string what = what_in;
    for (auto& c : what) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (const RuleMeta* by_key = builtin_rules().resolve(what_in)) what = std::string(by_key->id);  // ID or name
    if (find_rule(what)) {
        if (auto doc = embedded::find("docs/rules/" + what + ".md")) {
            std::cout << *doc;
            if (!doc->empty() && doc->back() != '\n') std::cout << "\n";
            return 0;
        }
        const RuleMeta* m = find_rule(what);
        std::cout << m->id << " " << m->name << ": " << m->summary << "\n";
        return 0;
    }
    Config defaults;
    if (auto cfg = find_config(fs::current_path())) {
        try {
            defaults = load_config(*cfg);
        } catch (const ConfigError& e) {
            std::cerr << "osplint: " << e.what() << "\n";
            return 2;
        }
    }
    const MacroSpec* spec = defaults.catalog.find(what);
    if (!spec) spec = defaults.catalog.find_by_code(what);
    if (spec) {
        std::cout << defaults.catalog.render_card(*spec, false);
        return 0;
    }
    // A fixed cycle by its G code: G81, g83.
    if (what.size() > 1 && what[0] == 'G' && what.size() <= 4 &&
        std::all_of(what.begin() + 1, what.end(), [](char c) { return c >= '0' && c <= '9'; }))
        if (const CycleSpec* cycle = defaults.catalog.find_cycle(std::stoi(what.substr(1)))) {
            std::cout << defaults.catalog.render_card(*cycle, false);
            return 0;
        }
    std::cerr << "osplint: '" << what_in
              << "' is neither a rule ID or name (see `osplint rules`), a macro or G/M code of the catalog, nor a "
                 "fixed cycle"
              << builtin_rules().suggestion(what_in) << "\n";
    return 2;
}

// After a usage error: "did you mean" for a mistyped subcommand or long
// option, which CLI11 does not suggest by itself. Looks at the words of the
// command line the way the parser does: the first word that is not an option
// names the subcommand; every `--name` before a bare `--` must be an option
// of that subcommand (or of the application).
void suggest_after_usage_error(const CLI::App& app, int argc, char** argv) {
    const CLI::App* sub = nullptr;
    int first = 1;
    if (argc > 1 && argv[1][0] != '-') {
        const std::string word = argv[1];
        std::vector<std::string_view> names;
        for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; })) {
            names.push_back(s->get_name());
            if (s->get_name() == word) sub = s;
        }
        if (!sub) {
            const std::string near = closest_match(word, names);
            std::cerr << "osplint: unknown command '" << word << "'"
                      << (near.empty() ? std::string(" (see osplint --help)") : ": did you mean '" + near + "'?")
                      << "\n";
            return;
        }
        first = 2;
    }
    std::vector<std::string> longs;
    for (const CLI::App* a : {sub, &app}) {
        if (!a) continue;
        for (const CLI::Option* opt : a->get_options())
            for (const auto& l : opt->get_lnames()) longs.push_back("--" + l);
    }
    for (int i = first; i < argc; ++i) {
        std::string word = argv[i];
        if (word == "--") break;
        if (word.size() < 3 || word.compare(0, 2, "--") != 0) continue;
        word = word.substr(0, word.find('='));
        if (std::find(longs.begin(), longs.end(), word) != longs.end()) continue;
        const std::string near = closest_match(word, std::vector<std::string_view>(longs.begin(), longs.end()));
        std::cerr << "osplint: unknown option '" << word << "'"
                  << (near.empty() ? std::string() : ": did you mean '" + near + "'?") << "\n";
    }
}

// What a command wrote to standard output must have been written: a full
// disk or a closed descriptor is an error (exit 2), never a silent loss.
int output_written(int code) {
    errno = 0;
    std::cout.flush();
    const bool failed = !std::cout || std::fflush(stdout) != 0 || std::ferror(stdout);
    if (!failed) return code;
    const int e = errno;
    std::string why = e ? std::strerror(e) : "write error";
    if (::fcntl(STDOUT_FILENO, F_GETFD) == -1) why = "standard output is closed";
    std::cerr << "osplint: the report could not be written to standard output: " << why << "\n";
    return 2;
}

// `osplint config`: the configuration --config names, or the one that
// applies in `dir`, with every default filled in.
int cmd_config(const std::string& config_file, const std::string& dir) {
    Config c;
    std::error_code ec;
    if (!config_file.empty()) {
        c = load_config(config_file);
    } else if (!fs::is_directory(dir, ec)) {
        std::cerr << "osplint: " << dir << (fs::exists(dir, ec) ? ": not a directory" : ": no such directory") << "\n";
        return 2;
    } else if (auto f = find_config(dir)) {
        c = load_config(*f);
    }
    std::cout << dump_config(c);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    // Past a file size limit, a write fails (and is reported) instead of
    // ending the process.
    std::signal(SIGXFSZ, SIG_IGN);
    CLI::App app{"osplint: static analyzer for Okuma OSP part programs"};
    app.require_subcommand(0, 1);
    bool show_version = false;
    app.add_flag("--version", show_version, "Print the version and exit");

    cli::CheckOptions check;
    auto* check_cmd = app.add_subcommand("check", "Check part programs (files, directories, - for stdin)");
    cli::add_check_options(*check_cmd, check);

    auto* rules_cmd =
        app.add_subcommand("rules", "List every rule: ID, name, default severity, category, summary");
    std::string rules_format = "text";
    rules_cmd->add_option("--format", rules_format, "text (a table) or json (every rule's metadata)")
        ->check(CLI::IsMember({"text", "json"}));

    std::string explain_what;
    auto* explain_cmd = app.add_subcommand("explain", "Print a rule's documentation, a macro's card or a fixed cycle's card");
    explain_cmd->add_option("what", explain_what, "A rule ID or name (OSP104, m52-on-call-line), a macro name or code (OZAGR, G114) or a fixed cycle (G81)")->required();

    std::string config_file;
    std::string config_dir = ".";
    auto* config_cmd = app.add_subcommand("config", "Print the effective configuration");
    config_cmd->add_option("--config", config_file, "Configuration file (default: nearest osplint.toml)");
    config_cmd->add_option("dir", config_dir, "Directory whose configuration to show");

    cli::TraceOptions trace;
    auto* trace_cmd = app.add_subcommand("trace", "Print the modal state and cycle envelopes block by block");
    cli::add_trace_options(*trace_cmd, trace);

    auto* lsp_cmd = app.add_subcommand("lsp", "Run the language server (LSP 3.17 over stdin/stdout)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        suggest_after_usage_error(app, argc, argv);
        return 2;
    }
    if (show_version) {
        std::cout << "osplint " << version() << "\n";
        std::cout.flush();
        return std::cout ? 0 : 2;
    }
    try {
        if (*check_cmd) return output_written(cli::run_check(check));
        if (*rules_cmd) return output_written(cmd_rules(rules_format));
        if (*explain_cmd) return output_written(cmd_explain(explain_what));
        if (*trace_cmd) return output_written(cli::run_trace(trace));
        if (*lsp_cmd) return cli::run_lsp();
        if (*config_cmd) return output_written(cmd_config(config_file, config_dir));
    } catch (const ConfigError& e) {
        std::cerr << "osplint: configuration error: " << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        std::cerr << "osplint: out of memory\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "osplint: " << e.what() << "\n";
        return 2;
    }
    std::cout << app.help();
    return 2;
}
