// osplint.toml: machine defaults, travel limits, G/M-code macro registrations,
// shop macros (same schema as the shipped catalog), per-rule severities (for
// every file and per path), the files a directory walk skips, and the shop-wide
// file a configuration extends.
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
    friend bool operator==(const TravelLimit&, const TravelLimit&) = default;
};
// By axis letter: X, Y, Z.
using TravelLimits = std::map<char, TravelLimit>;
// The limits of X, Y and Z, in that order (nullptr: none for that axis):
// pointers into a TravelLimits, valid while it is neither changed nor gone.
using AxisLimits = std::array<const TravelLimit*, 3>;
inline AxisLimits axis_limits(const TravelLimits& travel) {
    AxisLimits out{};
    for (size_t i = 0; i < 3; ++i)
        if (auto it = travel.find(static_cast<char>('X' + i)); it != travel.end()) out[i] = &it->second;
    return out;
}

// One `exclude` pattern, or the `paths` of one `[[per-path]]` table, with the
// directory its patterns are relative to (that of the file that names them).
struct PathPattern {
    std::string pattern;
    std::filesystem::path base;
    std::string origin;  // the configuration file that names it
};

// Whether `file` (any path; made absolute against the working directory)
// matches `pattern`: a pattern without '/' matches any component of the path
// below `base` (or the file's name when it is elsewhere), one with '/' the
// path relative to `base` (support/glob.h).
bool path_matches(const PathPattern& pattern, const std::filesystem::path& file);

// A `[[per-path]]` table: rule severities for the files its patterns match.
struct PerPathRules {
    std::vector<PathPattern> paths;
    std::map<std::string, std::optional<Severity>> rule_severity;
    std::string origin;
    uint32_t line = 0;
};

struct Config {
    std::string path;                    // the file it was read from; empty for defaults
    std::vector<std::string> extends;    // the files it extends, nearest first (`extend`, chained)
    Units units = Units::Mm;             // [machine] units: when no G20/G21 is in effect
    Plane plane = Plane::G17;            // [machine] plane at program start
    Distance distance = Distance::Absolute;  // [machine] distance at program start (G90)
    TravelLimits travel;  // [machine.travel] x/y/z = [min, max]
    // [rules] ID = "error" | "warning" | "info" | "off"
    std::map<std::string, std::optional<Severity>> rule_severity;
    bool explain_unknown = false;        // [analysis] explain-unknown: enable OSP303-style notes
    // [analysis] may-findings: the severity of a finding that holds on some
    // paths only ("G91 may be in effect here"); nullopt: "off", none reported.
    // Never above the rule's own severity.
    std::optional<Severity> may_severity = Severity::Warning;
    Catalog catalog = Catalog::builtin();  // shipped macros + [macro.NAME] + [codes]
    std::vector<PathPattern> exclude;    // `exclude`: what a directory walk skips (inherited ones first)
    std::vector<PerPathRules> per_path;  // `[[per-path]]`, inherited ones first

    // Whether a directory walk skips `path` (a file or a folder).
    bool excluded(const std::filesystem::path& path) const;
    // The `[[per-path]]` tables that apply to `file`, in order.
    std::vector<size_t> per_path_matching(const std::filesystem::path& file) const;
    // Applies those tables' rule severities on top of [rules].
    void apply_per_path(const std::vector<size_t>& tables);

    // Effective severity of a rule; nullopt when the rule is off.
    std::optional<Severity> severity_of(std::string_view id, Severity default_severity,
                                        bool enabled_by_default) const;
};

// What a configuration may name: the IDs of the rules (the rules layer knows
// them; api/config.h reads configurations against the built-in rules).
struct RuleIdentity {
    std::string_view id;
    std::string_view name;  // "m52-on-call-line": accepted wherever the ID is
    Severity severity;
    bool enabled_by_default;
    // Whether an ID prefix ("OSP", "OSP0") turns it off too; the syntax-error
    // rule is turned off by its own key only.
    bool selected_by_prefix = true;
    // A retired ID: it names `replaced_by` (a renamed rule), or nothing (removed).
    bool retired = false;
    std::string_view replaced_by;
    std::string_view analysis_switch;  // RuleMeta::analysis_switch
};
using RuleIdentities = std::vector<RuleIdentity>;

// The rule that `key` names: its ID or its name, in any case, or a retired ID
// or name redirected to the rule that replaced it. The one mapping from what a
// user writes to a rule (RuleRegistry::resolve uses it too).
const RuleIdentity* resolve_rule(const RuleIdentities& rules, std::string_view key);
// The retired ID or name `key` is, if it is one (resolve_rule follows its
// redirect, if any: this says that it had to).
const RuleIdentity* retired_rule(const RuleIdentities& rules, std::string_view key);
// " (did you mean 'OSP104'?)" for the ID or name nearest to a key that names
// no rule, " (OSP117 was removed)" for a removed one; empty when none is near.
std::string rule_suggestion(const RuleIdentities& rules, std::string_view key);

// Reads and validates configuration text. Throws ConfigError (file, line, key).
// `extend` and the patterns are relative to the directory of `origin`.
Config read_config_text(std::string_view text, const std::string& origin, const RuleIdentities& rules);
// The same for a file.
Config read_config_file(const std::filesystem::path& file, const RuleIdentities& rules);
// The nearest osplint.toml in `dir` or its parents.
std::optional<std::filesystem::path> find_config(const std::filesystem::path& dir);
// The effective configuration as TOML (`osplint config`), every rule's severity included.
std::string render_config(const Config& config, const RuleIdentities& rules);

}  // namespace osplint
