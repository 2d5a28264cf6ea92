// Subcommands of the osplint executable.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace osplint::cli {

struct CheckOptions {
    std::vector<std::string> paths;
    std::string format = "text";
    std::string config;
    std::string fail_on = "warning";
    std::vector<std::string> select;
    std::vector<std::string> ignore;
    std::string stdin_filename;
    std::string color = "auto";
    unsigned jobs = 0;           // -j: worker threads; 0 = one per core
    std::string baseline;        // --baseline: report only findings not recorded there
    std::string write_baseline;  // --write-baseline: record the current findings there
    uint64_t max_findings = 0;   // --max-findings: per file; 0 = no limit
    uint64_t fold = 10;          // --fold: findings of one kind shown per file before the others fold; 0 = off
    bool engine_stats = false;   // --engine-stats: what the engine did, per file, on stderr
    bool statistics = false;     // --statistics: the number of findings of each rule instead of the findings
    std::string output_file;     // --output-file: the report goes there instead of standard output
    bool quiet = false;          // --quiet: the findings only (no summary, no notes)
    bool fix = false;            // --fix: apply the safe fixes to the files, then report what is left
    bool unsafe_fixes = false;   // --unsafe-fixes: --fix and --diff apply the unsafe fixes too
    bool diff = false;           // --diff: print the fixes as a unified diff, change nothing
    std::vector<std::string> exclude;  // --exclude: glob patterns a directory walk skips, besides osplint.toml's
    bool force_exclude = false;  // --force-exclude: the exclusions apply to the paths named too
};
void add_check_options(CLI::App& cmd, CheckOptions& o);
int run_check(const CheckOptions& o);

struct TraceOptions {
    std::string path;
    std::string config;
    std::string svg;             // --svg OUT.svg: also draw the cycle-axis side view
    bool envelopes_only = false; // --envelopes: only the blocks that run a macro or a hole
};
void add_trace_options(CLI::App& cmd, TraceOptions& o);
int run_trace(const TraceOptions& o);

// The files the command-line paths stand for: files as given, directories
// walked for program files, `-` for standard input; sorted, without
// duplicates. `skip` says which files and folders a walk passes over (and,
// with `skip_named`, which of the paths named are left out too).
using PathFilter = std::function<bool(const std::filesystem::path&)>;
std::vector<std::string> expand_paths(const std::vector<std::string>& args, std::vector<std::string>& errors,
                                      const PathFilter& skip = {}, bool skip_named = false);
bool is_program_file(const std::filesystem::path& p);

}  // namespace osplint::cli
