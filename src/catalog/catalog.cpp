// Loading, validating, merging and printing the macro catalog (see catalog.h
// and docs/catalog.md for the schema).
#include "catalog/catalog.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <functional>
#include <mutex>
#include <set>
#include <stdexcept>
#include <utility>

#include "support/embedded.h"
#include "support/errors.h"

namespace osplint {

namespace {

// ---------------------------------------------------------------------------
// Small string helpers

std::string upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::toupper(static_cast<unsigned char>(a[i])) != std::toupper(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

std::string format_number(double v) {
    char buf[64];
    auto res = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, res.ptr);
}

// The whole of `s` as a number ("5", "-0.5", "1000"), else nullopt.
std::optional<double> parse_number(std::string_view s) {
    if (s.empty()) return std::nullopt;
    if (s.front() == '+') s.remove_prefix(1);
    double v = 0;
    auto res = std::from_chars(s.data(), s.data() + s.size(), v);
    if (res.ec != std::errc() || res.ptr != s.data() + s.size()) return std::nullopt;
    return v;
}

// "g0114" -> "G114"; "M204" -> "M204"; empty on a malformed code.
std::string normalize_code(std::string_view code) {
    while (!code.empty() && std::isspace(static_cast<unsigned char>(code.front()))) code.remove_prefix(1);
    while (!code.empty() && std::isspace(static_cast<unsigned char>(code.back()))) code.remove_suffix(1);
    if (code.size() < 2) return {};
    char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(code[0])));
    if (letter != 'G' && letter != 'M') return {};
    std::string_view digits = code.substr(1);
    for (char c : digits)
        if (!std::isdigit(static_cast<unsigned char>(c))) return {};
    while (digits.size() > 1 && digits.front() == '0') digits.remove_prefix(1);
    return std::string(1, letter) + std::string(digits);
}

bool is_name(std::string_view s) {
    if (s.empty()) return false;
    for (char c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) return false;
    return true;
}

// ---------------------------------------------------------------------------
// Enumerations and their names in the files

template <class E>
struct EnumName {
    std::string_view name;
    E value;
};

constexpr EnumName<ArgOmitted> kOmitted[] = {
    {"required", ArgOmitted::Required}, {"default", ArgOmitted::Default},
    {"current", ArgOmitted::Current},   {"none", ArgOmitted::None},
    {"unknown", ArgOmitted::Unknown},
};
constexpr EnumName<ArgSign> kSign[] = {
    {"any", ArgSign::Any},
    {"positive", ArgSign::Positive},
    {"non-negative", ArgSign::NonNegative},
    {"non-zero", ArgSign::NonZero},
};
constexpr EnumName<ArgRole> kRole[] = {
    {"position", ArgRole::Position}, {"cycle", ArgRole::Cycle},
    {"length", ArgRole::Length},     {"stroke", ArgRole::Stroke},
    {"shift", ArgRole::Shift},       {"feed", ArgRole::Feed},
    {"speed", ArgRole::Speed},       {"dwell", ArgRole::Dwell},
    {"time", ArgRole::Time},         {"comp-number", ArgRole::CompNumber},
    {"m-code", ArgRole::MCode},      {"vector", ArgRole::Vector},
    {"pitch", ArgRole::Pitch},       {"direction", ArgRole::Direction},
    {"count", ArgRole::Count},
};
constexpr EnumName<ArgInFormat> kInFormat[] = {
    {"required", ArgInFormat::Required},
    {"optional", ArgInFormat::Optional},
    {"absent", ArgInFormat::Absent},
};
constexpr EnumName<MacroForm> kForm[] = {
    {"CALL", MacroForm::Call},
    {"MODIN", MacroForm::Modin},
    {"GCODE", MacroForm::GCode},
    {"MCODE", MacroForm::MCode},
};
constexpr EnumName<M52Mode> kM52[] = {
    {"ignored-use-PM52", M52Mode::IgnoredUsePM52},
    {"fixed-cycle", M52Mode::FixedCycle},
    {"undocumented", M52Mode::Undocumented},
};
constexpr EnumName<M53Mode> kM53[] = {
    {"return-to-PT", M53Mode::ReturnToPT},
    {"fixed-cycle", M53Mode::FixedCycle},
    {"undocumented", M53Mode::Undocumented},
};
constexpr EnumName<RequiredScope> kScope[] = {
    {"every-call", RequiredScope::EveryCall},
    {"cycle-start", RequiredScope::CycleStart},
};

template <class E, std::size_t N>
std::string_view name_in(const EnumName<E> (&table)[N], E v) {
    for (const auto& e : table)
        if (e.value == v) return e.name;
    return "?";
}

template <class E, std::size_t N>
std::string choices(const EnumName<E> (&table)[N]) {
    std::string s;
    for (const auto& e : table) {
        if (!s.empty()) s += ", ";
        s += '"';
        s += e.name;
        s += '"';
    }
    return s;
}

int plane_index(int plane) {
    switch (plane) {
        case 17: return 0;
        case 18: return 1;
        case 19: return 2;
        default: return -1;
    }
}

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
        if (n->is_floating_point()) return n->as_floating_point()->get();
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
                out.push_back(e.as_floating_point()->get());
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
            double v = n->is_integer() ? static_cast<double>(n->as_integer()->get()) : n->as_floating_point()->get();
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

// Applies a macro (or fixed-cycle) table to `spec`: on a new spec every field
// given is set; on an existing one the fields given replace the old ones and
// `arg.NAME` tables patch or add arguments.
void apply_spec(Reader& r, MacroSpec& spec) {
    if (auto v = r.str("family")) spec.family = *v;
    if (auto v = r.str("title")) spec.title = *v;
    if (auto v = r.str("manual")) spec.manual = *v;
    if (auto v = r.str("source")) spec.source = *v;
    if (const toml::array* a = r.array("forms")) {
        spec.forms.clear();
        for (const auto& e : *a) spec.forms.push_back(r.enum_value(&e, "forms", kForm));
    }
    if (auto v = r.boolean("args_documented")) spec.args_documented = *v;
    if (auto v = r.boolean("mm_only")) spec.mm_only = *v;
    if (auto v = r.boolean("cycle_args_absolute_g91")) spec.cycle_args_absolute_g91 = *v;
    if (auto v = r.enumeration("m52", kM52)) spec.m52 = *v;
    if (auto v = r.enumeration("m53", kM53)) spec.m53 = *v;
    if (auto v = r.boolean("g60_ncyl_forbidden")) spec.g60_ncyl_forbidden = *v;
    if (auto v = r.boolean("vc120_128_clobbered")) spec.vc120_128_clobbered = *v;
    if (auto v = r.boolean("q_repeat_unsafe")) spec.q_repeat_unsafe = *v;
    if (auto v = r.boolean("g91_forbidden")) spec.g91_forbidden = *v;
    if (auto v = r.boolean("tapping")) spec.tapping = *v;
    if (auto v = r.enumeration("required_scope", kScope)) spec.required_scope = *v;
    if (r.has("format")) {
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
    if (const toml::table* g = r.table("gcode")) {
        Reader gr(*g, r.file(), r.key_path("gcode"));
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
        spec.gcode_form = std::move(form);
    }
    if (auto v = r.strings("codes")) {
        spec.codes.clear();
        const toml::node* n = r.get("codes");
        for (const auto& c : *v) {
            std::string code = normalize_code(c);
            if (code.empty()) r.fail(n, "codes", "\"" + c + "\" is not a G or M code");
            spec.codes.push_back(code);
        }
    }
    if (auto v = r.str("cancel")) spec.cancel = upper(*v);
    if (auto v = r.str("cancels")) spec.cancels = upper(*v);
    if (auto v = r.str("plane_table")) spec.plane_table = *v;
    if (auto v = r.str("common")) spec.common = *v;

    if (const toml::table* args = r.table("arg")) {
        Reader ar(*args, r.file(), r.key_path("arg"));
        for (const auto& [name, node] : in_source_order(*args)) {
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
    if (r.has("at_least_one")) {
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
    if (r.has("relations")) {
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
            if (auto v = e.str("when")) rel.when = *v;
            if (auto v = e.str("source")) rel.source = *v;
            if (auto v = e.boolean("inferred")) rel.inferred = *v;
            if (auto v = e.str("note")) rel.note = *v;
            spec.relations.push_back(std::move(rel));
        });
    }
    if (r.has("action")) {
        spec.action.clear();
        r.each_table("action", [&](Reader& e) {
            ActionStep step;
            if (auto v = e.str("step")) step.step = *v;
            else e.fail(nullptr, "step", "an action step needs 'step'");
            if (auto v = e.str("text")) step.text = *v;
            if (auto v = e.str("feed")) step.feed = *v;
            if (auto v = e.str("target")) step.target = upper(*v);
            if (auto v = e.str("by")) step.by = upper(*v);
            if (auto v = e.str("when")) step.when = *v;
            if (auto v = e.boolean("inferred")) step.inferred = *v;
            if (auto v = e.str("source")) step.source = *v;
            spec.action.push_back(std::move(step));
        });
    }
    if (r.has("notes")) spec.notes = read_notes(r);
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
// Card rendering helpers

std::string md_escape(std::string_view s) {
    std::string out;
    for (char c : s) {
        if (c == '|' || c == '*' || c == '_' || c == '`' || c == '<' || c == '[' || c == ']' || c == '\\')
            out += '\\';
        out += c;
    }
    return out;
}

// Word-wraps `text` to `width` columns; continuation lines get `indent`.
std::string wrap(std::string_view text, std::size_t first_col, std::size_t indent, std::size_t width = 100) {
    std::string out;
    std::size_t col = first_col;
    bool first_word = true;
    std::size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && text[i] == ' ') ++i;
        std::size_t j = i;
        while (j < text.size() && text[j] != ' ') ++j;
        if (j == i) break;
        std::string_view word = text.substr(i, j - i);
        if (!first_word && col + 1 + word.size() > width) {
            out += '\n';
            out.append(indent, ' ');
            col = indent;
        } else if (!first_word) {
            out += ' ';
            ++col;
        }
        out += word;
        col += word.size();
        first_word = false;
        i = j;
    }
    return out;
}

std::string omitted_text(const ArgSpec& a) {
    switch (a.omitted) {
        case ArgOmitted::Required: return "required";
        case ArgOmitted::Default: return "default " + a.default_text;
        case ArgOmitted::Current: return a.default_text.empty() ? "current value" : a.default_text;
        case ArgOmitted::None:
            if (a.default_text.empty() || a.default_text.rfind("none", 0) == 0) return a.default_text.empty() ? "none" : a.default_text;
            return "none; printed: " + a.default_text;
        case ArgOmitted::Unknown: return "not documented";
    }
    return "?";
}


std::string format_status_text(const MacroSpec& spec, const ArgSpec& a) {
    // One word when every documented form agrees, else per form.
    std::vector<MacroForm> forms = spec.forms;
    if (forms.empty()) forms.push_back(MacroForm::Call);
    if (spec.kind == SpecKind::FixedCycle) return std::string(to_string(a.format_status(MacroForm::GCode)));
    bool same = true;
    for (auto f : forms) same = same && a.format_status(f) == a.format_status(forms.front());
    if (same) return std::string(to_string(a.format_status(forms.front())));
    std::string s;
    for (auto f : forms) {
        if (!s.empty()) s += ", ";
        s += std::string(to_string(f)) + " " + std::string(to_string(a.format_status(f)));
    }
    return s;
}

std::string axis_cell(char c) { return c ? std::string(1, c) : std::string("-"); }

std::string m52_text(M52Mode m) {
    switch (m) {
        case M52Mode::IgnoredUsePM52:
            return "ignored on the call line: command PM=52 (M52 on blocks run while a MODIN call is modal is valid)";
        case M52Mode::FixedCycle: return "as with fixed cycles";
        case M52Mode::Undocumented: return "not documented";
    }
    return "?";
}

std::string m53_text(M53Mode m) {
    switch (m) {
        case M53Mode::ReturnToPT: return "returns to PT (G71 is not read); M53 without PT raises an alarm";
        case M53Mode::FixedCycle: return "as with fixed cycles (G71 gives the return level)";
        case M53Mode::Undocumented: return "not documented";
    }
    return "?";
}

std::string join_forms(const std::vector<MacroForm>& forms) {
    std::string s;
    for (auto f : forms) s += (s.empty() ? "" : ", ") + std::string(to_string(f));
    return s;
}

std::string step_suffix(const ActionStep& st) {
    std::string s;
    if (!st.feed.empty()) s += " [" + st.feed + "]";
    if (!st.target.empty()) s += " -> " + st.target;
    if (!st.by.empty()) s += " (moves by " + st.by + ", direction not stated)";
    if (!st.when.empty()) s += " (when " + st.when + ")";
    if (st.inferred) s += " (target inferred)";
    return s;
}

std::string relation_text(const Relation& rel) {
    std::string s = rel.left + " " + rel.op + " " + rel.right;
    if (rel.plane) s += " in G" + std::to_string(rel.plane);
    if (!rel.when.empty()) s += " when " + rel.when;
    if (rel.inferred) s += " (inferred)";
    if (!rel.source.empty()) s += " [" + rel.source + "]";
    if (!rel.note.empty()) s += ": " + rel.note;
    return s;
}

std::string at_least_one_text(const AtLeastOne& r) {
    std::string s = "at least one of ";
    for (std::size_t i = 0; i < r.args.size(); ++i) s += (i ? ", " : "") + r.args[i];
    if (r.plane) s += " in G" + std::to_string(r.plane);
    if (r.inferred) s += " (inferred)";
    if (!r.source.empty()) s += " [" + r.source + "]";
    return s;
}


// Writes a card as terminal text or Markdown; the sections look alike in both.
class Card {
public:
    explicit Card(bool md) : md_(md) {}
    bool md() const { return md_; }
    std::string take() { return std::move(out_); }

    void line(std::string s) {
        while (!s.empty() && s.back() == ' ') s.pop_back();
        out_ += s;
        out_ += '\n';
    }
    void title(const std::string& name, const std::string& title) {
        if (md_) line("### " + md_escape(name) + (title.empty() ? "" : ": " + md_escape(title)));
        else line(name + (title.empty() ? "" : " - " + title));
    }
    // A section heading, preceded by a blank line.
    void heading(const std::string& text) {
        line("");
        line(md_ ? "**" + md_escape(text) + "**" : text);
        if (md_) line("");
    }
    // "key: value" lines, values aligned in text mode.
    void facts(const std::vector<std::pair<std::string, std::string>>& items) {
        std::size_t col = 0;
        for (const auto& f : items) col = std::max(col, f.first.size() + 5);
        for (const auto& [k, v] : items) {
            if (md_) {
                line("- **" + md_escape(k) + "**: " + md_escape(v));
            } else {
                std::string label = "  " + k + ":";
                label.resize(col, ' ');
                line(label + wrap(v, col, col));
            }
        }
    }
    void bullets(const std::vector<std::string>& items) {
        for (const auto& text : items) line(md_ ? "- " + md_escape(text) : "  - " + wrap(text, 4, 4));
    }
    // A paragraph of prose (indented in text mode).
    void para(const std::string& text) {
        if (md_) line(md_escape(text));
        else line("  " + wrap(text, 2, 4));
    }
    // Labelled items such as action steps: "3a   text".
    void labelled(const std::vector<std::pair<std::string, std::string>>& items) {
        for (const auto& [label, text] : items) {
            if (md_) {
                line("- **" + md_escape(label) + "** " + md_escape(text));
            } else {
                std::string l = "  " + label;
                l.resize(std::max<std::size_t>(l.size() + 1, 7), ' ');
                line(l + wrap(text, l.size(), 7));
            }
        }
    }
    // A table; the last column is free text (wrapped in text mode).
    void table(const std::vector<std::string>& head, const std::vector<std::vector<std::string>>& rows,
               const std::set<std::size_t>& code_columns = {}) {
        if (md_) {
            std::string h = "|", sep = "|";
            for (const auto& c : head) h += " " + md_escape(c) + " |", sep += "---|";
            line(h);
            line(sep);
            for (const auto& row : rows) {
                std::string s = "|";
                for (std::size_t i = 0; i < row.size(); ++i) {
                    std::string cell = code_columns.count(i) ? "`" + row[i] + "`" : md_escape(row[i]);
                    s += " " + cell + " |";
                }
                line(s);
            }
            return;
        }
        std::vector<std::size_t> width(head.size());
        for (std::size_t i = 0; i < head.size(); ++i) width[i] = head[i].size();
        for (const auto& row : rows)
            for (std::size_t i = 0; i + 1 < row.size(); ++i) width[i] = std::max(width[i], row[i].size());
        auto emit = [&](const std::vector<std::string>& row) {
            std::string s = " ";
            for (std::size_t i = 0; i + 1 < row.size(); ++i) {
                s += ' ';
                s += row[i];
                s.append(width[i] - row[i].size() + 1, ' ');
            }
            s += ' ';
            line(s + wrap(row.back(), s.size(), s.size(), std::max<std::size_t>(110, s.size() + 50)));
        };
        emit(head);
        for (const auto& row : rows) emit(row);
    }

private:
    bool md_;
    std::string out_;
};

}  // namespace

// ---------------------------------------------------------------------------
// Public helpers

std::string_view to_string(ArgOmitted v) { return name_in(kOmitted, v); }
std::string_view to_string(ArgSign v) { return name_in(kSign, v); }
std::string_view to_string(ArgRole v) { return name_in(kRole, v); }
std::string_view to_string(ArgInFormat v) { return name_in(kInFormat, v); }
std::string_view to_string(MacroForm v) { return name_in(kForm, v); }
std::string_view to_string(M52Mode v) { return name_in(kM52, v); }
std::string_view to_string(M53Mode v) { return name_in(kM53, v); }
std::string_view to_string(RequiredScope v) { return name_in(kScope, v); }

std::optional<std::vector<ExprTerm>> parse_catalog_expr(std::string_view text) {
    std::vector<ExprTerm> terms;
    std::size_t i = 0;
    auto skip = [&] {
        while (i < text.size() && text[i] == ' ') ++i;
    };
    skip();
    int sign = 1;
    if (i < text.size() && (text[i] == '-' || text[i] == '+')) {
        sign = text[i] == '-' ? -1 : 1;
        ++i;
        skip();
    }
    while (true) {
        std::size_t j = i;
        while (j < text.size() && (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '.')) ++j;
        if (j == i) return std::nullopt;
        std::string_view tok = text.substr(i, j - i);
        ExprTerm term;
        term.sign = sign;
        if (std::isdigit(static_cast<unsigned char>(tok[0])) || tok[0] == '.') {
            auto v = parse_number(tok);
            if (!v) return std::nullopt;
            term.number = *v;
        } else {
            if (!is_name(tok)) return std::nullopt;
            term.name = upper(tok);
        }
        terms.push_back(std::move(term));
        i = j;
        skip();
        if (i == text.size()) break;
        if (text[i] != '+' && text[i] != '-') return std::nullopt;
        sign = text[i] == '-' ? -1 : 1;
        ++i;
        skip();
    }
    return terms;
}

std::optional<char> ArgSpec::axis(int plane) const {
    int i = plane_index(plane);
    if (i < 0 || axes[i] == '\0') return std::nullopt;
    return axes[i];
}

const ArgSpec* MacroSpec::arg(std::string_view n) const {
    for (const auto& a : args)
        if (iequals(a.name, n)) return &a;
    for (const auto& a : args)
        for (const auto& al : a.aliases)
            if (iequals(al, n)) return &a;
    return nullptr;
}

const ArgSpec* MacroSpec::arg_for_address(std::string_view address) const {
    if (gcode_form && !gcode_form->address_map.empty()) {
        auto it = gcode_form->address_map.find(upper(address));
        return it == gcode_form->address_map.end() ? nullptr : arg(it->second);
    }
    return arg(address);
}

bool MacroSpec::has_form(MacroForm form) const {
    return std::find(forms.begin(), forms.end(), form) != forms.end();
}

const Reading* MacroSpec::reading(std::string_view id) const {
    for (const auto& r : readings)
        if (iequals(r.id, id)) return &r;
    return nullptr;
}

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
        if (!n->is_integer() || n->as_integer()->get() != 1)
            r.fail(n, "schema", "this osplint reads catalog schema 1");
    }
    if (const toml::table* pt = r.table("plane_table")) read_plane_tables(*pt, origin, cat.plane_tables_);
    if (const toml::table* ct = r.table("common")) read_common(*ct, origin, cat.common_);
    if (const toml::table* m = r.table("macro")) cat.merge(*m, origin);
    if (const toml::table* c = r.table("cycle")) {
        Reader cr(*c, origin, "cycle");
        for (const auto& [key, node] : in_source_order(*c)) {
            const toml::table* t = cr.table(key);
            std::string name = upper(key);
            int code = 0;
            std::string norm = normalize_code(name);
            if (norm.empty() || norm[0] != 'G') cr.fail(node, key, "a fixed cycle is named by its G code, e.g. G81");
            code = std::stoi(norm.substr(1));
            CycleSpec spec;
            spec.kind = SpecKind::FixedCycle;
            spec.name = norm;
            spec.gcode = code;
            spec.required_scope = RequiredScope::CycleStart;
            Reader one(*t, origin, cr.key_path(key));
            apply_spec(one, spec);
            one.done();
            spec.origin = origin;
            validate_spec(spec, origin, line_of(*node), cr.key_path(key));
            if (cat.find_cycle(code)) cr.fail(node, key, "duplicate fixed cycle");
            cat.cycles_.push_back(std::move(spec));
        }
        cr.done();
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

void Catalog::merge(const toml::table& macros_table, const std::string& origin) {
    // Stage every change first so that a bad entry leaves the catalog unchanged.
    struct Staged {
        MacroSpec spec;
        MacroSpec* existing;  // nullptr: a new macro
        uint32_t line;
        bool codes_given;
    };
    std::vector<Staged> staged;
    Reader r(macros_table, origin, "macro");
    for (const auto& [key, node] : in_source_order(macros_table)) {
        const toml::table* t = r.table(key);
        std::string name = upper(key);
        if (!is_name(name) || name[0] != 'O')
            r.fail(node, key, "a macro is named by its program name, e.g. OZAGR");
        for (const auto& s : staged)
            if (s.spec.name == name) r.fail(node, key, "the macro is defined twice");
        MacroSpec* existing = nullptr;
        for (auto& m : macros_)
            if (m.name == name) existing = &m;
        Reader one(*t, origin, r.key_path(key));
        bool replace = one.boolean("replace").value_or(false);
        Staged st{MacroSpec{}, existing, line_of(*node), t->contains("codes")};
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
        validate_spec(st.spec, origin, st.line, r.key_path(key));
        staged.push_back(std::move(st));
    }
    r.done();

    // Cross-references: cancel / cancels must name a macro known after the
    // merge, and one merge must not give a code to two macros.
    auto known_after = [&](const std::string& n) {
        if (find(n)) return true;
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
}

void Catalog::register_code(std::string code, std::string macro) {
    std::string norm = normalize_code(code);
    if (norm.empty()) throw std::invalid_argument("not a G or M code: " + code);
    if (macro.empty()) {
        codes_.erase(norm);
        return;
    }
    codes_[norm] = upper(macro);
}

const MacroSpec* Catalog::find_by_code(std::string_view code) const {
    auto it = codes_.find(normalize_code(code));
    return it == codes_.end() ? nullptr : find(it->second);
}

const MacroSpec* Catalog::find(std::string_view name) const {
    for (const auto& m : macros_)
        if (iequals(m.name, name)) return &m;
    return nullptr;
}

const CycleSpec* Catalog::find_cycle(int gcode) const {
    for (const auto& c : cycles_)
        if (c.gcode == gcode) return &c;
    return nullptr;
}

const CommonRules* Catalog::common_rules(std::string_view id) const {
    for (const auto& c : common_)
        if (c.id == id) return &c;
    return nullptr;
}

const PlaneTable* Catalog::plane_table(std::string_view id) const {
    for (const auto& t : plane_tables_)
        if (t.id == id) return &t;
    return nullptr;
}

Catalog Catalog::builtin() {
    static std::mutex mu;
    static std::optional<Catalog> cached;
    std::lock_guard<std::mutex> lock(mu);
    if (!cached) {
        auto text = embedded::find("data/macros.toml");
        if (!text) throw ConfigError("data/macros.toml", 0, "", "the macro catalog is not embedded in this build");
        cached = from_toml_text(*text, "data/macros.toml");
    }
    return *cached;
}

std::string Catalog::render_card(const MacroSpec& spec, bool md) const {
    Card card(md);
    const bool cycle = spec.kind == SpecKind::FixedCycle;
    auto codes_of = [&](const std::string& macro) {
        std::string s;
        for (const auto& [code, name] : codes_)
            if (name == macro) s += (s.empty() ? "" : ", ") + code;
        return s;
    };

    card.title(spec.name, spec.title);
    if (md) card.line("");
    std::vector<std::pair<std::string, std::string>> facts;
    if (!spec.family.empty()) facts.emplace_back("Family", spec.family);
    if (!spec.manual.empty() || !spec.source.empty())
        facts.emplace_back("Manual", spec.manual + (spec.source.empty() ? "" : ", " + spec.source));
    if (!cycle) facts.emplace_back("Forms", join_forms(spec.forms));
    if (std::string r = codes_of(spec.name); !r.empty()) facts.emplace_back("Registered to", r);
    if (!spec.cancel.empty()) {
        std::string r = codes_of(spec.cancel);
        facts.emplace_back("Cancel", spec.cancel + (r.empty() ? "" : " (" + r + ")"));
    }
    if (!spec.cancels.empty()) facts.emplace_back("Cancels", spec.cancels);
    if (!spec.origin.empty() && spec.origin != "data/macros.toml") facts.emplace_back("Defined in", spec.origin);
    card.facts(facts);

    // Command format: printed lines, then the G-code macro form when it differs.
    bool gcode_printed = false;
    if (spec.gcode_form)
        for (const auto& f : spec.formats) gcode_printed = gcode_printed || f.text == spec.gcode_form->text;
    if (!spec.formats.empty() || spec.gcode_form) {
        card.heading("Format");
        std::vector<std::string> lines;
        for (const auto& f : spec.formats) lines.push_back(f.text + (f.source.empty() ? "" : "    (" + f.source + ")"));
        if (spec.gcode_form && !gcode_printed)
            lines.push_back(spec.gcode_form->text + "    (G-code macro form" +
                            (spec.gcode_form->source.empty() ? "" : ", " + spec.gcode_form->source) + ")");
        if (md) card.line("```text");
        for (const auto& l : lines) card.line(md ? l : "  " + l);
        if (md) card.line("```");
        if (spec.gcode_form && !spec.gcode_form->address_map.empty()) {
            std::string map;
            for (const auto& [addr, target] : spec.gcode_form->address_map)
                map += (map.empty() ? "" : ", ") + addr + "=" + target;
            if (md) card.line("");
            card.para("G-code form addresses: " + map + "." +
                      (spec.gcode_form->note.empty() ? "" : " " + spec.gcode_form->note));
        }
    }

    // Arguments and the conditions between them.
    if (!spec.args_documented && spec.args.empty()) {
        card.heading("Arguments");
        card.para("Not documented in the manuals; any address is accepted.");
    } else {
        card.heading(md ? "Arguments" : "Arguments (machine axis in G17/G18/G19)");
        std::vector<std::vector<std::string>> rows;
        for (const auto& a : spec.args) {
            std::string name = a.name;
            for (const auto& al : a.aliases) name += "/" + al;
            if (a.undocumented) name += " (undocumented)";
            std::string meaning = a.meaning;
            if (!a.note.empty()) meaning += " (" + a.note + ")";
            if (!a.source.empty()) meaning += " [" + a.source + "]";
            rows.push_back({name, omitted_text(a), [&] { std::string v = constraint_text(a); return v.empty() ? std::string("any") : v; }(), axis_cell(a.axes[0]), axis_cell(a.axes[1]),
                            axis_cell(a.axes[2]), format_status_text(spec, a), meaning});
        }
        card.table({"Arg", "If omitted", "Values", "G17", "G18", "G19", "Format", "Meaning"}, rows, {0});
    }
    std::vector<std::string> conditions;
    for (const auto& r : spec.at_least_one) conditions.push_back(at_least_one_text(r));
    for (const auto& rel : spec.relations) conditions.push_back(relation_text(rel));
    if (!conditions.empty()) {
        card.heading("Conditions");
        card.bullets(conditions);
    }

    // Modes.
    std::vector<std::pair<std::string, std::string>> modes;
    if (cycle) {
        modes.emplace_back("Required arguments", "on the block that starts the cycle (modal within the cycle)");
        if (spec.tapping) modes.emplace_back("Tapping cycle", "yes");
    } else {
        modes.emplace_back("mm only", spec.mm_only ? "yes" : "not stated");
        modes.emplace_back("Cycle axis under G91", spec.cycle_args_absolute_g91
                                                       ? "absolute: from the workpiece origin even in G91"
                                                       : "follows G90/G91 as with fixed cycles");
        modes.emplace_back("M52 on the call line", m52_text(spec.m52));
        modes.emplace_back("M53", m53_text(spec.m53));
        modes.emplace_back("G60 with NCYL", spec.g60_ncyl_forbidden ? "forbidden (collision)" : "not restricted");
        modes.emplace_back("VC120-VC128", spec.vc120_128_clobbered ? "overwritten by the macro" : "not used");
        modes.emplace_back("Q repeat count",
                           spec.q_repeat_unsafe ? "unsafe (abnormal from the 2nd call)" : "not restricted");
        if (spec.g91_forbidden) modes.emplace_back("G91 mode", "not usable (wrong motion, no alarm)");
        if (spec.tapping) modes.emplace_back("Tapping cycle", "yes");
        if (spec.required_scope == RequiredScope::CycleStart)
            modes.emplace_back("Required arguments", "on the block that starts the cycle");
    }
    card.heading("Modes");
    card.facts(modes);

    if (!spec.action.empty()) {
        card.heading("Action sequence");
        std::vector<std::pair<std::string, std::string>> steps;
        for (const auto& st : spec.action) steps.emplace_back(st.step, st.text + step_suffix(st));
        card.labelled(steps);
    }
    auto with_source = [](const CatalogNote& n) { return n.text + (n.source.empty() ? "" : " [" + n.source + "]"); };
    if (!spec.notes.empty()) {
        card.heading("Notes");
        std::vector<std::string> items;
        for (const auto& n : spec.notes) items.push_back(with_source(n));
        card.bullets(items);
    }
    if (!spec.readings.empty()) {
        card.heading("Readings");
        std::vector<std::string> items;
        for (const auto& rd : spec.readings) {
            std::string text = rd.id + (rd.open ? " (open, configurable)" : "") + ": " + rd.issue +
                               (rd.issue.empty() ? "" : " ") + "Reading: " + rd.reading;
            if (!rd.override_hint.empty()) text += " To take the other reading: " + rd.override_hint;
            items.push_back(text);
        }
        card.bullets(items);
    }
    if (const CommonRules* common = spec.common.empty() ? nullptr : common_rules(spec.common)) {
        card.heading((common->title.empty() ? common->id : common->title) +
                     (common->source.empty() ? "" : " [" + common->source + "]"));
        std::vector<std::string> items;
        for (const auto& n : common->notes) items.push_back(with_source(n));
        for (const auto& rd : common->readings)
            items.push_back("Reading " + rd.id + ": " + rd.issue + (rd.issue.empty() ? "" : " ") + rd.reading);
        card.bullets(items);
    }

    // The manual's plane table as printed, with the reading taken.
    if (const PlaneTable* pt = spec.plane_table.empty() ? nullptr : plane_table(spec.plane_table)) {
        card.heading("Plane table " + pt->id + (pt->source.empty() ? "" : " [" + pt->source + "]"));
        if (!pt->columns.empty()) {
            static const char* kRows[] = {"G17", "G18", "G19"};
            std::vector<std::string> head = {""};
            head.insert(head.end(), pt->columns.begin(), pt->columns.end());
            std::vector<std::vector<std::string>> rows;
            for (int i = 0; i < 3; ++i) {
                std::vector<std::string> row = {kRows[i]};
                for (std::size_t c = 0; c < pt->columns.size(); ++c) {
                    std::string cell = c < pt->rows[i].size() ? pt->rows[i][c] : "";
                    row.push_back(cell.empty() && !md ? "." : cell);  // "." marks a blank cell
                }
                rows.push_back(std::move(row));
            }
            card.table(head, rows);
        }
        if (!pt->reading.empty()) {
            if (md) card.line("");
            card.para("Reading: " + pt->reading);
        }
    }
    return card.take();
}

std::string constraint_text(const ArgSpec& a) {
    std::vector<std::string> parts;
    if (!a.allowed.empty()) {
        std::string s = "one of ";
        for (std::size_t i = 0; i < a.allowed.size(); ++i) s += (i ? ", " : "") + format_number(a.allowed[i]);
        parts.push_back(s);
    }
    if (a.sign != ArgSign::Any) parts.emplace_back(to_string(a.sign));
    if (a.negative_allowed) parts.emplace_back("negative allowed");
    if (a.always_incremental) parts.emplace_back("always incremental");
    if (a.g91_only) parts.emplace_back("G91 only");
    std::string s;
    for (const auto& p : parts) s += (s.empty() ? "" : "; ") + p;
    return s;
}

bool relation_holds(double left, std::string_view op, double right) {
    if (op == ">") return left > right;
    if (op == ">=") return left >= right;
    if (op == "<") return left < right;
    if (op == "<=") return left <= right;
    if (op == "==") return left == right;
    if (op == "!=") return left != right;
    return true;
}

}  // namespace osplint
