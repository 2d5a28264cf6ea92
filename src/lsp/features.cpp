#include "lsp/features.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "catalog/catalog.h"
#include "catalog/citations.h"
#include "rules/registry.h"
#include "support/embedded.h"
#include "support/text.h"
#include "syntax/directive.h"
#include "syntax/frontend_fast.h"

namespace osplint::lsp {

namespace {

std::string format_number(double v) {
    if (!std::isfinite(v)) return "?";  // never "inf" or "nan" in a hover
    if (v == std::floor(v) && std::fabs(v) < 1e15) return fmt::format("{}", static_cast<long long>(v));
    return fmt::format("{}", v);
}

}  // namespace

json markdown(std::string text) { return json{{"kind", "markdown"}, {"value", std::move(text)}}; }


// --- diagnostics -----------------------------------------------------------

json to_lsp_diagnostic(const Diagnostic& d, const std::string& uri, Encoding enc, int64_t version) {
    auto range = [&](const SourceRange& r) {
        json out(json::value_t::object);
        out["start"] = to_lsp_position(r.start, enc);
        out["end"] = to_lsp_position(r.end, enc);
        return out;
    };
    json out;
    out["range"] = range(d.range);
    out["severity"] = d.severity == Severity::Error ? 1 : d.severity == Severity::Warning ? 2 : 3;
    out["source"] = std::string(kSource);
    std::string message = d.message;
    json related = json::array();
    for (const auto& n : d.notes) {
        if (n.range) {
            related.push_back({{"location", {{"uri", uri}, {"range", range(*n.range)}}}, {"message", n.message}});
        } else {
            message += "\nnote: " + n.message;
        }
    }
    out["message"] = message;
    if (!d.rule.empty()) {
        out["code"] = d.rule;
        if (find_rule(d.rule)) out["codeDescription"] = {{"href", std::string(kRuleDocBase) + d.rule + ".md"}};
    }
    if (!related.empty()) out["relatedInformation"] = std::move(related);
    json fixes = json::array();
    for (const auto& f : d.fixes) {
        json edits = json::array();
        for (const auto& e : f.edits) edits.push_back({{"range", range(e.range)}, {"newText", e.replacement}});
        fixes.push_back({{"title", f.title}, {"safe", f.safe}, {"edits", std::move(edits)}});
    }
    out["data"] = {{"version", version}, {"fixes", std::move(fixes)}};
    return out;
}

namespace {

void key_number(std::string& k, uint32_t n) { k.append(reinterpret_cast<const char*>(&n), sizeof n); }
void key_text(std::string& k, std::string_view t) {
    key_number(k, static_cast<uint32_t>(t.size()));
    k.append(t);
}
void key_position(std::string& k, const Position& p) {
    key_number(k, p.line);
    key_number(k, p.byte_col);
    key_number(k, p.cp_col);
    key_number(k, p.utf16_col);
}
void key_range(std::string& k, const SourceRange& r) {
    key_position(k, r.start);
    key_position(k, r.end);
}

// Everything of a finding to_lsp_diagnostic writes.
std::string text_key(const Diagnostic& d, Encoding enc) {
    std::string k;
    key_number(k, static_cast<uint32_t>(enc));
    key_text(k, d.rule);
    key_number(k, static_cast<uint32_t>(d.severity));
    key_text(k, d.message);
    key_range(k, d.range);
    key_number(k, static_cast<uint32_t>(d.notes.size()));
    for (const Note& n : d.notes) {
        key_text(k, n.message);
        key_number(k, n.range.has_value());
        if (n.range) key_range(k, *n.range);
    }
    key_number(k, static_cast<uint32_t>(d.fixes.size()));
    for (const Fix& f : d.fixes) {
        key_text(k, f.title);
        key_number(k, f.safe);
        key_number(k, static_cast<uint32_t>(f.edits.size()));
        for (const TextEdit& e : f.edits) {
            key_range(k, e.range);
            key_text(k, e.replacement);
        }
    }
    return k;
}

std::string dump(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

}  // namespace

std::string publish_text(const std::string& uri, int64_t version, const std::vector<Diagnostic>& diags, Encoding enc,
                         DiagnosticTexts& texts) {
    // Keys in the order nlohmann::json writes them (sorted), as make_notification's message.
    std::string out = R"({"jsonrpc":"2.0","method":"textDocument/publishDiagnostics","params":{"diagnostics":[)";
    const std::string v = std::to_string(version);
    DiagnosticTexts now;
    now.reserve(diags.size());
    for (size_t i = 0; i < diags.size(); ++i) {
        std::string key = text_key(diags[i], enc);
        auto it = now.find(key);
        if (it == now.end()) {
            auto old = texts.find(key);
            if (old != texts.end()) {
                it = now.emplace(std::move(key), std::move(old->second)).first;
            } else {
                // Written with version 0, then cut there: "version" is the last key of "data".
                const std::string whole = dump(to_lsp_diagnostic(diags[i], uri, enc, 0));
                constexpr std::string_view kVersion = R"("version":0})";
                const size_t at = whole.rfind(kVersion);
                it = now.emplace(std::move(key), std::make_pair(whole.substr(0, at + kVersion.size() - 2),
                                                                whole.substr(at + kVersion.size() - 1)))
                         .first;
            }
        }
        if (i) out += ',';
        out += it->second.first;
        out += v;
        out += it->second.second;
    }
    out += R"(],"uri":)";
    out += dump(json(uri));
    if (version >= 0) {
        out += R"(,"version":)";
        out += v;
    }
    out += "}}";
    texts = std::move(now);
    return out;
}

// --- G and M codes ----------------------------------------------------------

std::optional<std::string_view> code_meaning(std::string_view code) {
    struct Entry {
        std::string_view code, meaning;
    };
    // Meanings as given in the syntax and macro references (SYNTAX.md,
    // MACROS.md): the OSP5020M command-code tables and the fixed-cycle manual.
    static constexpr Entry kCodes[] = {
        {"G0", "Positioning (rapid traverse)"},
        {"G1", "Linear interpolation (cutting feed)"},
        {"G2", "Circular interpolation, clockwise"},
        {"G3", "Circular interpolation, counterclockwise"},
        {"G4", "Dwell (`G4 F` seconds)"},
        {"G10", "Parallel and rotation shift of the coordinate system: cancel"},
        {"G11", "Parallel and rotation shift of the coordinate system (`G11 X Y P`)"},
        {"G15", "Work coordinate system selection, modal (`G15 H n`)"},
        {"G16", "Work coordinate system selection, this block only (`G16 H n`; `H0` = machine coordinates)"},
        {"G17", "Plane selection: X-Y (cycle axis Z)"},
        {"G18", "Plane selection: Z-X (cycle axis Y)"},
        {"G19", "Plane selection: Y-Z (cycle axis X)"},
        {"G20", "Inch data input"},
        {"G21", "Metric (mm) data input"},
        {"G30", "Positioning to home position (`G30 P n`)"},
        {"G40", "Cutter radius compensation cancel"},
        {"G41", "Cutter radius compensation, left (`G41 D n`)"},
        {"G42", "Cutter radius compensation, right (`G42 D n`)"},
        {"G53", "Tool length offset cancel"},
        {"G56", "Tool length offset, Z axis (`G56 H n`)"},
        {"G60", "One-directional positioning (never together with NCYL in the back-counterboring macros)"},
        {"G71", "Fixed cycle: designation of the return level for M53 (`G71 Z`)"},
        {"G77", "Fixed cycle: step & pick cycle"},
        {"G78", "Fixed cycle: variable pick cycle"},
        {"G79", "Fixed cycle: back boring cycle"},
        {"G80", "Fixed cycle cancel"},
        {"G81", "Fixed cycle: drill cycle (spot drill)"},
        {"G82", "Fixed cycle: drill cycle (counterboring, dwell at the bottom)"},
        {"G83", "Fixed cycle: pick cycle (deep-hole drilling)"},
        {"G84", "Fixed cycle: tap cycle"},
        {"G85", "Fixed cycle: boring cycle (reamer)"},
        {"G86", "Fixed cycle: boring cycle"},
        {"G87", "Fixed cycle: step cycle"},
        {"G88", "Fixed cycle: fine boring cycle"},
        {"G89", "Fixed cycle: boring cycle"},
        {"G90", "Absolute programming"},
        {"G91", "Incremental programming"},
        {"G98", "Fixed cycle: return to the initial point (I point)"},
        {"G99", "Fixed cycle: return to the clearance point (R point)"},
        {"G100", "Fixed cycle: drilling ignored for this block only (valid only while a fixed cycle is active)"},
        {"G186", "Fixed cycle: multi-step boring cycle"},
        {"M0", "Program stop"},
        {"M1", "Optional stop"},
        {"M2", "Program end (M02)"},
        {"M3", "Spindle start, clockwise"},
        {"M4", "Spindle start, counterclockwise"},
        {"M5", "Spindle stop"},
        {"M6", "Tool change"},
        {"M7", "Coolant on (M7; the coolant kind is machine-specific)"},
        {"M8", "Coolant on"},
        {"M9", "Coolant off"},
        {"M12", "Coolant on (M12; the coolant kind is machine-specific)"},
        {"M30", "Program end and reset"},
        {"M52", "Fixed cycle return level: upper limit (on a macro's CALL/MODIN line use PM=52)"},
        {"M53", "Fixed cycle return level: the level given by G71 (macros: the PT level)"},
        {"M54", "Fixed cycle return level: the R point"},
        {"M843", "Synchronized tapping: spindle start (instead of M03; alone in its block)"},
        {"M845", "Synchronized tapping: spindle stop (instead of M05; alone in its block)"},
    };
    for (const auto& e : kCodes)
        if (e.code == code) return e.meaning;
    return std::nullopt;
}

// --- hover -----------------------------------------------------------------

namespace {

template <class T, class F>
std::string show(const Val<T>& v, F f) {
    return v.known ? f(v.value) : std::string("unknown");
}

std::string show_plane(const ModalState& s) {
    return show(s.plane, [](Plane p) { return std::string(plane_name(p)); });
}
std::string show_distance(const ModalState& s) {
    return show(s.distance, [](Distance d) { return std::string(d == Distance::Absolute ? "G90" : "G91"); });
}
std::string show_units(const ModalState& s) {
    return show(s.units, [](Units u) { return std::string(u == Units::Mm ? "mm (G21)" : "inch (G20)"); });
}
std::string show_motion(const ModalState& s) {
    return show(s.motion, [](int m) { return "G" + std::to_string(m); });
}
std::string show_cycle(const ModalState& s) {
    return show(s.cycle, [](const std::optional<ActiveCycle>& c) {
        if (!c) return std::string("none");
        return c->macro.empty() ? fmt::format("G{}", c->code) : fmt::format("G{} ({})", c->code, c->macro);
    });
}
std::string show_return(const ModalState& s) {
    return show(s.cycle_return, [](CycleReturn r) { return std::string(r == CycleReturn::Initial ? "G98" : "G99"); });
}
std::string show_level(const ModalState& s) {
    return show(s.return_level, [](int m) { return "M" + std::to_string(m); });
}
std::string show_modin(const ModalState& s) {
    return show(s.modin, [](const std::optional<ActiveModin>& m) {
        return m ? m->macro + " (line " + std::to_string(m->line) + ")" : std::string("none");
    });
}

std::string state_table(const ModalState& before, const ModalState& after) {
    std::string out = "| | in effect at this block | after it |\n|---|---|---|\n";
    auto row = [&](std::string_view name, const std::string& a, const std::string& b) {
        out += fmt::format("| {} | {} | {} |\n", name, a, b);
    };
    row("plane", show_plane(before), show_plane(after));
    row("distance", show_distance(before), show_distance(after));
    row("units", show_units(before), show_units(after));
    row("motion", show_motion(before), show_motion(after));
    row("fixed cycle", show_cycle(before), show_cycle(after));
    row("cycle return", show_return(before), show_return(after));
    row("return level", show_level(before), show_level(after));
    row("MODIN", show_modin(before), show_modin(after));
    return out;
}

std::string role_text(ArgRole r) {
    switch (r) {
        case ArgRole::Position:
            return "positioning-plane coordinate (follows G90/G91)";
        case ArgRole::Cycle:
            return "cycle-axis coordinate";
        case ArgRole::Length:
            return "length or distance";
        case ArgRole::Stroke:
            return "tool or clutch stroke";
        case ArgRole::Shift:
            return "shift for tool insertion/withdrawal or relief";
        case ArgRole::Feed:
            return "feed rate";
        case ArgRole::Speed:
            return "spindle speed";
        case ArgRole::Dwell:
            return "dwell time";
        case ArgRole::Time:
            return "time";
        case ArgRole::CompNumber:
            return "cutter-radius compensation number";
        case ArgRole::MCode:
            return "M code handed to the macro";
        case ArgRole::Vector:
            return "end-point vector component";
        case ArgRole::Pitch:
            return "pitch";
        case ArgRole::Direction:
            return "direction selector";
        case ArgRole::Count:
            return "repeat count";
    }
    return std::string(to_string(r));
}

std::string unit_text(ArgRole r, const ModalState* state) {
    const bool inch = state && state->units.is(Units::Inch);
    switch (r) {
        case ArgRole::Position:
        case ArgRole::Cycle:
        case ArgRole::Length:
        case ArgRole::Stroke:
        case ArgRole::Shift:
        case ArgRole::Vector:
        case ArgRole::Pitch:
            return inch ? "inch" : "mm";
        case ArgRole::Feed:
            return inch ? "inch/min" : "mm/min";
        case ArgRole::Speed:
            return "min⁻¹";
        default:
            return "";
    }
}

std::string omitted_text(const ArgSpec& a) {
    switch (a.omitted) {
        case ArgOmitted::Required:
            return "required (omitting it raises an alarm)";
        case ArgOmitted::Default:
            return "default " + (a.default_text.empty() ? std::string("value") : a.default_text);
        case ArgOmitted::Current:
            return a.default_text.empty() ? "the current value" : "the current value (" + a.default_text + ")";
        case ArgOmitted::None:
            return a.default_text.empty() ? "no value: the related function is not performed" : a.default_text;
        case ArgOmitted::Unknown:
            return "not documented";
    }
    return "?";
}


int plane_number(const ModalState* s) {
    if (!s || !s->plane.known) return 0;
    return plane_number(s->plane.value);
}

std::string rule_doc(std::string_view id) {
    const std::string rule = upper(id);
    if (auto doc = embedded::find("docs/rules/" + rule + ".md")) return std::string(*doc);
    if (const RuleMeta* m = find_rule(rule)) return fmt::format("**{}** `{}`\n\n{}", m->id, m->name, m->summary);
    return fmt::format("`{}` is not an osplint rule (see `osplint rules`).", rule);
}

// The hovered token: `r` contains the offset, or ends at it (cursor just after a word).
bool hits(ByteRange r, uint32_t off) { return r.contains(off) || (!r.empty() && r.end == off); }

json hover_result(std::string text, const SourceText& src, ByteRange r, Encoding enc) {
    return json{{"contents", markdown(std::move(text))}, {"range", to_lsp_range(src, r, enc)}};
}

std::string card_or_note(const Config& config, const DocumentModel& doc, const std::string& name) {
    if (const MacroSpec* spec = config.catalog.find(name)) return config.catalog.render_card(*spec, true);
    for (const auto& p : doc.outline.programs)
        if (p.name == upper(name))
            return fmt::format("**{}**: subprogram defined in this file (line {}).", p.name, p.line);
    return fmt::format("**{}** is not in the macro catalog and not defined in this file.", upper(name));
}

std::optional<json> hover_directive(const SourceText& source, const Block& b, uint32_t off, Encoding enc) {
    const std::string& text = source.text();
    for (const auto& c : b.comments) {
        if (!hits(c.range, off) || c.range.end > text.size()) continue;
        if (!parse_directive(text, c.range).is_directive) return std::nullopt;
        // The alphanumeric run around the offset.
        uint32_t a = std::min(off, c.range.end);
        uint32_t e = a;
        while (a > c.range.begin && is_alnum(text[a - 1])) --a;
        while (e < c.range.end && is_alnum(text[e])) ++e;
        const std::string token = upper(std::string_view(text).substr(a, e - a));
        if (token.size() < 4 || token.compare(0, 3, "OSP") != 0) return std::nullopt;
        if (!std::all_of(token.begin() + 3, token.end(), [](char ch) { return ch >= '0' && ch <= '9'; }))
            return std::nullopt;
        return hover_result(rule_doc(token), source, {a, e}, enc);
    }
    return std::nullopt;
}

}  // namespace

std::string argument_doc(const MacroSpec& spec, const ArgSpec& a, int plane, const ModalState* state) {
    std::string out = fmt::format("**{}**", a.name);
    if (!a.aliases.empty()) {
        std::string al;
        for (const auto& x : a.aliases) al += (al.empty() ? "" : ", ") + x;
        out += " (also " + al + ")";
    }
    out += a.meaning.empty() ? "" : " — " + a.meaning;
    out += fmt::format("\n\nArgument of `{}`{}\n\n", spec.name, spec.title.empty() ? "" : ": " + spec.title);
    out += "- If omitted: " + omitted_text(a) + "\n";
    std::string role = role_text(a.role);
    if (std::string u = unit_text(a.role, state); !u.empty()) role += ", " + u;
    out += "- Role: " + role + "\n";
    if (std::string v = constraint_text(a); !v.empty()) out += "- Values: " + v + "\n";
    const bool has_axis = a.axes[0] || a.axes[1] || a.axes[2];
    if (has_axis) {
        if (plane) {
            if (auto ax = a.axis(plane))
                out += fmt::format("- Axis: **{}** (plane G{} in effect at this block)\n", *ax, plane);
            else
                out += fmt::format("- Axis: none in G{} (the plane in effect at this block)\n", plane);
        } else {
            std::string per;
            for (int p : {17, 18, 19}) {
                auto ax = a.axis(p);
                per += fmt::format("{}G{} {}", per.empty() ? "" : ", ", p, ax ? std::string(1, *ax) : "-");
            }
            out += "- Axis: " + per + (state ? " (the plane at this block is not known)" : "") + "\n";
        }
    }
    if (a.undocumented) out += "- Referenced by the manual but not defined in its argument table\n";
    if (!a.note.empty()) out += "- Note: " + a.note + "\n";
    // Where the manual prints it: the section, never the line; a shop's own
    // source as written.
    std::string where = cite_source(a.source);
    if (where.empty() && !find_manual(std::string_view(a.source).substr(0, a.source.find(':')))) where = a.source;
    if (!where.empty()) out += "- Source: " + where + "\n";
    return out;
}

json hover(const DocumentModel& doc, const BlockRecord* at, const Config& config, uint32_t offset, Encoding enc) {
    const SourceText& src = doc.source();
    const uint32_t line = src.line_of(offset);
    if (line == 0 || line > doc.outline.lines) return nullptr;
    // The block of the line: the walk's record, or the line parsed on its own.
    Block parsed;
    if (!at || at->block.line != line) {
        at = nullptr;
        const uint32_t start = src.line_start(line);
        const std::string_view text = src.line_text(line);
        const uint32_t text_end = start + static_cast<uint32_t>(text.size());
        const uint32_t next = line < src.line_count() ? src.line_start(line + 1) : src.size();
        FastLineParser parser;
        parser.parse(LineRef{text, std::string_view(src.text()).substr(text_end, next - text_end), line, start}, parsed);
    }
    const Block& b = at ? at->block : parsed;
    const BlockRecord* info = at;
    const MacroCall* call = info && info->call ? &*info->call : nullptr;

    // A rule ID inside an `(osplint: disable=...)` comment.
    for (const auto& c : b.comments)
        if (hits(c.range, offset)) {
            if (auto h = hover_directive(src, b, offset, enc)) return *h;
            return nullptr;
        }

    // The macro named after CALL / MODIN.
    for (const auto& st : b.statements) {
        if ((st.kind == StmtKind::Call || st.kind == StmtKind::Modin) && hits(st.name_range, offset))
            return hover_result(card_or_note(config, doc, st.name), src, st.name_range, enc);
    }

    // Words: exact hits first, then a word that ends at the cursor.
    const Word* word = nullptr;
    for (const auto& w : b.words)
        if (w.range.contains(offset)) word = &w;
    if (!word)
        for (const auto& w : b.words)
            if (hits(w.range, offset)) word = &w;
    if (!word) return nullptr;

    const ModalState* before = info ? &info->before : nullptr;
    // An argument of the macro this block invokes.
    if (call && call->spec) {
        for (const auto& a : call->args) {
            if (a.word != word) continue;
            const ArgSpec* spec_arg = call->spec->arg(a.name);
            if (!spec_arg) spec_arg = call->spec->arg_for_address(word->address);
            std::string text;
            if (spec_arg) {
                text = argument_doc(*call->spec, *spec_arg, plane_number(before), before);
            } else {
                text = fmt::format("**{}** is not an argument of `{}` (see its card).", a.name, call->name);
            }
            if (a.value.known) text += fmt::format("\nValue here: `{}`\n", format_number(a.value.value));
            return hover_result(std::move(text), src, word->range, enc);
        }
    }

    if ((word->address == "G" || word->address == "M") && word->number && *word->number >= 0 &&
        *word->number == std::floor(*word->number) && *word->number < 100000) {
        const std::string code = word->address + std::to_string(static_cast<int>(*word->number));
        std::string text;
        const MacroSpec* macro = config.catalog.find_by_code(code);
        if (macro) {
            text = config.catalog.render_card(*macro, true);
        } else {
            auto meaning = code_meaning(code);
            text = fmt::format("**{}** — {}\n", code, meaning ? *meaning : "no description available");
        }
        if (info) text += "\n**Modal state**\n\n" + state_table(info->before, info->after);
        if (!macro && word->address == "G")
            if (const CycleSpec* cy = config.catalog.find_cycle(static_cast<int>(*word->number)))
                text += "\n---\n\n" + config.catalog.render_card(*cy, true);
        return hover_result(std::move(text), src, word->range, enc);
    }
    return nullptr;
}

// --- code actions ----------------------------------------------------------

namespace {

std::string string_field(const json& obj, const char* key) {
    auto it = obj.find(key);
    return it != obj.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// A position or range sent by the client, rebuilt from its numbers (nothing
// else of what the client sent is echoed back); nullopt when malformed.
std::optional<json> clean_position(const json& p) {
    if (!p.is_object()) return std::nullopt;
    auto l = p.find("line");
    auto c = p.find("character");
    if (l == p.end() || c == p.end() || !l->is_number_integer() || !c->is_number_integer()) return std::nullopt;
    if (l->get<int64_t>() < 0 || c->get<int64_t>() < 0) return std::nullopt;
    return json{{"line", l->get<int64_t>()}, {"character", c->get<int64_t>()}};
}

std::optional<json> clean_range(const json& r) {
    if (!r.is_object() || !r.contains("start") || !r.contains("end")) return std::nullopt;
    auto a = clean_position(r["start"]);
    auto b = clean_position(r["end"]);
    if (!a || !b) return std::nullopt;
    return json{{"start", *a}, {"end", *b}};
}

// The diagnostic a code action resolves, as the client showed it.
json clean_diagnostic(const json& d, const json& range) {
    json out = {{"range", range}, {"source", std::string(kSource)}, {"message", string_field(d, "message")}};
    if (d.contains("severity") && d["severity"].is_number_integer()) out["severity"] = d["severity"];
    if (std::string code = string_field(d, "code"); !code.empty()) out["code"] = code;
    return out;
}

}  // namespace

json code_actions(const std::string& uri, const json& params, const SourceText& text, int64_t version, Encoding enc) {
    json actions = json::array();
    const json& context = params.at("context");
    if (!context.is_object()) throw std::invalid_argument("context must be an object");
    if (context.contains("only") && context["only"].is_array()) {
        bool wanted = false;
        for (const auto& k : context["only"])
            if (k.is_string() && (k == "quickfix" || k == "")) wanted = true;
        if (!wanted) return actions;
    }
    if (!context.contains("diagnostics") || !context["diagnostics"].is_array()) return actions;
    std::set<std::pair<std::string, uint32_t>> suppress_done;
    json suppressions = json::array();
    for (const auto& d : context["diagnostics"]) {
        if (!d.is_object() || string_field(d, "source") != kSource || !d.contains("range")) continue;
        const auto range = clean_range(d["range"]);
        if (!range) continue;
        const json diag = clean_diagnostic(d, *range);
        // Quick fixes carried in the diagnostic, when it is for this version.
        if (d.contains("data") && d["data"].is_object()) {
            const json& data = d["data"];
            const bool current = data.contains("version") && data["version"].is_number_integer() &&
                                 data["version"].get<int64_t>() == version;
            if (current && data.contains("fixes") && data["fixes"].is_array()) {
                bool first = true;
                for (const auto& f : data["fixes"]) {
                    if (!f.is_object() || !f.contains("edits") || !f["edits"].is_array()) continue;
                    json edits = json::array();
                    bool ok = true;
                    for (const auto& e : f["edits"]) {
                        auto r = e.is_object() && e.contains("range") ? clean_range(e["range"]) : std::nullopt;
                        if (!r || !e.contains("newText") || !e["newText"].is_string()) {
                            ok = false;
                            break;
                        }
                        edits.push_back({{"range", *r}, {"newText", e["newText"]}});
                    }
                    if (!ok || edits.empty()) continue;
                    std::string title = string_field(f, "title");
                    // The preferred action (applied by "fix all" in editors) is a safe fix only.
                    const bool safe = f.contains("safe") && f["safe"].is_boolean() && f["safe"].get<bool>();
                    actions.push_back({{"title", title.empty() ? std::string("Apply the fix") : title},
                                       {"kind", "quickfix"},
                                       {"diagnostics", json::array({diag})},
                                       {"isPreferred", first && safe},
                                       {"edit", {{"changes", {{uri, std::move(edits)}}}}}});
                    first = false;
                }
            }
        }
        // A suppression comment at the end of the block's line.
        const std::string rule = string_field(d, "code");
        const RuleMeta* meta = builtin_rules().find(rule);
        if (!meta || !meta->suppressible) continue;  // another tool's finding, or one no directive silences
        const uint32_t start = from_lsp_position(text, (*range)["start"], enc);
        const uint32_t line = text.line_of(start);
        if (!suppress_done.insert({rule, line}).second) continue;
        const std::string_view lt = text.line_text(line);
        const uint32_t end_col = enc == Encoding::Utf8 ? static_cast<uint32_t>(lt.size()) : count_columns(lt).utf16;
        const json pos = {{"line", line - 1}, {"character", end_col}};
        suppressions.push_back(
            {{"title", "Suppress " + rule + " on this block"},
             {"kind", "quickfix"},
             {"diagnostics", json::array({diag})},
             {"edit",
              {{"changes",
                {{uri, json::array({{{"range", {{"start", pos}, {"end", pos}}},
                                     {"newText", " (osplint: disable=" + rule + " -- reason)"}}})}}}}}});
    }
    for (auto& a : suppressions) actions.push_back(std::move(a));
    return actions;
}

}  // namespace osplint::lsp
