// `osplint trace`: the modal state the analyzer sees, block by block.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <fmt/format.h>

#include "analyzer/frontend.h"
#include "cli/commands.h"
#include "osplint/osplint.h"

namespace fs = std::filesystem;

namespace osplint::cli {

void add_trace_options(CLI::App& cmd, TraceOptions& o) {
    cmd.add_option("path", o.path, "Program file")->required();
    cmd.add_option("--config", o.config, "Configuration file (default: nearest osplint.toml)");
}

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
    AnalysisResult r = analyze(file, config, options);
    for (size_t i = 0; i < file.blocks.size(); ++i) {
        const Block& b = file.blocks[i];
        if (b.is_empty()) continue;
        const BlockInfo& info = r.blocks[i];
        std::string text(file.source.line_text(b.line));
        if (text.size() > 60) text = text.substr(0, 57) + "...";
        std::cout << fmt::format("{:>6}  {:<60}  {}\n", b.line, text,
                                 info.reachable ? describe_state(info.after) : std::string("(unreachable)"));
        if (info.call)
            std::cout << fmt::format("{:>6}  -> {} {}\n", "", call_kind_name(info.call->kind), info.call->name);
    }
    return 0;
}

}  // namespace osplint::cli
