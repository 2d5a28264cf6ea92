#include "output/writer.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <ostream>
#include <set>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "osplint/osplint.h"
#include "output/html.h"
#include "rules/registry.h"
#include "support/embedded.h"
#include "support/io.h"

namespace fs = std::filesystem;
using ojson = nlohmann::ordered_json;

namespace osplint {

std::optional<Format> parse_format(std::string_view name) {
    if (name == "text") return Format::Text;
    if (name == "json") return Format::Json;
    if (name == "sarif") return Format::Sarif;
    if (name == "gcc") return Format::Gcc;
    if (name == "github") return Format::Github;
    if (name == "html") return Format::Html;
    return std::nullopt;
}

namespace {

// Control characters never reach a terminal or a log: a tab becomes a blank
// (in one-line formats, so do line breaks), anything else U+FFFD.
std::string printable(std::string_view s, bool one_line) {
    std::string out;
    out.reserve(s.size());
    for (unsigned char c : s) {
        if (c == '\t' || (one_line && (c == '\n' || c == '\r'))) out += ' ';
        else if (c < 0x20 || c == 0x7f) out += "\xEF\xBF\xBD";
        else out += static_cast<char>(c);
    }
    return out;
}

const char* color_of(Severity s) {
    switch (s) {
        case Severity::Error: return "\x1b[1;31m";
        case Severity::Warning: return "\x1b[1;33m";
        case Severity::Info: return "\x1b[1;36m";
    }
    return "";
}

// The word each format uses for a severity.
std::string_view level(Severity s, std::string_view info) {
    return s == Severity::Error ? "error" : s == Severity::Warning ? "warning" : info;
}
std::string_view gcc_severity(Severity s) { return level(s, "note"); }
std::string_view github_command(Severity s) { return level(s, "notice"); }
std::string_view sarif_level(Severity s) { return level(s, "note"); }

std::string dump(const ojson& j) { return j.dump(-1, ' ', false, ojson::error_handler_t::replace); }

ojson range_json(const SourceRange& r) {
    return {{"start", {{"line", r.start.line}, {"column", r.start.cp_col + 1}}},
            {"end", {{"line", r.end.line}, {"column", r.end.cp_col + 1}}}};
}

// ------------------------------------------------------------------ text

class TextWriter final : public ReportWriter {
public:
    TextWriter(std::ostream& out, bool color) : out_(out), color_(color) {}
    void begin_file(const std::string& path) override { path_ = path; }
    void diagnostic(Diagnostic&& d) override {
        // The rule's page is pointed at once per run, with its first finding.
        const bool hint = d.rule.rfind("OSP", 0) == 0 && explained_.insert(d.rule).second;
        out_ << render_text_diagnostic(path_, d, color_, hint) << "\n";
    }
    void finish(const Counts& counts) override { out_ << render_summary(counts); }

private:
    std::ostream& out_;
    bool color_;
    std::string path_;
    std::set<std::string> explained_;
};

// ------------------------------------------------------------------- gcc

class GccWriter final : public ReportWriter {
public:
    explicit GccWriter(std::ostream& out) : out_(out) {}
    void begin_file(const std::string& path) override { path_ = printable(path, true); }
    void diagnostic(Diagnostic&& d) override {
        std::string message = d.message;
        if (d.folded) message += fmt::format(" (and {} more like this)", d.folded);
        out_ << fmt::format("{}:{}:{}: {}: {} [{}]\n", path_, d.range.start.line, d.range.start.cp_col + 1,
                            gcc_severity(d.severity), printable(message, true), d.rule);
    }
    void finish(const Counts&) override {}

private:
    std::ostream& out_;
    std::string path_;
};

// ---------------------------------------------------------------- github

class GithubWriter final : public ReportWriter {
public:
    explicit GithubWriter(std::ostream& out) : out_(out) {}
    void begin_file(const std::string& path) override { path_ = github_escape_property(path); }
    void diagnostic(Diagnostic&& d) override {
        std::string props = "file=" + path_;
        props += fmt::format(",line={}", d.range.start.line);
        // Columns only for a range on one line (GitHub ignores them otherwise).
        const bool one_line_range = d.range.end.line == d.range.start.line;
        if (one_line_range) props += fmt::format(",col={}", d.range.start.cp_col + 1);
        props += fmt::format(",endLine={}", d.range.end.line);
        if (one_line_range) props += fmt::format(",endColumn={}", d.range.end.cp_col + 1);
        props += ",title=" + github_escape_property(d.rule);
        std::string message = d.message;
        for (const auto& n : d.notes) {
            message += "\nnote: " + n.message;
            if (n.range && n.range->start.line != d.range.start.line)
                message += fmt::format(" (line {})", n.range->start.line);
        }
        for (const auto& f : d.fixes) message += "\nfix: " + f.title;
        out_ << fmt::format("::{} {}::{}\n", github_command(d.severity), props, github_escape_data(message));
    }
    void finish(const Counts&) override {}

private:
    std::ostream& out_;
    std::string path_;
};

// ------------------------------------------------------------------ json

ojson diagnostic_json(const Diagnostic& d) {
    ojson notes = ojson::array();
    for (const auto& n : d.notes) {
        ojson jn = {{"message", n.message}};
        if (n.range) jn["range"] = range_json(*n.range);
        notes.push_back(std::move(jn));
    }
    ojson fixes = ojson::array();
    for (const auto& f : d.fixes) {
        ojson edits = ojson::array();
        for (const auto& e : f.edits) edits.push_back({{"range", range_json(e.range)}, {"replacement", e.replacement}});
        fixes.push_back({{"title", f.title}, {"safe", f.safe}, {"edits", std::move(edits)}});
    }
    ojson j = {{"rule", d.rule},
               {"name", d.name},
               {"severity", severity_name(d.severity)},
               {"message", d.message},
               {"range", range_json(d.range)},
               {"notes", std::move(notes)},
               {"fixes", std::move(fixes)},
               {"fingerprint", d.fingerprint}};
    if (d.folded) {
        ojson f = {{"count", d.folded}};
        if (d.folded_last) f["last"] = range_json(*d.folded_last);
        j["folded"] = std::move(f);
    }
    return j;
}

// The versioned JSON contract (version 1):
//   {"version": 1, "tool": {...}, "files": [{"path", "diagnostics": [...],
//    "suppressed": [...], "error"?}], "summary": {files, error, warning, info,
//    suppressed, folded}}
class JsonWriter final : public ReportWriter {
public:
    explicit JsonWriter(std::ostream& out) : out_(out) {
        out_ << "{\"version\":1,\"tool\":" << dump(ojson{{"name", "osplint"}, {"version", std::string(version())}})
             << ",\"files\":[";
    }
    bool wants_fingerprints() const override { return true; }
    void begin_file(const std::string& path) override {
        out_ << (files_++ ? ",\n" : "\n") << "{\"path\":" << dump(ojson(path)) << ",\"diagnostics\":[";
        first_ = true;
        suppressed_.clear();
        suppressed_count_ = 0;
    }
    void diagnostic(Diagnostic&& d) override {
        out_ << (first_ ? "\n" : ",\n") << dump(diagnostic_json(d));
        first_ = false;
    }
    void suppressed(SuppressedDiagnostic&& s) override {
        ojson j = diagnostic_json(s.diagnostic);
        ojson how = {{"kind", s.kind == SuppressedDiagnostic::Kind::Baseline ? "baseline" : "inSource"},
                     {"reason", s.reason},
                     {"scope", s.kind == SuppressedDiagnostic::Kind::Baseline ? "baseline"
                               : s.file_scope                                 ? "file"
                                                                              : "block"}};
        if (s.directive) how["directive"] = range_json(*s.directive);
        j["suppression"] = std::move(how);
        suppressed_.append(suppressed_count_++ ? ",\n" : "\n");
        suppressed_.append(dump(j));
    }
    void end_file(const std::string&, const std::string& io_error) override {
        out_ << "],\"suppressed\":[";
        suppressed_.drain([&](std::string_view piece) { out_ << piece; });
        out_ << "]";
        if (!io_error.empty()) out_ << ",\"error\":" << dump(ojson(io_error));
        out_ << "}";
    }
    void finish(const Counts& c) override {
        out_ << "\n],\"summary\":"
             << dump(ojson{{"files", c.files},
                           {"error", c.error},
                           {"warning", c.warning},
                           {"info", c.info},
                           {"suppressed", c.suppressed},
                           {"folded", c.folded},
                           {"fixable", c.fixable},
                           {"unsafe_fixable", c.unsafe_fixable}})
             << "}\n";
    }

private:
    std::ostream& out_;
    size_t files_ = 0;
    bool first_ = true;
    Spool suppressed_;
    size_t suppressed_count_ = 0;
};

// ----------------------------------------------------------------- sarif

std::string percent_encode(std::string_view s) {
    static const char* hex = "0123456789ABCDEF";
    std::string out;
    for (unsigned char c : s) {
        if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
            out += static_cast<char>(c);
        } else {
            out += '%';
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    return out;
}

std::string file_uri(const fs::path& absolute, bool directory) {
    std::string p = absolute.generic_string();
    if (directory && (p.empty() || p.back() != '/')) p += '/';
    if (p.empty() || p.front() != '/') p = "/" + p;
    return "file://" + percent_encode(p);
}

// The paragraph under a heading of a rule doc, on one line.
std::string section(std::string_view doc, std::string_view heading) {
    size_t h = doc.find(heading);
    if (h == std::string_view::npos) return {};
    size_t start = doc.find('\n', h);
    if (start == std::string_view::npos) return {};
    std::string out;
    size_t i = start + 1;
    while (i < doc.size() && doc[i] == '\n') ++i;  // blank lines after the heading
    while (i < doc.size()) {
        size_t e = doc.find('\n', i);
        if (e == std::string_view::npos) e = doc.size();
        std::string_view line = doc.substr(i, e - i);
        if (line.empty() || line.front() == '#') break;
        if (!out.empty()) out += ' ';
        out += line;
        i = e + 1;
    }
    return out;
}

ojson rule_descriptor(const std::string& id, const std::string& name, Severity severity) {
    const RuleMeta* meta = find_rule(id);
    std::string summary = meta ? std::string(meta->summary) : name;
    auto doc = embedded::find("docs/rules/" + id + ".md");
    std::string full = doc ? section(*doc, "## What it does") : std::string();
    if (full.empty()) full = summary;
    // Complete sentences: consumers show these as descriptions.
    auto sentence = [](std::string s) {
        if (!s.empty() && s.back() != '.' && s.back() != '!' && s.back() != '?') s += '.';
        return s;
    };
    ojson help = doc ? ojson{{"text", std::string(*doc)}, {"markdown", std::string(*doc)}}
                     : ojson{{"text", sentence(summary)}, {"markdown", sentence(summary)}};
    ojson config = {{"level", sarif_level(meta ? meta->severity : severity)}};
    if (meta && !meta->enabled_by_default) config["enabled"] = false;
    ojson r = {{"id", id},
               {"name", meta ? std::string(meta->name) : name},
               {"shortDescription", {{"text", sentence(summary)}}},
               {"fullDescription", {{"text", sentence(full)}}},
               {"help", std::move(help)},
               {"defaultConfiguration", std::move(config)},
               {"properties", {{"tags", ojson::array({"osplint"})}}}};
    if (doc) r["helpUri"] = std::string(kProjectUri) + "/blob/main/docs/rules/" + id + ".md";
    return r;
}

ojson region(const SourceRange& r) {
    return {{"startLine", r.start.line},
            {"startColumn", r.start.utf16_col + 1},
            {"endLine", r.end.line},
            {"endColumn", r.end.utf16_col + 1}};
}

// SARIF 2.1.0: one run. The results are written as they come; the run's
// other members (the rules the results use, in the order they first appear,
// and the invocation, which says whether every file could be read) follow
// them (JSON members have no order).
class SarifWriter final : public ReportWriter {
public:
    SarifWriter(std::ostream& out, fs::path root) : out_(out) {
        std::error_code ec;
        root_ = fs::absolute(root, ec).lexically_normal();
        out_ << "{\"$schema\":" << dump(ojson(std::string(kSarifSchema))) << ",\"version\":\"2.1.0\",\"runs\":[{"
             << "\"columnKind\":\"utf16CodeUnits\",\"originalUriBaseIds\":"
             << dump(ojson{{"%SRCROOT%", {{"uri", file_uri(root_, true)}}}}) << ",\"results\":[";
    }
    bool wants_fingerprints() const override { return true; }
    void begin_file(const std::string& path) override {
        bool relative = false;
        artifact_ = {{"uri", sarif_artifact_uri(path, root_, relative)}};
        if (relative) artifact_["uriBaseId"] = "%SRCROOT%";
    }
    void diagnostic(Diagnostic&& d) override { write(d, nullptr); }
    void suppressed(SuppressedDiagnostic&& s) override { write(s.diagnostic, &s); }
    void end_file(const std::string& path, const std::string& io_error) override {
        if (io_error.empty()) return;
        notifications_.push_back({{"level", "error"},
                                  {"message", {{"text", path + ": " + io_error + "."}}},
                                  {"locations", ojson::array({{{"physicalLocation", {{"artifactLocation", artifact_}}}}})}});
    }
    void finish(const Counts&) override {
        ojson rules = ojson::array();
        for (const auto& r : rules_) rules.push_back(rule_descriptor(r.id, r.name, r.severity));
        ojson invocation = {{"executionSuccessful", notifications_.empty()}};
        if (!notifications_.empty()) invocation["toolExecutionNotifications"] = std::move(notifications_);
        invocation["workingDirectory"] = {{"uri", file_uri(root_, true)}};
        ojson driver = {{"name", "osplint"},
                        {"fullName", "osplint, static analyzer for Okuma OSP part programs"},
                        {"version", std::string(version())},
                        {"semanticVersion", std::string(version())},
                        {"informationUri", std::string(kProjectUri)},
                        {"rules", std::move(rules)}};
        out_ << "\n],\"invocations\":" << dump(ojson::array({std::move(invocation)}))
             << ",\"tool\":" << dump(ojson{{"driver", std::move(driver)}}) << "}]}\n";
    }

private:
    struct RuleUse {
        std::string id, name;
        Severity severity;
    };
    size_t rule_index(const Diagnostic& d) {
        auto [it, inserted] = index_.try_emplace(d.rule, rules_.size());
        if (inserted) rules_.push_back({d.rule, d.name, d.severity});
        return it->second;
    }
    ojson location(const SourceRange& range) const {
        return ojson{{"physicalLocation", {{"artifactLocation", artifact_}, {"region", region(range)}}}};
    }
    void write(const Diagnostic& d, const SuppressedDiagnostic* sp) {
        std::string text = d.message;
        ojson related = ojson::array();
        int next_id = 1;
        for (const auto& n : d.notes) {
            text += "\nNote: " + n.message;
            if (n.range)
                related.push_back({{"id", next_id++},
                                   {"message", {{"text", n.message}}},
                                   {"physicalLocation", location(*n.range)["physicalLocation"]}});
        }
        ojson res = {{"ruleId", d.rule},
                     {"ruleIndex", rule_index(d)},
                     {"level", sarif_level(d.severity)},
                     {"message", {{"text", text}}},
                     {"locations", ojson::array({location(d.range)})},
                     {"partialFingerprints", {{std::string(kFingerprintKey), d.fingerprint}}}};
        if (!related.empty()) res["relatedLocations"] = std::move(related);
        if (!d.fixes.empty()) {
            ojson fixes = ojson::array();
            for (const auto& f : d.fixes) {
                ojson replacements = ojson::array();
                for (const auto& e : f.edits)
                    replacements.push_back({{"deletedRegion", region(e.range)}, {"insertedContent", {{"text", e.replacement}}}});
                fixes.push_back({{"description", {{"text", f.title}}},
                                 {"artifactChanges", ojson::array({{{"artifactLocation", artifact_},
                                                                    {"replacements", std::move(replacements)}}})},
                                 {"properties", {{"safe", f.safe}}}});
            }
            res["fixes"] = std::move(fixes);
        }
        if (sp) {
            ojson s = {{"kind", sp->kind == SuppressedDiagnostic::Kind::Baseline ? "external" : "inSource"}};
            if (!sp->reason.empty()) s["justification"] = sp->reason;
            if (sp->directive) s["location"] = location(*sp->directive);
            res["suppressions"] = ojson::array({std::move(s)});
        }
        if (d.folded) res["properties"] = {{"osplintFolded", d.folded}};
        out_ << (results_++ ? ",\n" : "\n") << dump(res);
    }

    std::ostream& out_;
    fs::path root_;
    ojson artifact_;
    size_t results_ = 0;
    std::vector<RuleUse> rules_;
    std::map<std::string, size_t> index_;
    ojson notifications_ = ojson::array();
};

}  // namespace

ShownLine shown_line(std::string_view line, uint32_t start, uint32_t end) {
    // The byte offset of every code point, and of the end.
    std::vector<size_t> at;
    at.reserve(line.size() + 1);
    for (size_t i = 0; i < line.size(); ++i)
        if ((static_cast<unsigned char>(line[i]) & 0xC0) != 0x80) at.push_back(i);
    const auto n = static_cast<uint32_t>(at.size());
    at.push_back(line.size());
    ShownLine out;
    if (start > n) {  // past the text kept of a long line: the line without a caret
        out.text = n > kShownColumns ? std::string(line.substr(0, at[kShownColumns])) + "..." : std::string(line);
        return out;
    }
    end = std::clamp(end, start + 1, std::max(n, start + 1));
    uint32_t from = 0, to = n;
    if (n > kShownColumns) {
        from = start > kShownBefore ? start - kShownBefore : 0;
        to = std::min(n, from + kShownColumns);
        if (to - from < kShownColumns) from = to - kShownColumns;
    }
    const std::string before = from > 0 ? "..." : "";
    out.text = before + std::string(line.substr(at[from], at[to] - at[from])) + (to < n ? "..." : "");
    out.caret = static_cast<uint32_t>(before.size()) + (start - from);
    out.carets = std::max<uint32_t>(1, std::min(end, std::max(to, start + 1)) - start);
    return out;
}

std::string render_text_diagnostic(const std::string& path, const Diagnostic& d, bool color, bool explain_hint) {
    const char* bold = color ? "\x1b[1m" : "";
    const char* reset = color ? "\x1b[0m" : "";
    const char* blue = color ? "\x1b[1;34m" : "";
    std::string out = fmt::format("{}{}:{}:{}:{} {}{}[{}]{}: {}{}{}\n", bold, printable(path, true), d.range.start.line,
                                  d.range.start.cp_col + 1, reset, color ? color_of(d.severity) : "",
                                  severity_name(d.severity), d.rule, reset, bold, printable(d.message, true), reset);
    const std::string num = std::to_string(d.range.start.line);
    const std::string pad(num.size(), ' ');
    const uint32_t start = d.range.start.cp_col;
    const uint32_t end = d.range.end.line == d.range.start.line ? d.range.end.cp_col : start + 1;
    const ShownLine shown = shown_line(printable(d.line_text, true), start, end);
    out += fmt::format("{} {} |{} {}\n", blue, num, reset, shown.text);
    if (shown.carets)
        out += fmt::format("{} {} |{} {}{}{}{}\n", blue, pad, reset, std::string(shown.caret, ' '),
                           color ? color_of(d.severity) : "", std::string(shown.carets, '^'), reset);
    for (const auto& n : d.notes) {
        if (n.range && n.range->start.line != d.range.start.line)
            out += fmt::format("{} {} ={} note: {} (line {})\n", blue, pad, reset, printable(n.message, true),
                               n.range->start.line);
        else
            out += fmt::format("{} {} ={} note: {}\n", blue, pad, reset, printable(n.message, true));
    }
    for (const auto& f : d.fixes)
        out += fmt::format("{} {} ={} fix{}: {}\n", blue, pad, reset, f.safe ? "" : " (unsafe)", printable(f.title, true));
    if (explain_hint)
        out += fmt::format("{} {} ={} (run \"osplint explain {}\" for more)\n", blue, pad, reset, printable(d.rule, true));
    return out;
}

std::string render_summary(const Counts& s) {
    auto plural = [](uint64_t n, const char* word) { return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s"); };
    std::string out = fmt::format("{}, {}, {} in {}", plural(s.error, "error"), plural(s.warning, "warning"),
                                  plural(s.info, "info"), plural(s.files, "file"));
    if (s.folded) out += fmt::format(" ({} of them folded into the findings shown)", s.folded);
    if (s.fixable || s.unsafe_fixable) {
        out += fmt::format("; {} fixable with --fix", s.fixable);
        if (s.unsafe_fixable) out += fmt::format(" ({} more with --unsafe-fixes)", s.unsafe_fixable);
    }
    return out + "\n";
}

namespace {
// GitHub workflow commands: `%`, CR and LF escaped everywhere, and `:` and
// `,` too in a property value.
std::string github_escape(std::string_view s, bool property) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        switch (c) {
            case '%': out += "%25"; break;
            case '\r': out += "%0D"; break;
            case '\n': out += "%0A"; break;
            case ':': out += property ? "%3A" : ":"; break;
            case ',': out += property ? "%2C" : ","; break;
            default: out += c;
        }
    }
    return out;
}
}  // namespace

std::string github_escape_data(std::string_view s) { return github_escape(s, false); }

std::string github_escape_property(std::string_view s) { return github_escape(s, true); }

std::string sarif_artifact_uri(const std::string& path, const fs::path& root, bool& relative) {
    std::error_code ec;
    fs::path abs = fs::absolute(fs::path(path), ec).lexically_normal();
    fs::path base = fs::absolute(root, ec).lexically_normal();
    fs::path rel = abs.lexically_relative(base);
    if (!rel.empty() && *rel.begin() != ".." && rel != ".") {
        relative = true;
        return percent_encode(rel.generic_string());
    }
    relative = false;
    return file_uri(abs, false);
}

std::unique_ptr<ReportWriter> make_writer(Format format, std::ostream& out, const WriterOptions& options) {
    switch (format) {
        case Format::Text: return std::make_unique<TextWriter>(out, options.color);
        case Format::Json: return std::make_unique<JsonWriter>(out);
        case Format::Sarif: return std::make_unique<SarifWriter>(out, options.sarif_root);
        case Format::Gcc: return std::make_unique<GccWriter>(out);
        case Format::Github: return std::make_unique<GithubWriter>(out);
        case Format::Html: return make_html_writer(out, options);
    }
    return nullptr;
}

}  // namespace osplint
