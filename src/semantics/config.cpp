#include "semantics/config.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <toml++/toml.h>

#include "support/errors.h"

namespace osplint {
namespace {

uint32_t line_of(const toml::node& n) { return static_cast<uint32_t>(n.source().begin.line); }

[[noreturn]] void fail(const std::string& origin, const toml::node& n, const std::string& key,
                       const std::string& message) {
    throw ConfigError(origin, line_of(n), key, message);
}

std::string expect_string(const std::string& origin, const toml::node& n, const std::string& key) {
    if (auto s = n.value<std::string>(); s && n.is_string()) return *s;
    fail(origin, n, key, "expected a string");
}

void check_keys(const std::string& origin, const toml::table& t, const std::string& prefix,
                std::initializer_list<std::string_view> allowed) {
    for (const auto& [k, v] : t) {
        bool ok = false;
        for (auto a : allowed)
            if (k.str() == a) ok = true;
        if (!ok) {
            std::string list;
            for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
            fail(origin, v, prefix + std::string(k.str()), "unknown key (expected one of: " + list + ")");
        }
    }
}

const toml::table& expect_table(const std::string& origin, const toml::node& n, const std::string& key) {
    if (const auto* t = n.as_table()) return *t;
    fail(origin, n, key, "expected a table");
}

void read_machine(Config& c, const std::string& origin, const toml::table& m) {
    check_keys(origin, m, "machine.", {"units", "plane", "distance", "travel"});
    if (const auto* n = m.get("units")) {
        auto s = expect_string(origin, *n, "machine.units");
        if (s == "mm") c.units = Units::Mm;
        else if (s == "inch") c.units = Units::Inch;
        else fail(origin, *n, "machine.units", "expected \"mm\" or \"inch\", got \"" + s + "\"");
    }
    if (const auto* n = m.get("plane")) {
        auto s = expect_string(origin, *n, "machine.plane");
        if (s == "G17") c.plane = Plane::G17;
        else if (s == "G18") c.plane = Plane::G18;
        else if (s == "G19") c.plane = Plane::G19;
        else fail(origin, *n, "machine.plane", "expected \"G17\", \"G18\" or \"G19\", got \"" + s + "\"");
    }
    if (const auto* n = m.get("distance")) {
        auto s = expect_string(origin, *n, "machine.distance");
        if (s == "G90") c.distance = Distance::Absolute;
        else if (s == "G91") c.distance = Distance::Incremental;
        else fail(origin, *n, "machine.distance", "expected \"G90\" or \"G91\", got \"" + s + "\"");
    }
    if (const auto* n = m.get("travel")) {
        const auto& t = expect_table(origin, *n, "machine.travel");
        check_keys(origin, t, "machine.travel.", {"x", "y", "z"});
        for (const auto& [k, v] : t) {
            std::string key = "machine.travel." + std::string(k.str());
            const auto* arr = v.as_array();
            if (!arr || arr->size() != 2) fail(origin, v, key, "expected [min, max]");
            double lim[2];
            for (size_t i = 0; i < 2; ++i) {
                const auto& e = *arr->get(i);
                if (e.is_floating_point()) lim[i] = *e.value<double>();
                else if (e.is_integer()) lim[i] = static_cast<double>(*e.value<int64_t>());
                else fail(origin, e, key, "expected numbers");
                if (!std::isfinite(lim[i])) fail(origin, e, key, "expected finite numbers (a travel has two ends)");
            }
            if (!(lim[0] < lim[1])) fail(origin, v, key, "min must be below max");
            c.travel[static_cast<char>(std::toupper(static_cast<unsigned char>(k.str()[0])))] = {lim[0], lim[1]};
        }
    }
}

void read_rules(Config& c, const std::string& origin, const toml::table& r, const RuleIdentities& rules) {
    for (const auto& [k, v] : r) {
        std::string id(k.str());
        std::string key = "rules." + id;
        bool known = false;
        for (const auto& m : rules) known = known || m.id == id;
        if (!known) fail(origin, v, key, "unknown rule ID (see `osplint rules`)");
        auto s = expect_string(origin, v, key);
        if (s == "off") {
            c.rule_severity[id] = std::nullopt;
        } else if (auto sev = parse_severity(s)) {
            c.rule_severity[id] = *sev;
        } else {
            fail(origin, v, key, "expected \"error\", \"warning\", \"info\" or \"off\", got \"" + s + "\"");
        }
    }
}

}  // namespace

std::optional<Severity> Config::severity_of(std::string_view id, Severity default_severity,
                                            bool enabled_by_default) const {
    if (auto it = rule_severity.find(std::string(id)); it != rule_severity.end()) return it->second;
    if (!enabled_by_default) return std::nullopt;
    return default_severity;
}

Config read_config_text(std::string_view text, const std::string& origin, const RuleIdentities& rules) {
    toml::table root;
    try {
        root = toml::parse(text, origin);
    } catch (const toml::parse_error& e) {
        throw ConfigError(origin, static_cast<uint32_t>(e.source().begin.line), "",
                          std::string(e.description()));
    }
    Config c;
    c.path = origin;
    check_keys(origin, root, "", {"machine", "rules", "macros", "macro", "analysis"});
    if (const auto* n = root.get("machine")) read_machine(c, origin, expect_table(origin, *n, "machine"));
    if (const auto* n = root.get("macro")) c.catalog.merge(expect_table(origin, *n, "macro"), origin);
    if (const auto* n = root.get("macros")) {
        const auto& t = expect_table(origin, *n, "macros");
        check_keys(origin, t, "macros.", {"gcode"});
        if (const auto* g = t.get("gcode")) {
            for (const auto& [k, v] : expect_table(origin, *g, "macros.gcode")) {
                std::string code(k.str());
                std::string key = "macros.gcode." + code;
                bool ok = code.size() >= 2 && (code[0] == 'G' || code[0] == 'M');
                for (size_t i = 1; ok && i < code.size(); ++i) ok = std::isdigit(static_cast<unsigned char>(code[i]));
                if (!ok) fail(origin, v, key, "expected a G or M code such as G114 or M204");
                if (auto meaning = Catalog::builtin_meaning(code); !meaning.empty())
                    fail(origin, v, key, code + " is " + std::string(meaning) + " of the control, not a macro code");
                auto macro = expect_string(origin, v, key);
                if (!c.catalog.find(macro))
                    fail(origin, v, key, "macro \"" + macro + "\" is not in the catalog (define it under [macro." +
                                             macro + "])");
                c.catalog.register_code(code, macro);
            }
        }
    }
    if (const auto* n = root.get("rules")) read_rules(c, origin, expect_table(origin, *n, "rules"), rules);
    if (const auto* n = root.get("analysis")) {
        const auto& t = expect_table(origin, *n, "analysis");
        check_keys(origin, t, "analysis.", {"explain-unknown"});
        if (const auto* e = t.get("explain-unknown")) {
            if (!e->is_boolean()) fail(origin, *e, "analysis.explain-unknown", "expected true or false");
            c.explain_unknown = *e->value<bool>();
        }
    }
    // explain-unknown turns on the "cannot tell" findings (OSP303) unless [rules] says otherwise.
    if (c.explain_unknown && !c.rule_severity.count("OSP303")) c.rule_severity["OSP303"] = Severity::Info;
    return c;
}

Config read_config_file(const std::filesystem::path& file, const RuleIdentities& rules) {
    std::error_code ec;
    const auto st = std::filesystem::status(file, ec);
    if (!std::filesystem::exists(st)) throw ConfigError(file.string(), 0, "", "no such configuration file");
    if (std::filesystem::is_directory(st))
        throw ConfigError(file.string(), 0, "", "is a directory, not a configuration file (osplint.toml)");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ConfigError(file.string(), 0, "", "cannot read the configuration file");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw ConfigError(file.string(), 0, "", "cannot read the configuration file");
    return read_config_text(ss.str(), file.string(), rules);
}

std::optional<std::filesystem::path> find_config(const std::filesystem::path& dir) {
    std::error_code ec;
    std::filesystem::path d = std::filesystem::absolute(dir, ec);
    if (ec) return std::nullopt;
    for (int depth = 0; depth < 256; ++depth) {
        auto candidate = d / "osplint.toml";
        if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
        if (!d.has_parent_path() || d.parent_path() == d) break;
        d = d.parent_path();
    }
    return std::nullopt;
}

std::string render_config(const Config& c, const RuleIdentities& rule_ids) {
    toml::table root;
    toml::table machine;
    machine.insert("units", c.units == Units::Mm ? "mm" : "inch");
    machine.insert("plane", plane_name(c.plane));
    machine.insert("distance", c.distance == Distance::Absolute ? "G90" : "G91");
    toml::table travel;
    for (const auto& [axis, lim] : c.travel) {
        toml::array a;
        a.push_back(lim.min);
        a.push_back(lim.max);
        travel.insert(std::string(1, static_cast<char>(std::tolower(axis))), std::move(a));
    }
    machine.insert("travel", std::move(travel));
    root.insert("machine", std::move(machine));
    toml::table gcode;
    for (const auto& [code, macro] : c.catalog.registrations()) gcode.insert(code, macro);
    toml::table macros;
    macros.insert("gcode", std::move(gcode));
    root.insert("macros", std::move(macros));
    toml::table rules;
    for (const auto& m : rule_ids) {
        auto sev = c.severity_of(m.id, m.severity, m.enabled_by_default);
        rules.insert(std::string(m.id), sev ? std::string(severity_name(*sev)) : std::string("off"));
    }
    root.insert("rules", std::move(rules));
    toml::table analysis;
    analysis.insert("explain-unknown", c.explain_unknown);
    root.insert("analysis", std::move(analysis));
    std::ostringstream out;
    out << "# effective configuration" << (c.path.empty() ? " (built-in defaults)" : " from " + c.path) << "\n";
    out << root << "\n";
    return out.str();
}

}  // namespace osplint
