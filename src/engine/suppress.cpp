#include "engine/suppress.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

#include "rules/registry.h"

namespace osplint {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

std::string upper(std::string_view s) {
    std::string out(s);
    for (auto& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

// A cursor over the inside of one comment, with absolute offsets.
class Reader {
public:
    Reader(std::string_view text, uint32_t begin, uint32_t end) : text_(text), pos_(begin), end_(end) {}

    void skip_blanks() {
        while (pos_ < end_ && is_blank(text_[pos_])) ++pos_;
    }
    bool at_end() const { return pos_ >= end_; }
    uint32_t pos() const { return pos_; }
    char peek() const { return at_end() ? '\0' : text_[pos_]; }
    bool starts_with(std::string_view s) const {
        return end_ - pos_ >= s.size() && text_.substr(pos_, s.size()) == s;
    }
    bool take(char c) {
        if (peek() != c) return false;
        ++pos_;
        return true;
    }
    // Letters, digits, '_' and single '-' (a "--" ends the token: it starts the reason).
    ByteRange token() {
        uint32_t b = pos_;
        while (!at_end()) {
            char c = text_[pos_];
            if (c == '-' && starts_with("--")) break;
            if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) break;
            ++pos_;
        }
        return {b, pos_};
    }
    std::string_view slice(ByteRange r) const { return text_.substr(r.begin, r.size()); }
    void to_end() { pos_ = end_; }
    uint32_t end() const { return end_; }

private:
    std::string_view text_;
    uint32_t pos_, end_;
};


// Rules that ran in this analysis, by the same logic as analyze().
bool rule_ran(const RuleMeta& m, const Config& config, const AnalysisOptions& options) {
    if (!options.only_rules.empty())
        return std::find(options.only_rules.begin(), options.only_rules.end(), m.id) != options.only_rules.end();
    return config.severity_of(m.id, m.severity, m.enabled_by_default).has_value();
}

Severity severity_for(const RuleMeta& m, const Config& config) {
    return config.severity_of(m.id, m.severity, m.enabled_by_default).value_or(m.severity);
}

// One rule ID of one directive that names a rule a directive can silence.
struct Entry {
    std::string rule;
    size_t directive = 0;      // index into the directives
    size_t index = 0;          // position in the directive's ID list
    uint32_t target_line = 0;  // the line it silences; 0: none (or file scope)
    bool file_scope = false;
    bool used = false;
};

// Finds the program name of a block (for fingerprints).
std::string_view program_of(const ProgramFile& file, uint32_t block) {
    for (const auto& p : file.programs)
        if (block >= p.first_block && block < p.end_block) return p.name;
    return {};
}

}  // namespace

bool suppression_target(const Block& b) {
    return b.kind == LineKind::Block && (!b.is_empty() || !b.errors.empty());
}

DirectiveParse parse_directive(std::string_view text, ByteRange comment) {
    DirectiveParse out;
    if (comment.end > text.size() || comment.empty() || text[comment.begin] != '(') return out;
    uint32_t inner_end = comment.end;
    if (text[inner_end - 1] == ')' && inner_end - 1 > comment.begin) --inner_end;
    Reader r(text, comment.begin + 1, inner_end);
    r.skip_blanks();
    ByteRange head = r.token();
    if (!iequals(r.slice(head), "osplint")) return out;
    r.skip_blanks();
    if (!r.take(':')) return out;
    out.is_directive = true;
    auto fail = [&](std::string message, ByteRange where) {
        out.error = std::move(message);
        out.error_range = where.empty() ? ByteRange{where.begin, std::min(where.begin + 1, comment.end)} : where;
        return out;
    };

    SuppressionDirective d;
    d.comment = comment;
    r.skip_blanks();
    ByteRange action = r.token();
    std::string_view act = r.slice(action);
    if (iequals(act, "disable")) {
        d.action = SuppressionDirective::Action::Disable;
    } else if (iequals(act, "disable-file")) {
        d.action = SuppressionDirective::Action::DisableFile;
    } else if (act.empty()) {
        return fail("malformed osplint directive: expected disable=<rule IDs> or disable-file=<rule IDs>",
                    {r.pos(), r.pos()});
    } else {
        return fail(fmt::format("unknown osplint directive '{}': the directives are disable=<rule IDs> and "
                                "disable-file=<rule IDs>",
                                act),
                    action);
    }
    r.skip_blanks();
    if (!r.take('='))
        return fail(fmt::format("malformed osplint directive: expected '=' and rule IDs after '{}'", act),
                    {r.pos(), r.pos()});
    while (true) {
        r.skip_blanks();
        ByteRange id = r.token();
        if (id.empty()) {
            return fail("malformed osplint directive: expected a rule ID such as OSP104", {r.pos(), r.pos()});
        }
        d.ids.push_back({std::string(r.slice(id)), id});
        r.skip_blanks();
        if (!r.take(',')) break;
    }
    if (r.starts_with("--")) {
        r.take('-');
        r.take('-');
        r.skip_blanks();
        uint32_t b = r.pos();
        uint32_t e = r.end();
        while (e > b && is_blank(text[e - 1])) --e;
        d.reason = std::string(text.substr(b, e - b));
        r.to_end();
    }
    if (!r.at_end()) {
        uint32_t b = r.pos();
        ByteRange junk = r.token();
        if (junk.empty()) junk = {b, b + 1};
        return fail(fmt::format("malformed osplint directive: unexpected '{}': separate rule IDs with ',' and "
                                "write the reason after '--'",
                                r.slice(junk)),
                    junk);
    }
    out.directive = std::move(d);
    return out;
}

SuppressionResult apply_suppressions(const ProgramFile& file, std::vector<Diagnostic> diagnostics,
                                     const Config& config, const AnalysisOptions& options) {
    // The lines with directives; blocks are lines.
    std::vector<DirectiveLine> lines;
    const std::string& text = file.source.text();
    for (uint32_t bi = 0; bi < file.blocks.size(); ++bi) {
        const Block& b = file.blocks[bi];
        bool any = false;
        for (const auto& c : b.comments)
            if (parse_directive(text, c.range).is_directive) any = true;
        if (!any) continue;
        DirectiveLine l;
        l.line = b.line;
        l.line_start = file.source.line_start(b.line);
        l.text = std::string(file.source.line_text(b.line));
        l.program = std::string(program_of(file, bi));
        for (size_t j = bi; j < file.blocks.size(); ++j)
            if (suppression_target(file.blocks[j])) {
                l.target_line = file.blocks[j].line;
                break;
            }
        for (const auto& c : b.comments) l.comments.push_back(c.range);
        lines.push_back(std::move(l));
    }
    return apply_directive_lines(lines, std::move(diagnostics), config, options);
}

namespace {

// A position on a directive's line.
Position position_on(const DirectiveLine& l, uint32_t offset) {
    Position p;
    p.line = l.line;
    p.byte_col = offset - l.line_start;
    const ColumnCount c = count_columns(std::string_view(l.text).substr(0, std::min<size_t>(p.byte_col, l.text.size())));
    p.cp_col = c.cp;
    p.utf16_col = c.utf16;
    return p;
}
SourceRange range_on(const DirectiveLine& l, ByteRange r) { return SourceRange{r, position_on(l, r.begin), position_on(l, r.end)}; }

}  // namespace

SuppressionResult apply_directive_lines(const std::vector<DirectiveLine>& lines, std::vector<Diagnostic> diagnostics,
                                        const Config& config, const AnalysisOptions& options) {
    SuppressionResult out;
    const RuleMeta* unknown_meta = find_rule("OSP901");
    const RuleMeta* unused_meta = find_rule("OSP902");
    const bool report_unknown = unknown_meta && rule_ran(*unknown_meta, config, options);
    const bool report_unused = unused_meta && rule_ran(*unused_meta, config, options);

    std::vector<SuppressionDirective> directives;
    std::vector<size_t> directive_line;  // index into lines
    std::vector<Entry> entries;
    std::vector<Diagnostic> own;  // OSP901 / OSP902 findings
    std::map<std::string, int> occurrences;

    auto make = [&](const RuleMeta& meta, ByteRange range, const DirectiveLine& l, std::string message) -> Diagnostic& {
        Diagnostic d;
        d.rule = std::string(meta.id);
        d.name = std::string(meta.name);
        d.severity = severity_for(meta, config);
        d.message = std::move(message);
        d.range = range_on(l, range);
        d.line_text = l.text.substr(0, 1000);
        // The directive's text identifies the finding, never its line number.
        std::string key;
        const std::string_view body = std::string_view(l.text).substr(range.begin - l.line_start, range.size());
        for (char c : d.line_text)
            if (!std::isspace(static_cast<unsigned char>(c))) key += c;
        key += '|';
        key += body;
        const int occurrence = ++occurrences[fmt::format("{}|{}|{}", meta.id, l.program, key)];
        d.fingerprint = make_fingerprint(meta.id, l.program, key, occurrence);
        own.push_back(std::move(d));
        return own.back();
    };

    for (size_t li = 0; li < lines.size(); ++li) {
        const DirectiveLine& l = lines[li];
        for (const ByteRange& c : l.comments) {
            DirectiveParse p = parse_directive(l.text, ByteRange{c.begin - l.line_start, c.end - l.line_start});
            if (!p.is_directive) continue;
            auto shift = [&](ByteRange& r) {
                r.begin += l.line_start;
                r.end += l.line_start;
            };
            if (!p.directive) {
                shift(p.error_range);
                if (report_unknown) make(*unknown_meta, p.error_range, l, p.error);
                continue;
            }
            shift(p.directive->comment);
            for (auto& id : p.directive->ids) shift(id.range);
            const size_t di = directives.size();
            directives.push_back(std::move(*p.directive));
            directive_line.push_back(li);
            const SuppressionDirective& d = directives.back();
            const bool file_scope = d.action == SuppressionDirective::Action::DisableFile;
            const uint32_t target = file_scope ? 0 : l.target_line;
            for (size_t k = 0; k < d.ids.size(); ++k) {
                const auto& id = d.ids[k];
                std::string rule = upper(id.text);
                const RuleMeta* meta = find_rule(rule);
                if (!meta) {
                    if (!report_unknown) continue;
                    const RuleMeta* by_name = nullptr;
                    for (const auto& m : all_rules())
                        if (iequals(m.name, id.text)) by_name = &m;
                    if (by_name)
                        make(*unknown_meta, id.range, l,
                             fmt::format("'{}' is the name of {}: suppressions name rules by ID, write {}", id.text,
                                         by_name->id, by_name->id));
                    else
                        make(*unknown_meta, id.range, l,
                             fmt::format("unknown rule '{}' in suppression: no rule has this ID, so the directive "
                                         "silences nothing (see `osplint rules`)",
                                         id.text));
                    continue;
                }
                if (meta->id == "OSP001") {
                    if (report_unknown)
                        make(*unknown_meta, id.range, l,
                             "OSP001 (syntax-error) cannot be suppressed: a block that does not parse would be "
                             "passed over silently, and the control rejects it anyway; correct the block");
                    continue;
                }
                if ((unknown_meta && meta->id == unknown_meta->id) || (unused_meta && meta->id == unused_meta->id)) {
                    if (report_unknown)
                        make(*unknown_meta, id.range, l,
                             fmt::format("{} ({}) reports on the suppressions themselves and cannot be suppressed "
                                         "by a directive; turn it off in osplint.toml ([rules]) or with --ignore",
                                         meta->id, meta->name));
                    continue;
                }
                entries.push_back({std::string(meta->id), di, k, target, file_scope, false});
            }
        }
    }

    // Silence the findings the directives cover. OSP001 always stays.
    for (auto& d : diagnostics) {
        if (d.rule == "OSP001" || entries.empty()) {
            out.diagnostics.push_back(std::move(d));
            continue;
        }
        Entry* by = nullptr;
        for (auto& e : entries)
            if (!e.file_scope && e.target_line != 0 && e.target_line == d.range.start.line && e.rule == d.rule) {
                e.used = true;
                if (!by) by = &e;
            }
        if (!by)
            for (auto& e : entries)
                if (e.file_scope && e.rule == d.rule) {
                    e.used = true;
                    if (!by) by = &e;
                }
        if (!by) {
            out.diagnostics.push_back(std::move(d));
            continue;
        }
        const SuppressionDirective& dir = directives[by->directive];
        SuppressedDiagnostic s;
        s.kind = SuppressedDiagnostic::Kind::InSource;
        s.reason = dir.reason;
        s.file_scope = by->file_scope;
        s.directive = range_on(lines[directive_line[by->directive]], dir.comment);
        s.diagnostic = std::move(d);
        out.suppressed.push_back(std::move(s));
    }

    if (report_unused) {
        for (const auto& e : entries) {
            if (e.used) continue;
            const SuppressionDirective& dir = directives[e.directive];
            const DirectiveLine& l = lines[directive_line[e.directive]];
            const auto& id = dir.ids[e.index];
            const RuleMeta* meta = find_rule(e.rule);
            std::string message;
            if (!rule_ran(*meta, config, options))
                message = fmt::format("unused suppression: {} did not run (it is off in the configuration or not selected), so "
                                      "the directive silences nothing",
                                      e.rule);
            else if (e.file_scope)
                message = fmt::format("unused suppression: no {} finding in this file to silence; remove {} from "
                                      "the directive",
                                      e.rule, id.text);
            else if (e.target_line == 0)
                message = fmt::format("unused suppression: no block follows this directive, so {} is silenced "
                                      "nowhere",
                                      id.text);
            else
                message = fmt::format("unused suppression: no {} finding on {} to silence; remove {} from the "
                                      "directive",
                                      e.rule, e.target_line == l.line
                                                  ? std::string("this block")
                                                  : fmt::format("the block it applies to (line {})", e.target_line),
                                      id.text);
            Diagnostic& d = make(*unused_meta, id.range, l, std::move(message));
            if (!dir.reason.empty()) d.notes.push_back({"reason given: " + dir.reason, std::nullopt});

            // A fix when it is unambiguous: drop the whole directive when nothing in
            // it is needed, or drop this one ID when every other ID is in use.
            size_t others_used = 0, others_total = dir.ids.size() - 1, unused_here = 0;
            size_t valid_here = 0;
            for (const auto& o : entries)
                if (o.directive == e.directive) {
                    ++valid_here;
                    if (o.used) {
                        if (o.index != e.index) ++others_used;
                    } else {
                        ++unused_here;
                    }
                }
            const bool all_valid = valid_here == dir.ids.size();
            if (all_valid && unused_here == dir.ids.size()) {
                uint32_t b = dir.comment.begin;
                while (b > l.line_start && is_blank(l.text[b - 1 - l.line_start])) --b;
                const ByteRange cut{b, dir.comment.end};
                d.fixes.push_back({"Remove the unused directive", {{range_on(l, cut), ""}}});
            } else if (all_valid && unused_here == 1 && others_used == others_total && others_total > 0) {
                const ByteRange cut = e.index + 1 < dir.ids.size()
                                          ? ByteRange{id.range.begin, dir.ids[e.index + 1].range.begin}
                                          : ByteRange{dir.ids[e.index - 1].range.end, id.range.end};
                d.fixes.push_back({fmt::format("Remove {} from the directive", id.text), {{range_on(l, cut), ""}}});
            }
        }
    }

    for (auto& d : own) out.diagnostics.push_back(std::move(d));
    std::stable_sort(out.diagnostics.begin(), out.diagnostics.end(), diagnostic_less);
    std::stable_sort(out.suppressed.begin(), out.suppressed.end(),
                     [](const SuppressedDiagnostic& a, const SuppressedDiagnostic& b) {
                         return diagnostic_less(a.diagnostic, b.diagnostic);
                     });
    return out;
}

}  // namespace osplint
