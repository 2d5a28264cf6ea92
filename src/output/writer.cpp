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
#include "output/json_text.h"
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

void range_members(JsonText& j, const SourceRange& r) {
    j.begin_object();
    j.key("start").begin_object().key("line").value(r.start.line).key("column").value(r.start.cp_col + 1).end_object();
    j.key("end").begin_object().key("line").value(r.end.line).key("column").value(r.end.cp_col + 1).end_object();
    j.end_object();
}

// A finding's members in the JSON report, written into the object open in `j`.
void diagnostic_members(JsonText& j, const Diagnostic& d) {
    j.key("rule").value(d.rule).key("name").value(d.name).key("severity").value(severity_name(d.severity));
    j.key("message").value(d.message);
    range_members(j.key("range"), d.range);
    j.key("notes").begin_array();
    for (const auto& n : d.notes) {
        j.begin_object().key("message").value(n.message);
        if (n.range) range_members(j.key("range"), *n.range);
        j.end_object();
    }
    j.end_array();
    j.key("fixes").begin_array();
    for (const auto& f : d.fixes) {
        j.begin_object().key("title").value(f.title).key("safe").value(f.safe).key("edits").begin_array();
        for (const auto& e : f.edits) {
            j.begin_object();
            range_members(j.key("range"), e.range);
            j.key("replacement").value(e.replacement).end_object();
        }
        j.end_array().end_object();
    }
    j.end_array();
    j.key("fingerprint").value(d.fingerprint);
    if (d.folded) {
        j.key("folded").begin_object().key("count").value(d.folded);
        if (d.folded_last) range_members(j.key("last"), *d.folded_last);
        j.end_object();
    }
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
        text_.assign(first_ ? "\n" : ",\n");
        JsonText j(text_);
        j.begin_object();
        diagnostic_members(j, d);
        j.end_object();
        out_ << text_;
        first_ = false;
    }
    void suppressed(SuppressedDiagnostic&& s) override {
        text_.assign(suppressed_count_++ ? ",\n" : "\n");
        JsonText j(text_);
        j.begin_object();
        diagnostic_members(j, s.diagnostic);
        j.key("suppression").begin_object();
        j.key("kind").value(s.kind == SuppressedDiagnostic::Kind::Baseline ? "baseline" : "inSource");
        j.key("reason").value(s.reason);
        j.key("scope").value(s.kind == SuppressedDiagnostic::Kind::Baseline ? "baseline"
                             : s.file_scope                                 ? "file"
                                                                            : "block");
        if (s.directive) range_members(j.key("directive"), *s.directive);
        j.end_object().end_object();
        suppressed_.append(text_);
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
    std::string text_;  // the finding being written (its capacity kept from one to the next)
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
        artifact_text_ = dump(artifact_);
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
    void region(JsonText& j, const SourceRange& r) const {
        j.begin_object().key("startLine").value(r.start.line).key("startColumn").value(r.start.utf16_col + 1);
        j.key("endLine").value(r.end.line).key("endColumn").value(r.end.utf16_col + 1).end_object();
    }
    void physical_location(JsonText& j, const SourceRange& range) const {
        j.begin_object().key("artifactLocation").raw(artifact_text_);
        region(j.key("region"), range);
        j.end_object();
    }
    void write(const Diagnostic& d, const SuppressedDiagnostic* sp) {
        std::string message = d.message;
        for (const auto& n : d.notes) message += "\nNote: " + n.message;
        text_.assign(results_++ ? ",\n" : "\n");
        JsonText j(text_);
        j.begin_object().key("ruleId").value(d.rule).key("ruleIndex").value(uint64_t{rule_index(d)});
        j.key("level").value(sarif_level(d.severity));
        j.key("message").begin_object().key("text").value(message).end_object();
        j.key("locations").begin_array().begin_object();
        physical_location(j.key("physicalLocation"), d.range);
        j.end_object().end_array();
        j.key("partialFingerprints").begin_object().key(kFingerprintKey).value(d.fingerprint).end_object();
        if (std::any_of(d.notes.begin(), d.notes.end(), [](const Note& n) { return n.range.has_value(); })) {
            j.key("relatedLocations").begin_array();
            int next_id = 1;
            for (const auto& n : d.notes) {
                if (!n.range) continue;
                j.begin_object().key("id").value(next_id++);
                j.key("message").begin_object().key("text").value(n.message).end_object();
                physical_location(j.key("physicalLocation"), *n.range);
                j.end_object();
            }
            j.end_array();
        }
        if (!d.fixes.empty()) {
            j.key("fixes").begin_array();
            for (const auto& f : d.fixes) {
                j.begin_object().key("description").begin_object().key("text").value(f.title).end_object();
                j.key("artifactChanges").begin_array().begin_object().key("artifactLocation").raw(artifact_text_);
                j.key("replacements").begin_array();
                for (const auto& e : f.edits) {
                    j.begin_object();
                    region(j.key("deletedRegion"), e.range);
                    j.key("insertedContent").begin_object().key("text").value(e.replacement).end_object();
                    j.end_object();
                }
                j.end_array().end_object().end_array();
                j.key("properties").begin_object().key("safe").value(f.safe).end_object();
                j.end_object();
            }
            j.end_array();
        }
        if (sp) {
            j.key("suppressions").begin_array().begin_object();
            j.key("kind").value(sp->kind == SuppressedDiagnostic::Kind::Baseline ? "external" : "inSource");
            if (!sp->reason.empty()) j.key("justification").value(sp->reason);
            if (sp->directive) {
                j.key("location").begin_object();
                physical_location(j.key("physicalLocation"), *sp->directive);
                j.end_object();
            }
            j.end_object().end_array();
        }
        if (d.folded) j.key("properties").begin_object().key("osplintFolded").value(d.folded).end_object();
        j.end_object();
        out_ << text_;
    }

    std::ostream& out_;
    fs::path root_;
    ojson artifact_;
    std::string artifact_text_;  // artifact_, dumped once per file
    std::string text_;           // the result being written (its capacity kept from one to the next)
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
