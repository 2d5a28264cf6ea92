// Language server: completion of macro names and of their arguments (features.h).
#include "lsp/features.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <set>

#include "catalog/catalog.h"
#include "support/text.h"

namespace osplint::lsp {

namespace {

struct CallLine {
    bool found = false;
    bool modin = false;
    std::size_t name_begin = 0, name_end = 0;  // the name after the keyword
};

// Blanks out comments so that text inside `( )` is never read as code.
std::string strip_comments(std::string_view line) {
    std::string out(line);
    bool in = false;
    for (auto& c : out) {
        if (!in && c == '(') in = true;
        if (in) {
            const bool close = c == ')';
            c = ' ';
            if (close) in = false;
        }
    }
    return out;
}

CallLine find_call(const std::string& code) {
    CallLine r;
    const std::string up = upper(code);
    for (std::string_view kw : {std::string_view("CALL"), std::string_view("MODIN")}) {
        std::size_t at = 0;
        while ((at = up.find(kw, at)) != std::string::npos) {
            const bool start_ok = at == 0 || !is_alnum(up[at - 1]);
            const std::size_t after = at + kw.size();
            const bool end_ok = after == up.size() || up[after] == ' ' || up[after] == '\t' || up[after] == 'O';
            if (start_ok && end_ok) {
                r.found = true;
                r.modin = kw == "MODIN";
                std::size_t i = after;
                while (i < up.size() && (up[i] == ' ' || up[i] == '\t')) ++i;
                r.name_begin = i;
                while (i < up.size() && is_alnum(up[i])) ++i;
                r.name_end = i;
                return r;
            }
            at = after;
        }
    }
    return r;
}

// The macros the catalog has in `form` (CALL or MODIN), then the
// subprograms known by name.
void macro_name_items(const Config& config, const ProgramNames& programs, MacroForm form, json& items) {
    std::set<std::string> seen;
    for (const auto& spec : config.catalog.macros()) {
        if (!spec.forms.empty() && !spec.has_form(form)) continue;
        seen.insert(spec.name);
        items.push_back({{"label", spec.name},
                         {"kind", 3},  // Function
                         {"detail", spec.title},
                         {"documentation", markdown(config.catalog.render_card(spec, true))},
                         {"insertText", spec.name},
                         {"sortText", "0" + spec.name}});
    }
    for (const auto& name : programs) {
        if (seen.count(name) || name.empty()) continue;
        items.push_back({{"label", name},
                         {"kind", 9},  // Module
                         {"detail", "subprogram"},
                         {"insertText", name},
                         {"sortText", "1" + name}});
    }
}

// The argument names written with `=` after the macro name (upper case),
// but the one being typed at `column`.
std::set<std::string> given_arguments(const std::string& code, std::size_t name_end, uint32_t column) {
    std::size_t tok = column;
    while (tok > 0 && is_alnum(code[tok - 1])) --tok;
    std::set<std::string> given;
    const std::string up = upper(code);
    for (std::size_t i = name_end; i < up.size();) {
        if (!std::isalpha(static_cast<unsigned char>(up[i])) || (i > 0 && is_alnum(up[i - 1]))) {
            ++i;
            continue;
        }
        std::size_t j = i;
        while (j < up.size() && is_alnum(up[j])) ++j;
        std::size_t k = j;
        while (k < up.size() && (up[k] == ' ' || up[k] == '\t')) ++k;
        if (k < up.size() && up[k] == '=' && i != tok) given.insert(up.substr(i, j - i));
        i = j;
    }
    return given;
}

}  // namespace

json completion(std::string_view line, uint32_t column, const Config& config, const ProgramNames& programs) {
    json items = json::array();
    auto result = [&] { return json{{"isIncomplete", false}, {"items", std::move(items)}}; };
    column = std::min<uint32_t>(column, static_cast<uint32_t>(line.size()));
    // Inside a comment: nothing to complete.
    {
        bool in = false;
        for (uint32_t i = 0; i < column; ++i) {
            if (line[i] == '(')
                in = true;
            else if (line[i] == ')')
                in = false;
        }
        if (in) return result();
    }
    const std::string code = strip_comments(line);
    const CallLine cl = find_call(code);
    if (!cl.found || column < cl.name_begin) return result();
    // The keyword must be followed by a blank before a name is completed.
    if (cl.name_begin == cl.name_end && cl.name_begin > 0 && code[cl.name_begin - 1] != ' ' &&
        code[cl.name_begin - 1] != '\t')
        return result();
    const MacroForm form = cl.modin ? MacroForm::Modin : MacroForm::Call;

    if (column <= cl.name_end) {
        macro_name_items(config, programs, form, items);
        return result();
    }

    // Arguments of the macro named on the line.
    const std::string name = upper(std::string_view(code).substr(cl.name_begin, cl.name_end - cl.name_begin));
    const MacroSpec* spec = config.catalog.find(name);
    if (!spec) return result();
    const std::set<std::string> given = given_arguments(code, cl.name_end, column);
    auto is_given = [&](const ArgSpec& a) {
        if (given.count(upper(a.name))) return true;
        for (const auto& al : a.aliases)
            if (given.count(upper(al))) return true;
        return false;
    };
    for (std::size_t i = 0; i < spec->args.size(); ++i) {
        const ArgSpec& a = spec->args[i];
        if (is_given(a)) continue;
        items.push_back({{"label", a.name},
                         {"kind", 5},  // Field
                         {"detail", (a.required() ? "required: " : "") + a.meaning},
                         {"documentation", markdown(argument_doc(*spec, a, 0, nullptr))},
                         {"insertText", a.name + "="},
                         {"filterText", a.name},
                         {"sortText", fmt::format("{}{:03}", a.required() ? 0 : 1, i)}});
    }
    return result();
}

}  // namespace osplint::lsp
