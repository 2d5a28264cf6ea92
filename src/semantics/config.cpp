#include "semantics/config.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>

#include <toml++/toml.h>

#include "support/errors.h"
#include "support/glob.h"
#include "support/text.h"

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

// The rule severities of [rules] or of a [[per-path]] table's `rules`: a key
// is a rule's ID or name, or a prefix of IDs ("OSP1") for every rule it
// starts but OSP001; a rule's own key wins over a prefix, a longer prefix over
// a shorter.
void read_severities(std::map<std::string, std::optional<Severity>>& into, const std::string& origin,
                     const std::string& prefix, const toml::table& t, const RuleIdentities& rules) {
    struct Entry {
        std::vector<std::string> ids;
        size_t rank;  // the order they apply in: prefixes by length, then rules by ID or name
        std::optional<Severity> severity;
    };
    std::vector<Entry> entries;
    for (const auto& [k, v] : t) {
        const std::string written(k.str());
        const std::string key = prefix + written;
        Entry e;
        if (const RuleIdentity* rule = resolve_rule(rules, written)) {
            e.ids.push_back(std::string(rule->id));
            e.rank = SIZE_MAX;
        } else {
            // OSP001 (a program that does not parse) is turned off by its own key only.
            for (const auto& r : rules)
                if (written.size() >= 4 && upper(written) == written && r.id.substr(0, written.size()) == written &&
                    r.selected_by_prefix && !r.retired)
                    e.ids.push_back(std::string(r.id));
            e.rank = written.size();
        }
        if (e.ids.empty())
            fail(origin, v, key,
                 "unknown rule ID or name" + rule_suggestion(rules, written) + " (see `osplint rules`)");
        auto s = expect_string(origin, v, key);
        if (s == "off") {
            e.severity = std::nullopt;
        } else if (auto sev = parse_severity(s)) {
            e.severity = *sev;
        } else {
            fail(origin, v, key, "expected \"error\", \"warning\", \"info\" or \"off\", got \"" + s + "\"");
        }
        entries.push_back(std::move(e));
    }
    std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.rank < b.rank; });
    for (const auto& e : entries)
        for (const auto& id : e.ids) into[id] = e.severity;
}

void read_rules(Config& c, const std::string& origin, const toml::table& r, const RuleIdentities& rules) {
    read_severities(c.rule_severity, origin, "rules.", r, rules);
}

std::filesystem::path base_of(const std::string& origin) {
    std::filesystem::path base = std::filesystem::path(origin).parent_path();
    return base.empty() ? std::filesystem::path(".") : base;
}

// A list of glob patterns: `exclude`, a [[per-path]] table's `paths`.
std::vector<PathPattern> read_patterns(const std::string& origin, const toml::node& n, const std::string& key) {
    const auto* arr = n.as_array();
    if (!arr) fail(origin, n, key, "expected an array of glob patterns such as [\"old/**\", \"*.BAK.MIN\"]");
    std::vector<PathPattern> out;
    for (const auto& e : *arr) {
        auto pattern = expect_string(origin, e, key);
        std::string_view why;
        if (!glob_valid(pattern, &why)) fail(origin, e, key, "bad glob pattern \"" + pattern + "\": " + std::string(why));
        while (pattern.size() > 2 && pattern.compare(0, 2, "./") == 0) pattern.erase(0, 2);
        out.push_back({pattern, base_of(origin), origin});
    }
    return out;
}

void read_per_path(Config& c, const std::string& origin, const toml::node& n, const RuleIdentities& rules) {
    const auto* arr = n.as_array();
    if (!arr || !arr->is_array_of_tables())
        fail(origin, n, "per-path", "expected [[per-path]] tables (each with `paths` and `rules`)");
    for (const auto& e : *arr) {
        const auto& t = *e.as_table();
        check_keys(origin, t, "per-path.", {"paths", "rules"});
        PerPathRules p;
        p.origin = origin;
        p.line = line_of(e);
        const auto* paths = t.get("paths");
        if (!paths) fail(origin, e, "per-path.paths", "missing: the glob patterns of the files the table applies to");
        p.paths = read_patterns(origin, *paths, "per-path.paths");
        if (p.paths.empty()) fail(origin, *paths, "per-path.paths", "an empty list applies to no file");
        if (const auto* r = t.get("rules"))
            read_severities(p.rule_severity, origin, "per-path.rules.", expect_table(origin, *r, "per-path.rules"),
                            rules);
        c.per_path.push_back(std::move(p));
    }
}

std::string read_text_file(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ConfigError(file.string(), 0, "", "cannot read the configuration file");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw ConfigError(file.string(), 0, "", "cannot read the configuration file");
    return ss.str();
}

std::string identity_of(const std::filesystem::path& file) {
    std::error_code ec;
    auto p = std::filesystem::weakly_canonical(std::filesystem::absolute(file, ec), ec);
    return (ec ? std::filesystem::absolute(file) : p).lexically_normal().string();
}

// Reads one file of an `extend` chain onto the configuration of the files it
// extends. `chain`: the files being read, outermost first (for cycles).
Config read_chain(std::string_view text, const std::string& origin, const RuleIdentities& rules,
                  std::vector<std::pair<std::string, std::string>>& chain) {
    toml::table root;
    try {
        root = toml::parse(text, origin);
    } catch (const toml::parse_error& e) {
        throw ConfigError(origin, static_cast<uint32_t>(e.source().begin.line), "",
                          std::string(e.description()));
    }
    check_keys(origin, root, "",
               {"extend", "exclude", "per-path", "machine", "rules", "macros", "codes", "macro", "cycle", "analysis"});
    Config c;
    if (const auto* n = root.get("extend")) {
        const auto written = expect_string(origin, *n, "extend");
        if (written.empty()) fail(origin, *n, "extend", "expected the path of a configuration file");
        const std::filesystem::path target = (base_of(origin) / written).lexically_normal();
        const std::string id = identity_of(target);
        for (size_t i = 0; i < chain.size(); ++i)
            if (chain[i].first == id) {
                std::string loop;
                for (size_t k = i; k < chain.size(); ++k) loop += chain[k].second + " -> ";
                fail(origin, *n, "extend",
                     "extends " + target.string() + ", which is already being read: the files extend each other (" +
                         loop + target.string() + ")");
            }
        std::error_code ec;
        const auto st = std::filesystem::status(target, ec);
        if (!std::filesystem::exists(st))
            fail(origin, *n, "extend", "the file it extends, " + target.string() + ", does not exist");
        if (std::filesystem::is_directory(st))
            fail(origin, *n, "extend", "the file it extends, " + target.string() + ", is a directory");
        chain.emplace_back(id, target.string());
        c = read_chain(read_text_file(target), target.string(), rules, chain);
        chain.pop_back();
        c.extends.insert(c.extends.begin(), c.path);
    }
    c.path = origin;
    if (const auto* n = root.get("exclude"))
        for (auto& p : read_patterns(origin, *n, "exclude")) c.exclude.push_back(std::move(p));
    if (const auto* n = root.get("machine")) read_machine(c, origin, expect_table(origin, *n, "machine"));
    if (const auto* n = root.get("macro")) c.catalog.merge(expect_table(origin, *n, "macro"), origin);
    if (const auto* n = root.get("cycle")) c.catalog.merge_cycles(expect_table(origin, *n, "cycle"), origin);
    if (const auto* n = root.get("macros"))
        fail(origin, *n, "macros",
             "[macros.gcode] is now [codes]: write each registration there, e.g. G113 = \"OLAPX\"");
    if (const auto* n = root.get("codes")) {
        for (const auto& [k, v] : expect_table(origin, *n, "codes")) {
            std::string code(k.str());
            std::string key = "codes." + code;
            bool ok = code.size() >= 2 && (code[0] == 'G' || code[0] == 'M');
            for (size_t i = 1; ok && i < code.size(); ++i) ok = std::isdigit(static_cast<unsigned char>(code[i]));
            if (!ok) fail(origin, v, key, "expected a G or M code such as G114 or M204");
            if (auto meaning = Catalog::builtin_meaning(code); !meaning.empty())
                fail(origin, v, key, code + " is " + std::string(meaning) + " of the control, not a macro code");
            auto macro = expect_string(origin, v, key);
            if (!macro.empty() && !c.catalog.find(macro))
                fail(origin, v, key, "macro \"" + macro + "\" is not in the catalog (define it under [macro." +
                                         macro + "])");
            c.catalog.register_code(code, macro);
        }
    }
    if (const auto* n = root.get("rules")) read_rules(c, origin, expect_table(origin, *n, "rules"), rules);
    if (const auto* n = root.get("per-path")) read_per_path(c, origin, *n, rules);
    if (const auto* n = root.get("analysis")) {
        const auto& t = expect_table(origin, *n, "analysis");
        check_keys(origin, t, "analysis.", {"explain-unknown", "may-findings"});
        if (const auto* e = t.get("explain-unknown")) {
            if (!e->is_boolean()) fail(origin, *e, "analysis.explain-unknown", "expected true or false");
            c.explain_unknown = *e->value<bool>();
        }
        if (const auto* e = t.get("may-findings")) {
            const auto v = e->value<std::string>();
            const auto sev = v ? parse_severity(*v) : std::nullopt;
            if (!v || (!sev && *v != "off"))
                fail(origin, *e, "analysis.may-findings", "expected \"error\", \"warning\", \"info\" or \"off\"");
            c.may_severity = sev;
        }
    }
    return c;
}

}  // namespace

std::optional<Severity> Config::severity_of(std::string_view id, Severity default_severity,
                                            bool enabled_by_default) const {
    if (auto it = rule_severity.find(std::string(id)); it != rule_severity.end()) return it->second;
    if (!enabled_by_default) return std::nullopt;
    return default_severity;
}

const RuleIdentity* resolve_rule(const RuleIdentities& rules, std::string_view key) {
    for (const auto& r : rules) {
        if (!iequals(r.id, key) && !iequals(r.name, key)) continue;
        if (!r.retired) return &r;
        if (r.replaced_by.empty()) return nullptr;
        return resolve_rule(rules, r.replaced_by);
    }
    return nullptr;
}

const RuleIdentity* retired_rule(const RuleIdentities& rules, std::string_view key) {
    for (const auto& r : rules)
        if (r.retired && (iequals(r.id, key) || iequals(r.name, key))) return &r;
    return nullptr;
}

std::string rule_suggestion(const RuleIdentities& rules, std::string_view key) {
    if (const RuleIdentity* r = retired_rule(rules, key); r && r->replaced_by.empty())
        return " (" + std::string(r->id) + " " + std::string(r->name) + " was removed)";
    std::vector<std::string_view> candidates;
    for (const auto& r : rules) {
        if (r.retired) continue;
        candidates.push_back(r.id);
        candidates.push_back(r.name);
    }
    const std::string near = closest_match(key, candidates);
    return near.empty() ? std::string() : " (did you mean '" + near + "'?)";
}

bool path_matches(const PathPattern& pattern, const std::filesystem::path& file) {
    std::error_code ec;
    const auto abs = std::filesystem::absolute(file, ec).lexically_normal();
    const auto base = std::filesystem::absolute(pattern.base, ec).lexically_normal();
    std::string rel = abs.lexically_relative(base).generic_string();
    const bool inside = !rel.empty() && rel != "." && rel.compare(0, 2, "..") != 0;
    if (pattern.pattern.find('/') == std::string::npos) {
        if (!inside) return glob_match(pattern.pattern, abs.filename().string());
        size_t start = 0;
        for (size_t i = 0; i <= rel.size(); ++i)
            if (i == rel.size() || rel[i] == '/') {
                if (glob_match(pattern.pattern, std::string_view(rel).substr(start, i - start))) return true;
                start = i + 1;
            }
        return false;
    }
    return inside && glob_match(pattern.pattern, rel);
}

bool Config::excluded(const std::filesystem::path& p) const {
    for (const auto& e : exclude)
        if (path_matches(e, p)) return true;
    return false;
}

std::vector<size_t> Config::per_path_matching(const std::filesystem::path& file) const {
    std::vector<size_t> out;
    for (size_t i = 0; i < per_path.size(); ++i)
        for (const auto& p : per_path[i].paths)
            if (path_matches(p, file)) {
                out.push_back(i);
                break;
            }
    return out;
}

void Config::apply_per_path(const std::vector<size_t>& tables) {
    for (size_t i : tables)
        for (const auto& [id, sev] : per_path.at(i).rule_severity) rule_severity[id] = sev;
}

Config read_config_text(std::string_view text, const std::string& origin, const RuleIdentities& rules) {
    std::vector<std::pair<std::string, std::string>> chain;
    chain.emplace_back(identity_of(origin), origin);
    Config c = read_chain(text, origin, rules, chain);
    // explain-unknown turns on the rules that say "cannot tell" unless [rules] says otherwise.
    if (c.explain_unknown)
        for (const auto& r : rules)
            if (r.analysis_switch == "explain-unknown" && !c.rule_severity.count(std::string(r.id)))
                c.rule_severity[std::string(r.id)] = r.severity;
    return c;
}

Config read_config_file(const std::filesystem::path& file, const RuleIdentities& rules) {
    std::error_code ec;
    const auto st = std::filesystem::status(file, ec);
    if (!std::filesystem::exists(st)) throw ConfigError(file.string(), 0, "", "no such configuration file");
    if (std::filesystem::is_directory(st))
        throw ConfigError(file.string(), 0, "", "is a directory, not a configuration file (osplint.toml)");
    return read_config_text(read_text_file(file), file.string(), rules);
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
    toml::table codes;
    for (const auto& [code, macro] : c.catalog.registrations()) codes.insert(code, macro);
    root.insert("codes", std::move(codes));
    toml::table rules;
    for (const auto& m : rule_ids) {
        auto sev = c.severity_of(m.id, m.severity, m.enabled_by_default);
        rules.insert(std::string(m.id), sev ? std::string(severity_name(*sev)) : std::string("off"));
    }
    root.insert("rules", std::move(rules));
    toml::table analysis;
    analysis.insert("explain-unknown", c.explain_unknown);
    analysis.insert("may-findings", c.may_severity ? std::string(severity_name(*c.may_severity)) : std::string("off"));
    root.insert("analysis", std::move(analysis));
    auto quoted = [](const std::string& s) {
        std::ostringstream q;
        q << toml::value<std::string>(s);
        return q.str();
    };
    std::ostringstream out;
    out << "# effective configuration" << (c.path.empty() ? " (built-in defaults)" : " from " + c.path) << "\n";
    for (const auto& e : c.extends) out << "# extends " << e << "\n";
    // Patterns are relative to the directory of the file that names them, shown after each.
    out << "exclude = [";
    for (const auto& e : c.exclude) out << "\n    " << quoted(e.pattern) << ",  # " << e.origin;
    out << (c.exclude.empty() ? "]\n\n" : "\n]\n\n");
    out << root << "\n";
    for (const auto& p : c.per_path) {
        out << "\n[[per-path]]  # " << p.origin << ":" << p.line << "\n";
        out << "paths = [";
        for (size_t i = 0; i < p.paths.size(); ++i) out << (i ? ", " : "") << quoted(p.paths[i].pattern);
        out << "]\nrules = {";
        size_t i = 0;
        for (const auto& [id, sev] : p.rule_severity)
            out << (i++ ? ", " : " ") << id << " = " << quoted(sev ? std::string(severity_name(*sev)) : "off");
        out << (p.rule_severity.empty() ? "}\n" : " }\n");
    }
    return out.str();
}

}  // namespace osplint
