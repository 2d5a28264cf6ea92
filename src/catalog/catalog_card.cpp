// A macro's card (`osplint explain NAME` as terminal text, the language
// server's hover as Markdown): its facts, command format, arguments and
// conditions, modes, action sequence, notes and readings, the common rules of
// its manual and the manual's plane table.
#include <algorithm>
#include <set>
#include <utility>

#include "catalog/catalog.h"
#include "catalog/citations.h"

namespace osplint {

namespace {

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

// Where a fact is printed, as a reader can look it up: the section's heading
// when it is in the macro's own manual, the manual and the section otherwise.
// A source of a manual outside the citation table (a shop's own) is kept as
// written.
std::string where(const std::string& manual, std::string_view source) {
    if (source.empty()) return {};
    const ManualSection* s = section_at(source);
    if (!s) {
        // A range over several sections of a known manual: the manual alone
        // (the card names it under "Manual"); a shop's own text as written.
        const Manual* m = find_manual(source.substr(0, source.find(':')));
        if (!m) return std::string(source);
        return m->key == manual ? std::string() : std::string(m->title);
    }
    if (manual_of(*s).key == manual) return cite_heading(s->key);
    return cite(s->key);
}

// " [where]", or "" when there is nothing to say.
std::string where_suffix(const std::string& manual, std::string_view source) {
    std::string w = where(manual, source);
    return w.empty() ? w : " [" + w + "]";
}

// The manual as a title: "Fixed cycles manual (OG84L, 2001-12-30)".
std::string manual_title(const std::string& manual) {
    const Manual* m = find_manual(manual);
    if (!m) return manual;
    std::string extra = std::string(m->program);
    if (!m->date.empty()) extra += (extra.empty() ? "" : ", ") + std::string(m->date);
    return std::string(m->title) + (extra.empty() ? "" : " (" + extra + ")");
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
    if (!st.when.empty()) s += " (when " + st.when.text() + ")";
    if (st.inferred) s += " (target inferred)";
    return s;
}

std::string relation_text(const std::string& manual, const Relation& rel) {
    std::string s = rel.left + " " + rel.op + " " + rel.right;
    if (rel.plane) s += " in G" + std::to_string(rel.plane);
    if (!rel.when.empty()) s += " when " + rel.when.text();
    if (rel.inferred) s += " (inferred)";
    s += where_suffix(manual, rel.source);
    if (!rel.note.empty()) s += ": " + rel.note;
    return s;
}

std::string at_least_one_text(const std::string& manual, const AtLeastOne& r) {
    std::string s = "at least one of ";
    for (std::size_t i = 0; i < r.args.size(); ++i) s += (i ? ", " : "") + r.args[i];
    if (r.plane) s += " in G" + std::to_string(r.plane);
    if (r.inferred) s += " (inferred)";
    s += where_suffix(manual, r.source);
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

// ---------------------------------------------------------------------------
// The sections of a card

// The G/M codes registered to `macro` ("G114").
std::string codes_of(const Catalog& catalog, const std::string& macro) {
    std::string s;
    for (const auto& [code, name] : catalog.registrations())
        if (name == macro) s += (s.empty() ? "" : ", ") + code;
    return s;
}

// The title and the facts: family, manual, forms, registrations, cancel.
void card_facts(Card& card, const Catalog& catalog, const MacroSpec& spec) {
    const bool cycle = spec.kind == SpecKind::FixedCycle;
    card.title(spec.name, spec.title);
    if (card.md()) card.line("");
    std::vector<std::pair<std::string, std::string>> facts;
    if (!spec.family.empty()) facts.emplace_back("Family", spec.family);
    if (!spec.manual.empty()) {
        std::string w = where(spec.manual, spec.source);
        facts.emplace_back("Manual", manual_title(spec.manual) + (w.empty() ? "" : ", " + w));
    }
    if (!cycle) facts.emplace_back("Forms", join_forms(spec.forms));
    if (std::string r = codes_of(catalog, spec.name); !r.empty()) facts.emplace_back("Registered to", r);
    if (!spec.cancel.empty()) {
        std::string r = codes_of(catalog, spec.cancel);
        facts.emplace_back("Cancel", spec.cancel + (r.empty() ? "" : " (" + r + ")"));
    }
    if (!spec.cancels.empty()) facts.emplace_back("Cancels", spec.cancels);
    if (!spec.origin.empty() && spec.origin != "data/macros.toml") facts.emplace_back("Defined in", spec.origin);
    card.facts(facts);
}

// Command format: printed lines, then the G-code macro form when it differs.
void card_format(Card& card, const MacroSpec& spec) {
    const bool md = card.md();
    bool gcode_printed = false;
    if (spec.gcode_form)
        for (const auto& f : spec.formats) gcode_printed = gcode_printed || f.text == spec.gcode_form->text;
    if (spec.formats.empty() && !spec.gcode_form) return;
    card.heading("Format");
    std::vector<std::string> lines;
    for (const auto& f : spec.formats) {
        std::string w = where(spec.manual, f.source);
        lines.push_back(f.text + (w.empty() ? "" : "    (" + w + ")"));
    }
    if (spec.gcode_form && !gcode_printed) {
        std::string w = where(spec.manual, spec.gcode_form->source);
        lines.push_back(spec.gcode_form->text + "    (G-code macro form" + (w.empty() ? "" : ", " + w) + ")");
    }
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
void card_arguments(Card& card, const MacroSpec& spec) {
    if (!spec.args_documented && spec.args.empty()) {
        card.heading("Arguments");
        card.para("Not documented in the manuals; any address is accepted.");
    } else {
        card.heading(card.md() ? "Arguments" : "Arguments (machine axis in G17/G18/G19)");
        std::vector<std::vector<std::string>> rows;
        for (const auto& a : spec.args) {
            std::string name = a.name;
            for (const auto& al : a.aliases) name += "/" + al;
            if (a.undocumented) name += " (undocumented)";
            std::string meaning = a.meaning;
            if (!a.note.empty()) meaning += " (" + a.note + ")";
            // The argument list itself goes unsaid; a note or a step elsewhere is named.
            if (std::string w = where(spec.manual, a.source);
                !w.empty() && w.find("Argument list\"") == std::string::npos)
                meaning += " [" + w + "]";
            std::string values = constraint_text(a);
            if (values.empty()) values = "any";
            rows.push_back({name, omitted_text(a), values, axis_cell(a.axes[0]), axis_cell(a.axes[1]),
                            axis_cell(a.axes[2]), format_status_text(spec, a), meaning});
        }
        card.table({"Arg", "If omitted", "Values", "G17", "G18", "G19", "Format", "Meaning"}, rows, {0});
    }
    std::vector<std::string> conditions;
    for (const auto& r : spec.at_least_one) conditions.push_back(at_least_one_text(spec.manual, r));
    for (const auto& rel : spec.relations) conditions.push_back(relation_text(spec.manual, rel));
    if (!conditions.empty()) {
        card.heading("Conditions");
        card.bullets(conditions);
    }
}

// Modes: mm only, G91, M52/M53, G60 with NCYL, common variables, Q repeat.
std::vector<std::pair<std::string, std::string>> modes_of(const MacroSpec& spec) {
    std::vector<std::pair<std::string, std::string>> modes;
    if (spec.kind == SpecKind::FixedCycle) {
        modes.emplace_back("Required arguments", "on the block that starts the cycle (modal within the cycle)");
        if (spec.tapping) modes.emplace_back("Tapping cycle", "yes");
    } else {
        modes.emplace_back("mm only", spec.units == MacroUnits::MmOnly ? "yes" : "not stated");
        modes.emplace_back(spec.g91 == G91Mode::Unsupported ? "G91 mode" : "Cycle axis under G91",
                           spec.g91 == G91Mode::Unsupported         ? "not usable (wrong motion, no alarm)"
                           : spec.g91 == G91Mode::CycleAxisAbsolute ? "absolute: from the workpiece origin even in G91"
                                                                    : "follows G90/G91 as with fixed cycles");
        modes.emplace_back("M52 on the call line", m52_text(spec.m52));
        modes.emplace_back("M53", m53_text(spec.m53));
        modes.emplace_back("G60 with NCYL",
                           spec.has(Hazard::G60NcylCollision) ? "forbidden (collision)" : "not restricted");
        modes.emplace_back("VC120-VC128",
                           spec.has(Hazard::OverwritesVc120To128) ? "overwritten by the macro" : "not used");
        modes.emplace_back("Q repeat count", spec.has(Hazard::RepeatCountAbnormal)
                                                 ? "unsafe (abnormal from the 2nd call)"
                                                 : "not restricted");
        if (spec.tapping) modes.emplace_back("Tapping cycle", "yes");
        if (spec.required_scope == RequiredScope::CycleStart)
            modes.emplace_back("Required arguments", "on the block that starts the cycle");
    }
    return modes;
}

std::string with_source(const std::string& manual, const CatalogNote& n) { return n.text + where_suffix(manual, n.source); }

// The action sequence, the notes and the readings taken.
void card_action_and_notes(Card& card, const MacroSpec& spec) {
    if (!spec.action.empty()) {
        card.heading("Action sequence");
        std::vector<std::pair<std::string, std::string>> steps;
        for (const auto& st : spec.action) steps.emplace_back(st.step, st.text + step_suffix(st));
        card.labelled(steps);
    }
    if (!spec.notes.empty()) {
        card.heading("Notes");
        std::vector<std::string> items;
        for (const auto& n : spec.notes) items.push_back(with_source(spec.manual, n));
        card.bullets(items);
    }
    if (!spec.readings.empty()) {
        card.heading("Readings");
        std::vector<std::string> items;
        for (const auto& rd : spec.readings) {
            std::string text = (rd.open ? "(open, configurable) " : "") + rd.issue + (rd.issue.empty() ? "" : " ") +
                               "Reading: " + rd.reading;
            if (!rd.override_hint.empty()) text += " To take the other reading: " + rd.override_hint;
            items.push_back(text);
        }
        card.bullets(items);
    }
}

// The common rules of the macro's manual.
void card_common_rules(Card& card, const Catalog& catalog, const MacroSpec& spec) {
    const CommonRules* common = spec.common.empty() ? nullptr : catalog.common_rules(spec.common);
    if (!common) return;
    card.heading(common->title.empty() ? "Common rules" : common->title);
    std::vector<std::string> items;
    for (const auto& n : common->notes) items.push_back(with_source(spec.manual, n));
    for (const auto& rd : common->readings)
        items.push_back("Reading: " + rd.issue + (rd.issue.empty() ? "" : " ") + rd.reading);
    card.bullets(items);
}

// The manual's plane table as printed, with the reading taken.
void card_plane_table(Card& card, const Catalog& catalog, const MacroSpec& spec) {
    const bool md = card.md();
    const PlaneTable* pt = spec.plane_table.empty() ? nullptr : catalog.plane_table(spec.plane_table);
    if (!pt) return;
    card.heading("Plane table" + where_suffix(spec.manual, pt->source));
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

}  // namespace

std::string Catalog::render_card(const MacroSpec& spec, bool md) const {
    Card card(md);
    card_facts(card, *this, spec);
    card_format(card, spec);
    card_arguments(card, spec);
    card.heading("Modes");
    card.facts(modes_of(spec));
    card_action_and_notes(card, spec);
    card_common_rules(card, *this, spec);
    card_plane_table(card, *this, spec);
    return card.take();
}

}  // namespace osplint
