// The public library API (include/osplint/osplint.h) over the engine.
#include "osplint/osplint.h"

#include "api/check.h"
#include "api/config.h"
#include "engine/workspace.h"
#include "support/errors.h"

namespace osplint {

std::string_view version() { return OSPLINT_VERSION; }

Configuration::Configuration() : impl_(std::make_shared<const Config>()) {}

Configuration Configuration::load(const std::string& path) {
    try {
        return Configuration(std::make_shared<const Config>(load_config(path)));
    } catch (const ConfigError& e) {
        throw ConfigurationError(e.what());
    }
}

Configuration Configuration::parse(std::string_view toml, const std::string& origin) {
    try {
        return Configuration(std::make_shared<const Config>(parse_config(toml, origin)));
    } catch (const ConfigError& e) {
        throw ConfigurationError(e.what());
    }
}

std::optional<std::string> Configuration::find(const std::string& dir) {
    if (auto p = find_config(dir)) return p->string();
    return std::nullopt;
}

std::string Configuration::dump() const { return dump_config(*impl_); }

namespace {

struct Prepared {
    ProgramNames known;
    AnalysisOptions options;
    explicit Prepared(const CheckOptions& o) {
        known.insert(o.known_programs.begin(), o.known_programs.end());
        options.known_programs = &known;
        options.only_rules = o.only_rules;
    }
};

// The configuration of the file at `path`: with the [[per-path]] tables that
// match it applied (a copy in `holder`), or the configuration itself.
const Config& for_path(const Config& config, const std::string& path, std::optional<Config>& holder) {
    if (config.per_path.empty()) return config;
    const std::vector<size_t> tables = config.per_path_matching(path);
    if (tables.empty()) return config;
    holder.emplace(config);
    holder->apply_per_path(tables);
    return *holder;
}

}  // namespace

FileResult check_text(const std::string& path, std::string_view text, const Configuration& config,
                      const CheckOptions& options) {
    Prepared p(options);
    std::optional<Config> holder;
    return check_text(path, text, for_path(config.get(), path, holder), p.options);
}

FileResult check_file(const std::string& path, const Configuration& config, const CheckOptions& options) {
    Prepared p(options);
    std::optional<Config> holder;
    return check_file(path, for_path(config.get(), path, holder), p.options);
}

void check_file(const std::string& path, const Configuration& config, const CheckOptions& options,
                DiagnosticSink& sink) {
    Prepared p(options);
    std::optional<Config> holder;
    check_path(path, for_path(config.get(), path, holder), p.options, sink);
}

}  // namespace osplint
