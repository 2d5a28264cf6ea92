// The macro catalog (see catalog.h): lookups, the names of the enumerations
// in the files, the catalog's expressions, and the shipped catalog. Reading
// catalog files is in catalog_read.cpp, the cards in catalog_card.cpp.
#include "catalog/catalog.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <charconv>
#include <mutex>
#include <stdexcept>
#include <unordered_map>

#include "catalog/catalog_internal.h"
#include "support/embedded.h"
#include "support/errors.h"

namespace osplint {

namespace catalog_detail {

// ---------------------------------------------------------------------------
// Small string helpers


std::string format_number(double v) {
    char buf[64];
    auto res = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, res.ptr);
}

std::optional<double> parse_number(std::string_view s) {
    if (s.empty()) return std::nullopt;
    if (s.front() == '+') s.remove_prefix(1);
    double v = 0;
    auto res = std::from_chars(s.data(), s.data() + s.size(), v);
    if (res.ec != std::errc() || res.ptr != s.data() + s.size()) return std::nullopt;
    if (!std::isfinite(v)) return std::nullopt;  // "inf", "nan": no value a program can be checked against
    return v;
}

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
    std::string out(1, letter);
    out += digits;
    return out;
}

bool is_name(std::string_view s) {
    if (s.empty()) return false;
    for (char c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) return false;
    return true;
}

}  // namespace catalog_detail

using namespace catalog_detail;

namespace {

int plane_index(int plane) {
    switch (plane) {
        case 17: return 0;
        case 18: return 1;
        case 19: return 2;
        default: return -1;
    }
}

}  // namespace

// ---------------------------------------------------------------------------
// Public helpers

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
std::string_view to_string(MacroUnits v) { return name_in(kUnits, v); }
std::string_view to_string(G91Mode v) { return name_in(kG91, v); }
std::string_view to_string(Hazard v) { return name_in(kHazard, v); }

namespace {
struct TextHash {
    using is_transparent = void;
    size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
};
}  // namespace

const std::vector<ExprTerm>* catalog_expr(std::string_view text) {
    using Parsed = std::unordered_map<std::string, std::optional<std::vector<ExprTerm>>, TextHash, std::equal_to<>>;
    thread_local Parsed parsed;
    // The texts are the catalog's, asked for again and again at the same
    // addresses: a small table by address answers most without hashing the
    // text (the text is still compared: an address may hold another since).
    struct Recent {
        const char* data = nullptr;
        const Parsed::value_type* entry = nullptr;
    };
    thread_local std::array<Recent, 64> recent{};
    Recent& r = recent[(reinterpret_cast<uintptr_t>(text.data()) >> 3) & 63];
    // Sizes, then bytes: a plain memcmp, which the compiler keeps inline here
    // (string_view's operator== it may leave as a call).
    if (r.data == text.data() && r.entry && r.entry->first.size() == text.size() &&
        std::memcmp(r.entry->first.data(), text.data(), text.size()) == 0)
        return r.entry->second ? &*r.entry->second : nullptr;
    auto it = parsed.find(text);
    if (it == parsed.end()) it = parsed.emplace(std::string(text), parse_catalog_expr(text)).first;
    r = {text.data(), &*it};  // unordered_map entries keep their address
    return it->second ? &*it->second : nullptr;
}

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

namespace {
// A name of at most 8 characters, upper-case, as a number (0: longer, or empty).
uint64_t packed_name(std::string_view n) {
    if (n.empty() || n.size() > 8) return 0;
    uint64_t key = 0;
    for (char c : n) key = key << 8 | static_cast<unsigned char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
    return key;
}
}  // namespace

namespace {
// The first slot of a packed name in a table of `mask + 1` slots.
size_t arg_slot(uint64_t key, size_t mask) { return static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> 40) & mask; }

// MacroSpec::arg_index.
void index_arg_names(MacroSpec& spec) {
    auto& args = spec.args;
    auto& arg_index = spec.arg_index;
    auto& arg_index_of = spec.arg_index_of;
    arg_index.clear();
    arg_index_of = 0;
    if (args.size() > 0xFFFF) return;  // arg() compares the names
    std::vector<std::pair<uint64_t, uint16_t>> index;
    for (size_t i = 0; i < args.size(); ++i) index.emplace_back(packed_name(args[i].name), static_cast<uint16_t>(i));
    for (size_t i = 0; i < args.size(); ++i)
        for (const auto& al : args[i].aliases) index.emplace_back(packed_name(al), static_cast<uint16_t>(i));
    if (index.empty()) return;
    for (const auto& [key, i] : index)
        if (!key) return;  // a name too long to pack: arg() compares the names
    size_t slots = 4;
    while (slots < 2 * index.size()) slots *= 2;
    std::vector<std::pair<uint64_t, uint16_t>> table(slots, {0, 0});
    for (const auto& [key, i] : index) {
        size_t s = arg_slot(key, slots - 1);
        while (table[s].first && table[s].first != key) s = (s + 1) & (slots - 1);
        if (!table[s].first) table[s] = {key, i};  // a name met before keeps its first argument
    }
    arg_index = std::move(table);
    arg_index_of = args.size();
}
}  // namespace

namespace {
// The slot of plane 17/18/19 and axis X/Y/Z in MacroSpec::position_args_ (-1: none).
int position_slot(int plane, char axis) {
    const int p = plane == 17 ? 0 : plane == 18 ? 1 : plane == 19 ? 2 : -1;
    const int a = axis == 'X' ? 0 : axis == 'Y' ? 1 : axis == 'Z' ? 2 : -1;
    return p < 0 || a < 0 ? -1 : p * 3 + a;
}
}  // namespace

const ArgSpec* MacroSpec::position_arg(int plane, char axis) const {
    if (position_args_of == args.size() + 1) {
        const int slot = position_slot(plane, axis);
        if (slot < 0) return nullptr;
        const int16_t at = position_args_[static_cast<size_t>(slot)];
        return at ? &args[static_cast<size_t>(at - 1)] : nullptr;
    }
    const ArgSpec* pos = nullptr;
    for (const auto& as : args)
        if (as.role == ArgRole::Position && as.axis(plane) && *as.axis(plane) == axis) pos = &as;
    return pos;
}

void MacroSpec::index_args() {
    index_arg_names(*this);
    position_args_.fill(0);
    for (size_t i = 0; i < args.size() && i < 0x7FFF; ++i) {
        if (args[i].role != ArgRole::Position) continue;
        for (int plane : {17, 18, 19})
            if (const auto a = args[i].axis(plane))
                if (const int slot = position_slot(plane, *a); slot >= 0)
                    position_args_[static_cast<size_t>(slot)] = static_cast<int16_t>(i + 1);
    }
    position_args_of = args.size() + 1;
    relation_sides_.clear();
    for (const Relation& r : relations) relation_sides_.push_back(relation_sides(r, *this));
    relation_sides_of = relations.size();
    relation_sides_args_ = args.size();
    step_sides_.clear();
    for (const ActionStep& step : action) step_sides_.push_back(osplint::step_sides(step, *this));
    step_sides_of = action.size();
    step_sides_args_ = args.size();
    index_action_args();
}

void MacroSpec::index_action_args() {
    action_args_.clear();
    action_args_read_ = false;
    action_reads_axis_made_ = false;
    std::vector<bool> in(args.size(), false);
    // False when `name` is not written exactly as the name or an alias of
    // argument `i` (then the call is searched by that spelling too).
    const auto add = [&](int i, std::string_view name) {
        if (i < 0) return false;
        const ArgSpec& a = args[static_cast<size_t>(i)];
        if (name != a.name && std::find(a.aliases.begin(), a.aliases.end(), name) == a.aliases.end()) return false;
        if (!in[static_cast<size_t>(i)]) action_args_.push_back(static_cast<uint16_t>(i));
        in[static_cast<size_t>(i)] = true;
        return true;
    };
    const auto add_terms = [&](const std::optional<std::vector<ExprTerm>>& terms, const std::vector<int>& found) {
        for (size_t k = 0; k < terms->size(); ++k)
            if (!(*terms)[k].name.empty() && !add(found[k], (*terms)[k].name)) return false;
        return true;
    };
    if (args.size() > 0xFFFF) return;
    for (size_t i = 0; i < action.size(); ++i) {
        const ActionStep& step = action[i];
        const StepSides& sides = step_sides_[i];
        if (!step.target.empty() && !(sides.target && add_terms(sides.target, sides.target_args))) return;
        if (step.target.empty() && !step.by.empty() && !(sides.by && add_terms(sides.by, sides.by_args))) return;
        for (const ConditionAtom* at : step.when.atoms()) {
            if (at->arg.empty()) continue;
            const ArgSpec* a = arg(at->arg);
            if (!add(a ? static_cast<int>(a - args.data()) : -1, at->arg)) return;
        }
    }
    action_args_read_ = true;
    for (int plane : {17, 18, 19})
        for (char axis : {'X', 'Y', 'Z'})
            action_reads_axis_[static_cast<size_t>(position_slot(plane, axis))] = reads_axis_now(plane, axis);
    action_reads_axis_made_ = true;
}

bool MacroSpec::reads_axis_now(int plane, char axis) const {
    const std::vector<uint16_t>* reads = action_args();
    if (!reads) return true;
    const auto read = [&](const ArgSpec* a) {
        if (!a) return false;
        const auto index = static_cast<uint16_t>(a - args.data());
        return std::find(reads->begin(), reads->end(), index) != reads->end();
    };
    return read(arg_for_address(std::string_view(&axis, 1))) || read(position_arg(plane, axis));
}

bool MacroSpec::action_reads_axis(int plane, char axis) const {
    const int slot = position_slot(plane, axis);
    if (!action_args()) return true;
    if (slot < 0 || !action_reads_axis_made_) return reads_axis_now(plane, axis);
    return action_reads_axis_[static_cast<size_t>(slot)];
}

namespace {

// The argument of each term of `terms` (its index in the spec's args; -1 for
// a number or a name that is no argument of the spec).
void link_terms(const std::optional<std::vector<ExprTerm>>& terms, const MacroSpec& spec, std::vector<int>& args) {
    if (!terms) return;
    for (const ExprTerm& t : *terms) {
        const ArgSpec* a = t.name.empty() ? nullptr : spec.arg(t.name);
        args.push_back(a ? static_cast<int>(a - spec.args.data()) : -1);
    }
}

}  // namespace

StepSides step_sides(const ActionStep& step, const MacroSpec& spec) {
    StepSides out;
    if (!step.target.empty()) out.target = parse_catalog_expr(step.target);
    else if (!step.by.empty()) out.by = parse_catalog_expr(step.by);
    else out.to_limit = contains_ci(step.text, "+ limit");
    link_terms(out.target, spec, out.target_args);
    link_terms(out.by, spec, out.by_args);
    return out;
}


RelationSides relation_sides(const Relation& r, const MacroSpec& spec) {
    RelationSides out;
    out.left = parse_catalog_expr(r.left);
    out.right = parse_catalog_expr(r.right);
    link_terms(out.left, spec, out.left_args);
    link_terms(out.right, spec, out.right_args);
    // The left side read first: a cycle-axis name there decides; a side not
    // read orders nothing (the catalog refuses such a side when it loads).
    const auto names_cycle_axis = [&](const std::vector<int>& args) {
        for (int i : args)
            if (i >= 0 && spec.args[static_cast<size_t>(i)].role == ArgRole::Cycle) return true;
        return false;
    };
    out.cycle_order = out.left && (names_cycle_axis(out.left_args) || (out.right && names_cycle_axis(out.right_args)));
    return out;
}

const ArgSpec* MacroSpec::arg(std::string_view n) const {
    if (!arg_index.empty() && arg_index_of == args.size()) {
        const uint64_t key = packed_name(n);
        if (!key) return nullptr;  // every name is packed: a longer one is none of them
        const size_t mask = arg_index.size() - 1;
        for (size_t s = arg_slot(key, mask);; s = (s + 1) & mask) {
            if (arg_index[s].first == key) return &args[arg_index[s].second];
            if (!arg_index[s].first) return nullptr;  // the table is at most half full
        }
    }
    for (const auto& a : args)
        if (iequals(a.name, n)) return &a;
    for (const auto& a : args)
        for (const auto& al : a.aliases)
            if (iequals(al, n)) return &a;
    return nullptr;
}

const ArgSpec* MacroSpec::arg_for_address(std::string_view address) const {
    if (gcode_form && !gcode_form->address_map.empty()) {
        // Addresses are written in capitals: the key as it is, without a copy.
        const bool capitals = std::none_of(address.begin(), address.end(), [](char c) { return c >= 'a' && c <= 'z'; });
        const auto& map = gcode_form->address_map;
        auto it = capitals ? map.find(address) : map.find(upper(address));
        return it == map.end() ? nullptr : arg(it->second);
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
// Catalog lookups

std::string_view Catalog::builtin_meaning(std::string_view code) {
    const std::string norm = catalog_detail::normalize_code(code);
    if (norm.empty() || norm.size() > 5) return {};
    const int n = std::stoi(norm.substr(1));
    if (norm[0] == 'G') {
        switch (n) {
            case 0: case 1: case 2: case 3: case 60: return "a motion code";
            case 4: return "the dwell";
            case 10: case 11: case 15: case 16: return "a coordinate system code";
            case 17: case 18: case 19: return "a plane selection";
            case 20: case 21: return "a unit selection";
            case 30: return "the home position return";
            case 40: case 41: case 42: return "a cutter compensation code";
            case 53: case 56: return "a tool length offset code";
            case 90: case 91: return "a distance mode";
            case 98: case 99: return "a fixed-cycle return level";
            default: return n >= 73 && n <= 89 ? "a fixed cycle" : std::string_view();
        }
    }
    switch (n) {
        case 0: case 1: return "a program stop";
        case 2: case 30: return "the program end";
        case 3: case 4: case 5: case 19: return "a spindle code";
        case 6: return "the tool change";
        case 7: case 8: case 9: case 12: return "a coolant code";
        case 52: case 53: case 54: return "a fixed-cycle return level";
        default: return {};
    }
}

void Catalog::register_code(std::string code, std::string macro) {
    std::string norm = normalize_code(code);
    if (norm.empty()) throw std::invalid_argument("not a G or M code: " + code);
    if (macro.empty()) codes_.erase(norm);
    else codes_[norm] = upper(macro);
    index_codes();
}

void Catalog::index_codes() {
    code_keys_.clear();
    for (const auto& [key, name] : codes_) {
        int number = 0;
        const auto [end, ec] = std::from_chars(key.data() + 1, key.data() + key.size(), number);
        if (ec == std::errc() && end == key.data() + key.size()) code_keys_.emplace_back(key[0], number);
    }
}

const MacroSpec* Catalog::find_by_code(std::string_view code) const {
    auto it = codes_.find(normalize_code(code));
    return it == codes_.end() ? nullptr : find(it->second);
}

const MacroSpec* Catalog::find_by_code(char letter, int number) const {
    letter = ascii_upper(letter);
    for (const auto& [l, n] : code_keys_)
        if (l == letter && n == number) return find_by_code(std::string(1, letter) + std::to_string(number));
    return nullptr;
}

void Catalog::index_macros() {
    macro_index_.clear();
    macro_index_of_ = 0;
    if (macros_.empty() || macros_.size() > 0xFFFFFFFFu) return;
    for (const auto& m : macros_)
        if (!packed_name(m.name)) return;  // a name too long to pack: find() compares the names
    size_t slots = 4;
    while (slots < 2 * macros_.size()) slots *= 2;
    std::vector<std::pair<uint64_t, uint32_t>> table(slots, {0, 0});
    for (size_t i = 0; i < macros_.size(); ++i) {
        const uint64_t key = packed_name(macros_[i].name);
        size_t s = arg_slot(key, slots - 1);
        while (table[s].first && table[s].first != key) s = (s + 1) & (slots - 1);
        if (!table[s].first) table[s] = {key, static_cast<uint32_t>(i)};  // the first of a name, as the search
    }
    macro_index_ = std::move(table);
    macro_index_of_ = macros_.size();
}

const MacroSpec* Catalog::find(std::string_view name) const {
    if (name.empty()) return nullptr;
    if (!macro_index_.empty() && macro_index_of_ == macros_.size()) {
        const uint64_t key = packed_name(name);
        if (!key) return nullptr;  // every name is packed: a longer one is none of them
        const size_t mask = macro_index_.size() - 1;
        for (size_t s = arg_slot(key, mask);; s = (s + 1) & mask) {
            if (!macro_index_[s].first) return nullptr;  // the table is at most half full
            if (macro_index_[s].first != key) continue;
            // Packing drops the difference a NUL byte makes ("A" and "\0A"):
            // the name itself decides, by the search below when it differs.
            const MacroSpec& m = macros_[macro_index_[s].second];
            if (iequals(m.name, name)) return &m;
            break;
        }
    }
    // Most names have five letters and share their first ones (OG87C, OG87N):
    // the last letter tells them apart before the whole name is compared.
    const char last = ascii_upper(name.back());
    for (const auto& m : macros_)
        if (m.name.size() == name.size() && ascii_upper(m.name.back()) == last && iequals(m.name, name)) return &m;
    return nullptr;
}

const CycleSpec* Catalog::find_cycle(int gcode) const {
    if (gcode >= 0 && gcode < 1024 && !((cycle_codes_[static_cast<size_t>(gcode) >> 6] >> (gcode & 63)) & 1u))
        return nullptr;
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
