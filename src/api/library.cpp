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

}  // namespace

FileResult check_text(const std::string& path, std::string_view text, const Configuration& config,
                      const CheckOptions& options) {
    Prepared p(options);
    return check_text(path, text, config.get(), p.options);
}

FileResult check_file(const std::string& path, const Configuration& config, const CheckOptions& options) {
    Prepared p(options);
    return check_file(path, config.get(), p.options);
}

void check_file(const std::string& path, const Configuration& config, const CheckOptions& options,
                DiagnosticSink& sink) {
    Prepared p(options);
    check_path(path, config.get(), p.options, sink);
}

}  // namespace osplint
