// osplint.toml: machine defaults, travel limits, G/M-code macro registrations,
// shop macros (same schema as the shipped catalog) and per-rule severities.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "catalog/catalog.h"
#include "osplint/diagnostic.h"
#include "semantics/modal.h"

namespace osplint {

struct TravelLimit {
    double min = 0;
    double max = 0;
};

struct Config {
    std::string path;                    // the file it was read from; empty for defaults
    Units units = Units::Mm;             // [machine] units: when no G20/G21 is in effect
    Plane plane = Plane::G17;            // [machine] plane at program start
    Distance distance = Distance::Absolute;  // [machine] distance at program start (G90)
    std::map<char, TravelLimit> travel;  // [machine.travel] x/y/z = [min, max]
    // [rules] ID = "error" | "warning" | "info" | "off"
    std::map<std::string, std::optional<Severity>> rule_severity;
    bool explain_unknown = false;        // [analysis] explain-unknown: enable OSP303-style notes
    Catalog catalog = Catalog::builtin();  // shipped macros + [macro.NAME] + [macros.gcode]

    // Effective severity of a rule; nullopt when the rule is off.
    std::optional<Severity> severity_of(std::string_view id, Severity default_severity,
                                        bool enabled_by_default) const;
};

// What a configuration may name: the IDs of the rules (the rules layer knows
// them; api/config.h reads configurations against the built-in rules).
struct RuleIdentity {
    std::string_view id;
    Severity severity;
    bool enabled_by_default;
};
using RuleIdentities = std::vector<RuleIdentity>;

// Reads and validates configuration text. Throws ConfigError (file, line, key).
Config read_config_text(std::string_view text, const std::string& origin, const RuleIdentities& rules);
// The same for a file.
Config read_config_file(const std::filesystem::path& file, const RuleIdentities& rules);
// The nearest osplint.toml in `dir` or its parents.
std::optional<std::filesystem::path> find_config(const std::filesystem::path& dir);
// The effective configuration as TOML (`osplint config`), every rule's severity included.
std::string render_config(const Config& config, const RuleIdentities& rules);

}  // namespace osplint
