#include "engine/suppress.h"

#include <algorithm>
#include <cctype>
#include <map>

#include <fmt/format.h>

#include "engine/fingerprint.h"
#include "support/text.h"
#include "syntax/source.h"

namespace osplint {

Position position_on_line(uint32_t line, uint32_t line_start, std::string_view text, uint32_t offset) {
    Position p;
    p.line = line;
    p.byte_col = offset - line_start;
    const ColumnCount c = count_columns(text.substr(0, std::min<size_t>(p.byte_col, text.size())));
    p.cp_col = c.cp;
    p.utf16_col = c.utf16;
    return p;
}

namespace {

SourceRange range_on(uint32_t line, uint32_t line_start, std::string_view text, ByteRange r) {
    return SourceRange{r, position_on_line(line, line_start, text, r.begin), position_on_line(line, line_start, text, r.end)};
}

}  // namespace

bool SuppressionFilter::runs(const RuleMeta& meta) const { return rule_runs(meta, config_, only_); }

SuppressionFilter::SuppressionFilter(const FileOutline& outline, const RuleRegistry& rules, const Config& config,
                                     const std::vector<std::string>& only_rules)
    : rules_(rules), config_(config), only_(only_rules) {
    unknown_meta_ = rules.find(kBadSuppressionRule);
    unused_meta_ = rules.find(kUnusedSuppressionRule);
    report_unknown_ = unknown_meta_ && runs(*unknown_meta_);
    report_unused_ = unused_meta_ && runs(*unused_meta_);

    for (const DirectiveSite& site : outline.directives) {
        const size_t li = lines_.size();
        Line l;
        l.line = site.line;
        l.line_start = site.offset;
        l.text = site.text;
        l.program = site.program < outline.programs.size() ? outline.programs[site.program].name : std::string();
        l.target_line = site.target ? site.target_line : 0;
        lines_.push_back(std::move(l));
        const Line& line = lines_.back();
        for (const ByteRange& c : site.comments) {
            DirectiveParse p = parse_directive(line.text, ByteRange{c.begin - line.line_start, c.end - line.line_start});
            if (!p.is_directive) continue;
            auto shift = [&](ByteRange& r) {
                r.begin += line.line_start;
                r.end += line.line_start;
            };
            if (!p.directive) {
                shift(p.error_range);
                if (report_unknown_) make(*unknown_meta_, p.error_range, line, p.error);
                continue;
            }
            shift(p.directive->comment);
            for (auto& id : p.directive->ids) shift(id.range);
            const size_t di = directives_.size();
            directives_.push_back(std::move(*p.directive));
            directive_line_.push_back(li);
            const SuppressionDirective& d = directives_.back();
            const bool file_scope = d.action == SuppressionDirective::Action::DisableFile;
            const uint32_t target = file_scope ? 0 : line.target_line;
            for (size_t k = 0; k < d.ids.size(); ++k) {
                const auto& id = d.ids[k];
                const RuleMeta* meta = rules.resolve(id.text);  // an ID or a name, or a retired one redirected
                if (meta && report_unknown_ && rules.is_retired(id.text))
                    make(*unknown_meta_, id.range, line,
                         fmt::format("'{}' is a retired name of {} ({}): the directive still silences {}, but "
                                     "write its ID",
                                     id.text, meta->id, meta->name, meta->id));
                if (!meta) {
                    if (report_unknown_)
                        make(*unknown_meta_, id.range, line,
                             fmt::format("unknown rule '{}' in suppression: no rule has this ID or name, so the "
                                         "directive silences nothing{} (see `osplint rules`)",
                                         id.text, rules.suggestion(id.text)));
                    continue;
                }
                if (!meta->suppressible) {
                    if (report_unknown_)
                        make(*unknown_meta_, id.range, line,
                             meta->category == RuleCategory::Directive
                                 ? fmt::format("{} ({}) reports on the suppressions themselves and cannot be "
                                               "suppressed by a directive; turn it off in osplint.toml ([rules]) or "
                                               "with --ignore",
                                               meta->id, meta->name)
                                 : fmt::format("{} ({}) cannot be suppressed: a block that does not parse would be "
                                               "passed over silently, and the control rejects it anyway; correct "
                                               "the block",
                                               meta->id, meta->name));
                    continue;
                }
                entries_.push_back({std::string(meta->id), di, k, target, file_scope, false});
            }
        }
    }
}

Diagnostic& SuppressionFilter::make(const RuleMeta& meta, ByteRange range, const Line& l, std::string message) {
    Diagnostic d;
    d.rule = std::string(meta.id);
    d.name = std::string(meta.name);
    d.severity = config_.severity_of(meta.id, meta.severity, meta.enabled_by_default).value_or(meta.severity);
    d.message = std::move(message);
    d.range = range_on(l.line, l.line_start, l.text, range);
    d.line_text = l.text.substr(0, 1000);
    // The directive's text identifies the finding, never its line number.
    std::string key;
    const std::string_view body = std::string_view(l.text).substr(range.begin - l.line_start, range.size());
    for (char c : d.line_text)
        if (!std::isspace(static_cast<unsigned char>(c))) key += c;
    key += '|';
    key += body;
    const std::string full = fmt::format("{}|{}|{}", meta.id, l.program, key);
    int occurrence = 1;
    for (auto& [k, n] : occurrences_)
        if (k == full) occurrence = ++n;
    if (occurrence == 1) occurrences_.emplace_back(full, 1);
    d.fingerprint = make_fingerprint(meta.id, l.program, key, occurrence);
    own_.push_back(std::move(d));
    return own_.back();
}

// Block entries for the finding's line first, then file entries.
const SuppressionFilter::Entry* SuppressionFilter::find(const Diagnostic& d) const {
    if (entries_.empty()) return nullptr;  // (a rule that cannot be suppressed never has an entry)
    for (const auto& e : entries_)
        if (!e.file_scope && e.target_line != 0 && e.target_line == d.range.start.line && e.rule == d.rule) return &e;
    for (const auto& e : entries_)
        if (e.file_scope && e.rule == d.rule) return &e;
    return nullptr;
}

bool SuppressionFilter::covers(const Diagnostic& d) const { return find(d) != nullptr; }

bool SuppressionFilter::silence(Diagnostic& d, SuppressedDiagnostic& out) {
    const Entry* by = find(d);
    if (!by) return false;
    // Every entry that would have silenced it counts as used.
    const bool file_scope = by->file_scope;
    for (auto& e : entries_)
        if (e.rule == d.rule && e.file_scope == file_scope &&
            (file_scope || (e.target_line != 0 && e.target_line == d.range.start.line)))
            e.used = true;
    const SuppressionDirective& dir = directives_[by->directive];
    const Line& l = lines_[directive_line_[by->directive]];
    out.kind = SuppressedDiagnostic::Kind::InSource;
    out.reason = dir.reason;
    out.file_scope = by->file_scope;
    out.directive = range_on(l.line, l.line_start, l.text, dir.comment);
    out.diagnostic = std::move(d);
    return true;
}

std::vector<bool> SuppressionFilter::used() const {
    std::vector<bool> out;
    for (const auto& e : entries_) out.push_back(e.used);
    return out;
}

void SuppressionFilter::set_used(const std::vector<bool>& used) {
    for (size_t i = 0; i < entries_.size() && i < used.size(); ++i) entries_[i].used = used[i];
}

std::vector<Diagnostic> SuppressionFilter::finish() {
    if (report_unused_) {
        for (const auto& e : entries_) {
            if (e.used) continue;
            const SuppressionDirective& dir = directives_[e.directive];
            const Line& l = lines_[directive_line_[e.directive]];
            const auto& id = dir.ids[e.index];
            const RuleMeta* meta = rules_.find(e.rule);
            std::string message;
            if (!runs(*meta))
                message = fmt::format("unused suppression: {} did not run (it is off in the configuration or not "
                                      "selected), so the directive silences nothing",
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
                                      e.rule,
                                      e.target_line == l.line
                                          ? std::string("this block")
                                          : fmt::format("the block it applies to (line {})", e.target_line),
                                      id.text);
            Diagnostic& d = make(*unused_meta_, id.range, l, std::move(message));
            if (!dir.reason.empty()) d.notes.push_back({"reason given: " + dir.reason, std::nullopt});

            // A fix when it is unambiguous: drop the whole directive when nothing in
            // it is needed, or drop this one ID when every other ID is in use.
            size_t others_used = 0, others_total = dir.ids.size() - 1, unused_here = 0, valid_here = 0;
            for (const auto& o : entries_)
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
                // Safe: a comment the control ignores.
                d.fixes.push_back({"Remove the unused directive", {{range_on(l.line, l.line_start, l.text, cut), ""}}, true});
            } else if (all_valid && unused_here == 1 && others_used == others_total && others_total > 0) {
                const ByteRange cut = e.index + 1 < dir.ids.size()
                                          ? ByteRange{id.range.begin, dir.ids[e.index + 1].range.begin}
                                          : ByteRange{dir.ids[e.index - 1].range.end, id.range.end};
                d.fixes.push_back({fmt::format("Remove {} from the directive", id.text),
                                   {{range_on(l.line, l.line_start, l.text, cut), ""}}, true});
            }
        }
    }
    std::vector<Diagnostic> out = std::move(own_);
    own_.clear();
    std::stable_sort(out.begin(), out.end(), diagnostic_less);
    return out;
}

}  // namespace osplint
