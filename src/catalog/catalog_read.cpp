// Reading catalog tables into specs (see catalog.h and docs/catalog.md for
// the schema): the shipped catalog file and the [macro] tables of a
// configuration, with errors that name the file, line and key; the checks
// across a macro's fields; merging shop macros into the catalog.
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <utility>

#include "catalog/catalog.h"
#include "catalog/catalog_internal.h"
#include "support/errors.h"

namespace osplint {

using namespace catalog_detail;

namespace {

// ---------------------------------------------------------------------------
// Reading TOML tables with line-accurate errors

std::string_view type_name(const toml::node& n) {
    switch (n.type()) {
        case toml::node_type::table: return "a table";
        case toml::node_type::array: return "an array";
        case toml::node_type::string: return "a string";
        case toml::node_type::integer: return "an integer";
        case toml::node_type::floating_point: return "a number";
        case toml::node_type::boolean: return "a boolean";
        default: return "a date/time";
    }
}

class Reader {
public:
    Reader(const toml::table& table, const std::string& file, std::string path)
        : table_(table), file_(file), path_(std::move(path)) {}

    const std::string& file() const { return file_; }
    const std::string& path() const { return path_; }
    std::string key_path(std::string_view key) const {
        return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
    }

    [[noreturn]] void fail(const toml::node* at, std::string_view key, const std::string& msg) const {
        uint32_t line = at ? at->source().begin.line : table_.source().begin.line;
        throw ConfigError(file_, line, key_path(key), msg);
    }

    bool has(std::string_view key) const { return table_.contains(key); }

    // inf and nan are TOML floats, and never a value a macro takes.
    double finite(const toml::node* at, std::string_view key, double v) const {
        if (!std::isfinite(v)) fail(at, key, "expected a finite number, found " + format_number(v));
        return v;
    }

    const toml::node* get(std::string_view key) {
        seen_.insert(std::string(key));
        return table_.get(key);
    }

    std::optional<std::string> str(std::string_view key) {
        const toml::node* n = get(key);
        if (!n) return std::nullopt;
        if (!n->is_string()) fail(n, key, "expected a string, found " + std::string(type_name(*n)));
        return n->as_string()->get();
    }
    std::optional<bool> boolean(std::string_view key) {
        const toml::node* n = get(key);
        if (!n) return std::nullopt;
        if (!n->is_boolean()) fail(n, key, "expected true or false, found " + std::string(type_name(*n)));
        return n->as_boolean()->get();
    }
    std::optional<double> number(std::string_view key) {
        const toml::node* n = get(key);
        if (!n) return std::nullopt;
        if (n->is_integer()) return static_cast<double>(n->as_integer()->get());
        if (n->is_floating_point()) return finite(n, key, n->as_floating_point()->get());
        fail(n, key, "expected a number, found " + std::string(type_name(*n)));
    }
    const toml::table* table(std::string_view key) {
        const toml::node* n = get(key);
        if (!n) return nullptr;
        if (!n->is_table()) fail(n, key, "expected a table, found " + std::string(type_name(*n)));
        return n->as_table();
    }
    const toml::array* array(std::string_view key) {
        const toml::node* n = get(key);
        if (!n) return nullptr;
        if (!n->is_array()) fail(n, key, "expected an array, found " + std::string(type_name(*n)));
        return n->as_array();
    }
    std::optional<std::vector<std::string>> strings(std::string_view key) {
        const toml::array* a = array(key);
        if (!a) return std::nullopt;
        std::vector<std::string> out;
        for (const auto& e : *a) {
            if (!e.is_string())
                fail(&e, key, "expected an array of strings, found " + std::string(type_name(e)));
            out.push_back(e.as_string()->get());
        }
        return out;
    }
    std::optional<std::vector<double>> numbers(std::string_view key) {
        const toml::array* a = array(key);
        if (!a) return std::nullopt;
        std::vector<double> out;
        for (const auto& e : *a) {
            if (e.is_integer())
                out.push_back(static_cast<double>(e.as_integer()->get()));
            else if (e.is_floating_point())
                out.push_back(finite(&e, key, e.as_floating_point()->get()));
            else
                fail(&e, key, "expected an array of numbers, found " + std::string(type_name(e)));
        }
        return out;
    }
    template <class E, std::size_t N>
    E enum_value(const toml::node* n, std::string_view key, const EnumName<E> (&table)[N]) const {
        if (!n->is_string()) fail(n, key, "expected a string, found " + std::string(type_name(*n)));
        const std::string& s = n->as_string()->get();
        for (const auto& e : table)
            if (e.name == s) return e.value;
        fail(n, key, "unknown value \"" + s + "\"; expected one of " + choices(table));
    }
    template <class E, std::size_t N>
    std::optional<E> enumeration(std::string_view key, const EnumName<E> (&table)[N]) {
        const toml::node* n = get(key);
        if (!n) return std::nullopt;
        return enum_value(n, key, table);
    }
    // Each element of an array of tables, as a Reader.
    void each_table(std::string_view key, const std::function<void(Reader&)>& fn) {
        const toml::array* a = array(key);
        if (!a) return;
        std::size_t i = 0;
        for (const auto& e : *a) {
            std::string elem_path = key_path(key) + "[" + std::to_string(i++) + "]";
            if (!e.is_table())
                throw ConfigError(file_, e.source().begin.line, elem_path,
                                  "expected a table, found " + std::string(type_name(e)));
            Reader r(*e.as_table(), file_, elem_path);
            fn(r);
            r.done();
        }
    }

    // Every key must have been read: anything else is a typo or an unknown field.
    void done() const {
        for (auto&& [k, v] : table_) {
            if (seen_.count(std::string(k.str()))) continue;
            uint32_t line = k.source().begin.line ? k.source().begin.line : v.source().begin.line;
            throw ConfigError(file_, line, key_path(k.str()), "unknown key");
        }
    }

private:
    const toml::table& table_;
    const std::string& file_;
    std::string path_;
    std::set<std::string> seen_;
};

uint32_t line_of(const toml::node& n) { return n.source().begin.line; }

// Children of a table in the order they were written (toml++ keeps keys sorted).
std::vector<std::pair<std::string, const toml::node*>> in_source_order(const toml::table& t) {
    std::vector<std::pair<std::string, const toml::node*>> out;
    for (auto&& [k, v] : t) out.emplace_back(std::string(k.str()), &v);
    std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
        return line_of(*a.second) < line_of(*b.second);
    });
    return out;
}

// ---------------------------------------------------------------------------
// Building specs from tables

std::vector<CatalogNote> read_notes(Reader& r) {
    std::vector<CatalogNote> out;
    r.each_table("notes", [&](Reader& e) {
        CatalogNote note;
        if (auto v = e.str("text")) note.text = *v;
        else e.fail(nullptr, "text", "a note needs 'text'");
        if (auto v = e.str("source")) note.source = *v;
        out.push_back(std::move(note));
    });
    return out;
}

std::vector<Reading> read_readings(Reader& r) {
    std::vector<Reading> out;
    r.each_table("readings", [&](Reader& e) {
        Reading rd;
        if (auto v = e.str("id")) rd.id = *v;
        else e.fail(nullptr, "id", "a reading needs 'id'");
        if (auto v = e.str("issue")) rd.issue = *v;
        if (auto v = e.str("reading")) rd.reading = *v;
        else e.fail(nullptr, "reading", "a reading needs 'reading'");
        if (auto v = e.boolean("open")) rd.open = *v;
        if (auto v = e.str("override")) rd.override_hint = *v;
        out.push_back(std::move(rd));
    });
    return out;
}

void read_axes(Reader& r, ArgSpec& arg) {
    const toml::node* n = r.get("axis");
    if (!n) return;
    if (n->is_string()) {
        const std::string& s = n->as_string()->get();
        // Shorthands: the plane's cycle axis, first or second positioning-plane axis.
        if (s == "cycle") arg.axes = {'Z', 'Y', 'X'};
        else if (s == "first") arg.axes = {'X', 'Z', 'Y'};
        else if (s == "second") arg.axes = {'Y', 'X', 'Z'};
        else if (s == "none") arg.axes = {'\0', '\0', '\0'};
        else r.fail(n, "axis", "unknown value \"" + s + "\"; expected \"cycle\", \"first\", \"second\", \"none\" or an array of three axes");
        return;
    }
    if (!n->is_array() || n->as_array()->size() != 3)
        r.fail(n, "axis", "expected an array of three axes (G17, G18, G19) or a shorthand string");
    const toml::array& a = *n->as_array();
    for (std::size_t i = 0; i < 3; ++i) {
        const toml::node& e = a[i];
        std::string s = e.is_string() ? upper(e.as_string()->get()) : std::string("?");
        if (s.empty()) arg.axes[i] = '\0';
        else if (s == "X" || s == "Y" || s == "Z") arg.axes[i] = s[0];
        else r.fail(&e, "axis", "an axis is \"X\", \"Y\", \"Z\" or \"\" (none)");
    }
}

void read_in_format(Reader& r, ArgSpec& arg) {
    const toml::node* n = r.get("in_format");
    if (!n) return;
    if (n->is_string()) {
        arg.in_format.fill(r.enum_value(n, "in_format", kInFormat));
        return;
    }
    if (!n->is_table())
        r.fail(n, "in_format", "expected a string or a table of call forms, found " + std::string(type_name(*n)));
    arg.in_format.fill(ArgInFormat::Absent);
    Reader per_form(*n->as_table(), r.file(), r.key_path("in_format"));
    for (const auto& f : kForm)
        if (auto v = per_form.enumeration(f.name, kInFormat)) arg.in_format[static_cast<std::size_t>(f.value)] = *v;
    per_form.done();
}

void read_default(Reader& r, ArgSpec& arg) {
    if (const toml::node* n = r.get("default")) {
        if (n->is_integer() || n->is_floating_point()) {
            double v = n->is_integer() ? static_cast<double>(n->as_integer()->get())
                                       : r.finite(n, "default", n->as_floating_point()->get());
            arg.default_value = v;
            arg.default_text = format_number(v);
        } else if (n->is_string()) {
            arg.default_text = n->as_string()->get();
            arg.default_value = parse_number(arg.default_text);
        } else {
            r.fail(n, "default", "expected a string or a number, found " + std::string(type_name(*n)));
        }
    }
    if (auto v = r.number("default_value")) arg.default_value = *v;
}

// Applies the fields of an argument table to `arg` (a new one or a patch).
void apply_arg(Reader& r, ArgSpec& arg, bool is_new) {
    if (is_new && !r.has("omitted"))
        r.fail(nullptr, "omitted", "a new argument needs 'omitted' (one of " + choices(kOmitted) + ")");
    if (is_new && !r.has("role"))
        r.fail(nullptr, "role", "a new argument needs 'role' (one of " + choices(kRole) + ")");
    if (auto v = r.strings("aliases")) {
        arg.aliases.clear();
        for (auto& a : *v) arg.aliases.push_back(upper(a));
    }
    if (auto v = r.str("meaning")) arg.meaning = *v;
    if (auto v = r.enumeration("omitted", kOmitted)) arg.omitted = *v;
    read_default(r, arg);
    if (auto v = r.enumeration("sign", kSign)) arg.sign = *v;
    if (auto v = r.numbers("allowed")) arg.allowed = *v;
    if (auto v = r.boolean("negative_allowed")) arg.negative_allowed = *v;
    if (auto v = r.enumeration("role", kRole)) arg.role = *v;
    read_axes(r, arg);
    read_in_format(r, arg);
    if (auto v = r.boolean("undocumented")) arg.undocumented = *v;
    if (auto v = r.boolean("always_incremental")) arg.always_incremental = *v;
    if (auto v = r.boolean("g91_only")) arg.g91_only = *v;
    if (auto v = r.str("source")) arg.source = *v;
    if (auto v = r.str("note")) arg.note = *v;
    r.done();
}

int read_plane(Reader& r) {
    const toml::node* n = r.get("plane");
    if (!n) return 0;
    if (n->is_string()) {
        std::string s = upper(n->as_string()->get());
        if (s == "G17") return 17;
        if (s == "G18") return 18;
        if (s == "G19") return 19;
    }
    r.fail(n, "plane", "expected \"G17\", \"G18\" or \"G19\"");
}

// The keys of catalog schema 1 that became properties of the macro: a
// configuration written for it stops with the key to write instead.
void reject_schema1_keys(Reader& r) {
    static const std::pair<const char*, const char*> renamed[] = {
        {"mm_only", "units = \"mm\" (or \"any\")"},
        {"cycle_args_absolute_g91", "g91 = \"cycle-axis-absolute\" (or \"follows-g91\")"},
        {"g91_forbidden", "g91 = \"unsupported\""},
        {"g60_ncyl_forbidden", "\"g60-ncyl-collision\" in hazards = [...]"},
        {"vc120_128_clobbered", "\"overwrites-vc120-vc128\" in hazards = [...]"},
        {"q_repeat_unsafe", "\"repeat-count-abnormal\" in hazards = [...]"},
    };
    for (const auto& [old_key, now] : renamed)
        if (const toml::node* n = r.get(old_key))
            r.fail(n, old_key, std::string("this key of catalog schema 1 is now written ") + now +
                                   " (see docs/catalog.md)");
}

// A `when` condition, parsed now so that a mistake names its line.
Condition read_condition(Reader& r) {
    const toml::node* n = r.get("when");
    if (!n) return {};
    if (!n->is_string()) r.fail(n, "when", "expected a string, found " + std::string(type_name(*n)));
    std::string error;
    auto c = Condition::parse(n->as_string()->get(), error);
    if (!c) r.fail(n, "when", error);
    return std::move(*c);
}

// The scalar fields of a macro table: names, call forms, mode behaviour.
void apply_spec_fields(Reader& r, MacroSpec& spec) {
    if (auto v = r.str("family")) spec.family = *v;
    if (auto v = r.str("title")) spec.title = *v;
    if (auto v = r.str("manual")) spec.manual = *v;
    if (auto v = r.str("source")) spec.source = *v;
    if (const toml::array* a = r.array("forms")) {
        spec.forms.clear();
        for (const auto& e : *a) spec.forms.push_back(r.enum_value(&e, "forms", kForm));
    }
    if (auto v = r.boolean("args_documented")) spec.args_documented = *v;
    reject_schema1_keys(r);
    if (auto v = r.enumeration("units", kUnits)) spec.units = *v;
    if (auto v = r.enumeration("g91", kG91)) spec.g91 = *v;
    if (auto v = r.enumeration("m52", kM52)) spec.m52 = *v;
    if (auto v = r.enumeration("m53", kM53)) spec.m53 = *v;
    if (const toml::array* a = r.array("hazards")) {
        spec.hazards = {};
        for (const auto& e : *a) {
            bool& h = spec.hazards[static_cast<std::size_t>(r.enum_value(&e, "hazards", kHazard))];
            if (h) r.fail(&e, "hazards", "\"" + e.as_string()->get() + "\" is listed twice");
            h = true;
        }
    }
    if (auto v = r.boolean("tapping")) spec.tapping = *v;
    if (auto v = r.enumeration("required_scope", kScope)) spec.required_scope = *v;
}

// `format`: the printed command-format lines.
void read_formats(Reader& r, MacroSpec& spec) {
    spec.formats.clear();
    r.each_table("format", [&](Reader& f) {
        FormatLine line;
        if (auto v = f.enumeration("form", kForm)) line.form = *v;
        else f.fail(nullptr, "form", "a format line needs 'form'");
        if (auto v = f.str("text")) line.text = *v;
        else f.fail(nullptr, "text", "a format line needs 'text'");
        if (auto v = f.str("source")) line.source = *v;
        spec.formats.push_back(std::move(line));
    });
}

// `gcode`: the G-code macro form and the arguments its addresses stand for.
GCodeForm read_gcode_form(Reader& r, const toml::table& g) {
    Reader gr(g, r.file(), r.key_path("gcode"));
    GCodeForm form;
    if (auto v = gr.str("text")) form.text = *v;
    else gr.fail(nullptr, "text", "the G-code form needs 'text'");
    if (auto v = gr.str("source")) form.source = *v;
    if (auto v = gr.str("note")) form.note = *v;
    if (const toml::table* m = gr.table("map")) {
        Reader mr(*m, r.file(), gr.key_path("map"));
        for (auto&& [k, v] : *m) {
            auto target = mr.str(k.str());
            form.address_map[upper(k.str())] = upper(*target);
        }
        mr.done();
    }
    gr.done();
    return form;
}

// `codes`: the G/M codes the macro is registered to by default.
void read_codes(Reader& r, MacroSpec& spec) {
    auto v = r.strings("codes");
    if (!v) return;
    spec.codes.clear();
    const toml::node* n = r.get("codes");
    for (const auto& c : *v) {
        std::string code = normalize_code(c);
        if (code.empty()) r.fail(n, "codes", "\"" + c.substr(0, 40) + (c.size() > 40 ? "..." : "") + "\" is not a G or M code");
        if (auto meaning = Catalog::builtin_meaning(code); !meaning.empty())
            r.fail(n, "codes", code + " is " + std::string(meaning) + " of the control, not a macro code");
        spec.codes.push_back(code);
    }
}

// `arg.NAME` tables: each patches the argument of that name or adds one.
void apply_args(Reader& r, const toml::table& args, MacroSpec& spec) {
    Reader ar(args, r.file(), r.key_path("arg"));
    for (const auto& [name, node] : in_source_order(args)) {
        const toml::table* t = ar.table(name);
        std::string uname = upper(name);
        if (!is_name(uname)) ar.fail(node, name, "an argument name is letters and digits");
        auto it = std::find_if(spec.args.begin(), spec.args.end(),
                               [&](const ArgSpec& a) { return a.name == uname; });
        bool is_new = it == spec.args.end();
        ArgSpec fresh;
        fresh.name = uname;
        ArgSpec& arg = is_new ? fresh : *it;
        Reader one(*t, r.file(), ar.key_path(name));
        apply_arg(one, arg, is_new);
        if (is_new) spec.args.push_back(std::move(fresh));
    }
    ar.done();
}

// `at_least_one`: sets of arguments of which one must be given.
void read_at_least_one(Reader& r, MacroSpec& spec) {
    spec.at_least_one.clear();
    r.each_table("at_least_one", [&](Reader& e) {
        AtLeastOne rule;
        rule.plane = read_plane(e);
        if (auto v = e.strings("args")) for (auto& a : *v) rule.args.push_back(upper(a));
        if (rule.args.size() < 2) e.fail(nullptr, "args", "'at_least_one' needs two or more argument names");
        if (auto v = e.str("source")) rule.source = *v;
        if (auto v = e.boolean("inferred")) rule.inferred = *v;
        spec.at_least_one.push_back(std::move(rule));
    });
}

// `cautions`: situations the manual warns about at the call.
void read_cautions(Reader& r, MacroSpec& spec) {
    spec.cautions.clear();
    r.each_table("cautions", [&](Reader& e) {
        Caution c;
        if (auto v = e.str("id")) c.id = *v;
        else e.fail(nullptr, "id", "a caution needs 'id'");
        c.when = read_condition(e);
        if (c.when.empty()) e.fail(nullptr, "when", "a caution needs 'when': the situation it warns about");
        if (auto v = e.str("text")) c.text = *v;
        else e.fail(nullptr, "text", "a caution needs 'text'");
        if (auto v = e.str("source")) c.source = *v;
        if (auto v = e.str("severity")) {
            if (*v == "info") c.info = true;
            else if (*v != "warning") e.fail(e.get("severity"), "severity", "expected \"warning\" or \"info\"");
        }
        spec.cautions.push_back(std::move(c));
    });
}

// `relations`: `left op right` between argument values.
void read_relations(Reader& r, MacroSpec& spec) {
    spec.relations.clear();
    r.each_table("relations", [&](Reader& e) {
        Relation rel;
        if (auto v = e.str("left")) rel.left = upper(*v);
        else e.fail(nullptr, "left", "a relation needs 'left'");
        if (auto v = e.str("op")) rel.op = *v;
        else e.fail(nullptr, "op", "a relation needs 'op'");
        if (auto v = e.str("right")) rel.right = upper(*v);
        else e.fail(nullptr, "right", "a relation needs 'right'");
        static const std::set<std::string> ops{">", ">=", "<", "<=", "==", "!="};
        if (!ops.count(rel.op)) e.fail(e.get("op"), "op", "expected one of > >= < <= == !=");
        rel.plane = read_plane(e);
        rel.when = read_condition(e);
        if (auto v = e.str("source")) rel.source = *v;
        if (auto v = e.boolean("inferred")) rel.inferred = *v;
        if (auto v = e.str("note")) rel.note = *v;
        spec.relations.push_back(std::move(rel));
    });
}

// `action`: the manual's action sequence.
void read_action(Reader& r, MacroSpec& spec) {
    spec.action.clear();
    r.each_table("action", [&](Reader& e) {
        ActionStep step;
        if (auto v = e.str("step")) step.step = *v;
        else e.fail(nullptr, "step", "an action step needs 'step'");
        if (auto v = e.str("text")) step.text = *v;
        if (auto v = e.str("feed")) step.feed = *v;
        if (auto v = e.str("target")) step.target = upper(*v);
        if (auto v = e.str("by")) step.by = upper(*v);
        step.when = read_condition(e);
        if (auto v = e.boolean("inferred")) step.inferred = *v;
        if (auto v = e.str("source")) step.source = *v;
        spec.action.push_back(std::move(step));
    });
}

// Applies a macro (or fixed-cycle) table to `spec`: on a new spec every field
// given is set; on an existing one the fields given replace the old ones and
// `arg.NAME` tables patch or add arguments. The fields are read in a fixed
// order, so that the first bad one is the one reported.
void apply_spec(Reader& r, MacroSpec& spec) {
    apply_spec_fields(r, spec);
    if (r.has("format")) read_formats(r, spec);
    if (const toml::table* g = r.table("gcode")) spec.gcode_form = read_gcode_form(r, *g);
    read_codes(r, spec);
    if (auto v = r.str("cancel")) spec.cancel = upper(*v);
    if (auto v = r.str("cancels")) spec.cancels = upper(*v);
    if (auto v = r.str("plane_table")) spec.plane_table = *v;
    if (auto v = r.str("common")) spec.common = *v;
    if (const toml::table* args = r.table("arg")) apply_args(r, *args, spec);
    if (r.has("at_least_one")) read_at_least_one(r, spec);
    if (r.has("relations")) read_relations(r, spec);
    if (r.has("action")) read_action(r, spec);
    if (r.has("notes")) spec.notes = read_notes(r);
    if (r.has("cautions")) read_cautions(r, spec);
    if (r.has("readings")) spec.readings = read_readings(r);
}

// Checks that cannot be made field by field: names referenced by the macro's
// own lists and expressions must be its arguments.
void validate_spec(const MacroSpec& spec, const std::string& file, uint32_t line, const std::string& path) {
    auto fail = [&](const std::string& key, const std::string& msg) {
        throw ConfigError(file, line, path + "." + key, msg);
    };
    if (spec.forms.empty() && spec.kind == SpecKind::Macro) fail("forms", "a macro needs at least one call form");
    std::set<std::string> names;
    for (const auto& a : spec.args) {
        if (!names.insert(a.name).second) fail("arg." + a.name, "duplicate argument");
        for (const auto& al : a.aliases)
            if (!names.insert(al).second) fail("arg." + a.name + ".aliases", "alias " + al + " is already a name");
        if (a.omitted == ArgOmitted::Default && a.default_text.empty())
            fail("arg." + a.name + ".default", "omitted = \"default\" needs the printed 'default'");
    }
    auto known = [&](const std::string& n) { return spec.arg(n) != nullptr; };
    auto check_expr = [&](const std::string& key, const std::string& text) {
        if (text.empty()) return;
        auto terms = parse_catalog_expr(text);
        if (!terms) fail(key, "\"" + text + "\" is not an expression of argument names, numbers, + and -");
        for (const auto& t : *terms)
            if (!t.name.empty() && !known(t.name)) fail(key, "\"" + t.name + "\" is not an argument of " + spec.name);
    };
    for (std::size_t i = 0; i < spec.action.size(); ++i) {
        check_expr("action[" + std::to_string(i) + "].target", spec.action[i].target);
        check_expr("action[" + std::to_string(i) + "].by", spec.action[i].by);
    }
    for (std::size_t i = 0; i < spec.relations.size(); ++i) {
        check_expr("relations[" + std::to_string(i) + "].left", spec.relations[i].left);
        check_expr("relations[" + std::to_string(i) + "].right", spec.relations[i].right);
    }
    auto check_condition = [&](const std::string& key, const Condition& c) {
        for (const ConditionAtom* a : c.atoms())
            if (!a->arg.empty() && !known(a->arg)) fail(key, "\"" + a->arg + "\" is not an argument of " + spec.name);
    };
    for (std::size_t i = 0; i < spec.action.size(); ++i)
        check_condition("action[" + std::to_string(i) + "].when", spec.action[i].when);
    for (std::size_t i = 0; i < spec.relations.size(); ++i)
        check_condition("relations[" + std::to_string(i) + "].when", spec.relations[i].when);
    for (std::size_t i = 0; i < spec.cautions.size(); ++i)
        check_condition("cautions[" + std::to_string(i) + "].when", spec.cautions[i].when);
    for (std::size_t i = 0; i < spec.at_least_one.size(); ++i)
        for (const auto& a : spec.at_least_one[i].args)
            if (!known(a)) fail("at_least_one[" + std::to_string(i) + "].args", a + " is not an argument of " + spec.name);
    if (spec.gcode_form)
        for (const auto& [addr, target] : spec.gcode_form->address_map)
            if (!known(target)) fail("gcode.map." + addr, target + " is not an argument of " + spec.name);
}

void read_plane_tables(const toml::table& t, const std::string& file, std::vector<PlaneTable>& out) {
    Reader r(t, file, "plane_table");
    for (const auto& [id, node] : in_source_order(t)) {
        const toml::table* pt = r.table(id);
        Reader pr(*pt, file, r.key_path(id));
        PlaneTable table;
        table.id = id;
        if (auto v = pr.str("source")) table.source = *v;
        if (auto v = pr.strings("columns")) table.columns = *v;
        static const char* kRows[] = {"G17", "G18", "G19"};
        for (int i = 0; i < 3; ++i) {
            if (auto v = pr.strings(kRows[i])) {
                if (!table.columns.empty() && v->size() != table.columns.size())
                    pr.fail(pr.get(kRows[i]), kRows[i], "a row needs one cell per column");
                table.rows[i] = *v;
            }
        }
        if (auto v = pr.str("reading")) table.reading = *v;
        pr.done();
        out.push_back(std::move(table));
    }
    r.done();
}

void read_common(const toml::table& t, const std::string& file, std::vector<CommonRules>& out) {
    Reader r(t, file, "common");
    for (const auto& [id, node] : in_source_order(t)) {
        const toml::table* ct = r.table(id);
        Reader cr(*ct, file, r.key_path(id));
        CommonRules rules;
        rules.id = id;
        if (auto v = cr.str("title")) rules.title = *v;
        if (auto v = cr.str("source")) rules.source = *v;
        rules.notes = read_notes(cr);
        rules.readings = read_readings(cr);
        cr.done();
        out.push_back(std::move(rules));
    }
    r.done();
}

// ---------------------------------------------------------------------------
// Merging a [macro] table

// A macro of a [macro] table, read and validated but not applied yet.
// The last element of `list` that `pick` picks (nullptr: none).
template <class List, class Pick>
auto* find_spec(List& list, Pick&& pick) {
    decltype(&*list.begin()) found = nullptr;
    for (auto& e : list)
        if (pick(e)) found = &e;
    return found;
}

struct StagedMacro {
    MacroSpec spec;
    MacroSpec* existing;  // nullptr: a new macro
    uint32_t line;
    bool codes_given;
};

// Reads every macro of the table into a StagedMacro: a patch of an existing
// macro of `macros`, a replacement (`replace = true`) or a new macro.
std::vector<StagedMacro> stage_macros(const toml::table& macros_table, const std::string& origin,
                                      std::deque<MacroSpec>& macros) {
    std::vector<StagedMacro> staged;
    Reader r(macros_table, origin, "macro");
    for (const auto& [key, node] : in_source_order(macros_table)) {
        const toml::table* t = r.table(key);
        std::string name = upper(key);
        if (!is_name(name) || name[0] != 'O')
            r.fail(node, key, "a macro is named by its program name, e.g. OZAGR");
        if (find_spec(staged, [&](const StagedMacro& s) { return s.spec.name == name; }))
            r.fail(node, key, "the macro is defined twice");
        MacroSpec* existing = find_spec(macros, [&](const MacroSpec& m) { return m.name == name; });
        Reader one(*t, origin, r.key_path(key));
        bool replace = one.boolean("replace").value_or(false);
        StagedMacro st{MacroSpec{}, existing, line_of(*node), t->contains("codes")};
        if (existing) {
            // A patch starts from the current definition; a replacement from
            // scratch, keeping the registrations unless it names its own.
            if (!replace) st.spec = *existing;
            else st.spec.codes = existing->codes;
        }
        st.spec.kind = SpecKind::Macro;
        st.spec.name = name;
        apply_spec(one, st.spec);
        one.done();
        st.spec.origin = origin;
        st.spec.index_args();
        validate_spec(st.spec, origin, st.line, r.key_path(key));
        staged.push_back(std::move(st));
    }
    r.done();
    return staged;
}

// Cross-references: cancel / cancels must name a macro known after the
// merge, and one merge must not give a code to two macros.
void check_cross_references(const std::vector<StagedMacro>& staged, const Catalog& catalog,
                            const std::string& origin) {
    auto known_after = [&](const std::string& n) {
        if (catalog.find(n)) return true;
        for (const auto& s : staged)
            if (s.spec.name == n) return true;
        return false;
    };
    std::map<std::string, std::string> claimed;
    for (const auto& s : staged) {
        std::string path = "macro." + s.spec.name;
        if (!s.spec.cancel.empty() && !known_after(s.spec.cancel))
            throw ConfigError(origin, s.line, path + ".cancel", "no macro " + s.spec.cancel);
        if (!s.spec.cancels.empty() && !known_after(s.spec.cancels))
            throw ConfigError(origin, s.line, path + ".cancels", "no macro " + s.spec.cancels);
        if (s.existing && !s.codes_given) continue;
        for (const auto& c : s.spec.codes) {
            auto [it, fresh] = claimed.emplace(c, s.spec.name);
            if (!fresh && it->second != s.spec.name)
                throw ConfigError(origin, s.line, path + ".codes", c + " is also registered to " + it->second);
        }
    }
}

}  // namespace

// ---------------------------------------------------------------------------
// Catalog

Catalog Catalog::from_toml_text(std::string_view text, std::string origin) {
    toml::table root;
    try {
        root = toml::parse(text, std::string_view(origin));
    } catch (const toml::parse_error& e) {
        throw ConfigError(origin, e.source().begin.line, "", std::string(e.description()));
    }
    Catalog cat;
    Reader r(root, origin, "");
    if (const toml::node* n = r.get("schema")) {
        if (!n->is_integer() || n->as_integer()->get() != 2)
            r.fail(n, "schema",
                   "this osplint reads catalog schema 2 (schema 1 wrote the macro's units, G91 mode and hazards "
                   "as separate booleans; see docs/catalog.md)");
    }
    if (const toml::table* pt = r.table("plane_table")) read_plane_tables(*pt, origin, cat.plane_tables_);
    if (const toml::table* ct = r.table("common")) read_common(*ct, origin, cat.common_);
    if (const toml::table* m = r.table("macro")) cat.merge(*m, origin);
    if (const toml::table* c = r.table("cycle")) {
        // Each cycle of the shipped catalog is new: one named twice is a mistake.
        Reader cr(*c, origin, "cycle");
        for (const auto& [key, node] : in_source_order(*c)) {
            const std::string norm = normalize_code(upper(key));
            if (!norm.empty() && norm[0] == 'G' && cat.find_cycle(std::stoi(norm.substr(1))))
                cr.fail(node, key, "duplicate fixed cycle");
        }
        cat.merge_cycles(*c, origin);
    }
    r.done();
    for (const auto* list : {&cat.macros_, &cat.cycles_}) {
        for (const auto& m : *list) {
            std::string path = (m.kind == SpecKind::Macro ? "macro." : "cycle.") + m.name;
            if (!m.plane_table.empty() && !cat.plane_table(m.plane_table))
                throw ConfigError(origin, 0, path + ".plane_table", "no plane_table \"" + m.plane_table + "\"");
            if (!m.common.empty() && !cat.common_rules(m.common))
                throw ConfigError(origin, 0, path + ".common", "no common rules \"" + m.common + "\"");
        }
    }
    return cat;
}

void Catalog::merge_cycles(const toml::table& cycles_table, const std::string& origin) {
    // Stage every change first so that a bad entry leaves the catalog unchanged.
    struct Staged {
        CycleSpec spec;
        CycleSpec* existing;  // nullptr: a new cycle
    };
    std::vector<Staged> staged;
    Reader cr(cycles_table, origin, "cycle");
    for (const auto& [key, node] : in_source_order(cycles_table)) {
        const toml::table* t = cr.table(key);
        const std::string norm = normalize_code(upper(key));
        if (norm.empty() || norm[0] != 'G') cr.fail(node, key, "a fixed cycle is named by its G code, e.g. G81");
        const int code = std::stoi(norm.substr(1));
        if (find_spec(staged, [&](const auto& s) { return s.spec.gcode == code; }))
            cr.fail(node, key, "the fixed cycle is defined twice");
        CycleSpec* existing = find_spec(cycles_, [&](const CycleSpec& c) { return c.gcode == code; });
        Reader one(*t, origin, cr.key_path(key));
        Staged st{CycleSpec{}, existing};
        // A patch starts from the current definition; a replacement from scratch.
        const bool replace = one.boolean("replace").value_or(false);
        if (existing && !replace) st.spec = *existing;
        st.spec.kind = SpecKind::FixedCycle;
        st.spec.name = norm;
        st.spec.gcode = code;
        st.spec.required_scope = RequiredScope::CycleStart;
        apply_spec(one, st.spec);
        one.done();
        st.spec.origin = origin;
        st.spec.index_args();
        validate_spec(st.spec, origin, line_of(*node), cr.key_path(key));
        staged.push_back(std::move(st));
    }
    cr.done();
    for (auto& s : staged) {
        if (s.existing) *s.existing = std::move(s.spec);
        else {
            const int code = s.spec.gcode;
            if (code >= 0 && code < 1024) cycle_codes_[static_cast<size_t>(code) >> 6] |= uint64_t{1} << (code & 63);
            cycles_.push_back(std::move(s.spec));
        }
    }
}

void Catalog::merge(const toml::table& macros_table, const std::string& origin) {
    // Stage every change first so that a bad entry leaves the catalog unchanged.
    std::vector<StagedMacro> staged = stage_macros(macros_table, origin, macros_);
    check_cross_references(staged, *this, origin);

    // Commit. Registrations change only for new macros and where `codes` is given.
    for (auto& s : staged) {
        bool register_codes = !s.existing || s.codes_given;
        if (s.existing && s.codes_given) {
            for (const auto& c : s.existing->codes) {
                auto it = codes_.find(c);
                if (it != codes_.end() && it->second == s.spec.name) codes_.erase(it);
            }
        }
        MacroSpec* target = s.existing;
        if (target) {
            *target = std::move(s.spec);
        } else {
            macros_.push_back(std::move(s.spec));
            target = &macros_.back();
        }
        if (register_codes)
            for (const auto& c : target->codes) codes_[c] = target->name;
    }
    index_macros();
    index_codes();
}

}  // namespace osplint
