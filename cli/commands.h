// Subcommands of the osplint executable.
#pragma once

#include <filesystem>
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
};
void add_check_options(CLI::App& cmd, CheckOptions& o);
int run_check(const CheckOptions& o);

struct TraceOptions {
    std::string path;
    std::string config;
};
void add_trace_options(CLI::App& cmd, TraceOptions& o);
int run_trace(const TraceOptions& o);

std::vector<std::string> expand_paths(const std::vector<std::string>& args, std::vector<std::string>& errors);
bool is_program_file(const std::filesystem::path& p);

}  // namespace osplint::cli
