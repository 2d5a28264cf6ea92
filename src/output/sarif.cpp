#include "output/sarif.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "support/embedded.h"
#include "rules/registry.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace osplint {
namespace {

std::string_view sarif_level(Severity s) {
    switch (s) {
        case Severity::Error: return "error";
        case Severity::Warning: return "warning";
        case Severity::Info: return "note";
    }
    return "error";
}

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

json rule_descriptor(const std::string& id, const Diagnostic& sample) {
    const RuleMeta* meta = find_rule(id);
    std::string summary = meta ? std::string(meta->summary) : sample.name;
    auto doc = embedded::find("docs/rules/" + id + ".md");
    std::string full = doc ? section(*doc, "## What it does") : std::string();
    if (full.empty()) full = summary;
    // Complete sentences: consumers show these as descriptions.
    auto sentence = [](std::string s) {
        if (!s.empty() && s.back() != '.' && s.back() != '!' && s.back() != '?') s += '.';
        return s;
    };
    json help;
    if (doc) {
        help = {{"text", std::string(*doc)}, {"markdown", std::string(*doc)}};
    } else {
        help = {{"text", sentence(summary)}, {"markdown", sentence(summary)}};
    }
    json config = {{"level", sarif_level(meta ? meta->severity : sample.severity)}};
    if (meta && !meta->enabled_by_default) config["enabled"] = false;
    json r = {{"id", id},
              {"name", meta ? std::string(meta->name) : sample.name},
              {"shortDescription", {{"text", sentence(summary)}}},
              {"fullDescription", {{"text", sentence(full)}}},
              {"help", std::move(help)},
              {"defaultConfiguration", std::move(config)},
              {"properties", {{"tags", json::array({"osplint"})}}}};
    if (doc) r["helpUri"] = std::string(kProjectUri) + "/blob/main/docs/rules/" + id + ".md";
    return r;
}

json region(const SourceRange& r) {
    return {{"startLine", r.start.line},
            {"startColumn", r.start.utf16_col + 1},
            {"endLine", r.end.line},
            {"endColumn", r.end.utf16_col + 1}};
}

}  // namespace

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

std::string render_sarif(const std::vector<FileResult>& results, const SarifOptions& options) {
    // Rules in ID order, each once.
    std::map<std::string, const Diagnostic*> used;
    for (const auto& r : results) {
        for (const auto& d : r.diagnostics) used.emplace(d.rule, &d);
        for (const auto& s : r.suppressed) used.emplace(s.diagnostic.rule, &s.diagnostic);
    }
    json rules = json::array();
    std::map<std::string, size_t> rule_index;
    for (const auto& [id, sample] : used) {
        rule_index[id] = rules.size();
        rules.push_back(rule_descriptor(id, *sample));
    }

    json results_json = json::array();
    json notifications = json::array();
    bool success = true;
    for (const auto& r : results) {
        bool relative = false;
        std::string uri = sarif_artifact_uri(r.path, options.root, relative);
        json artifact = {{"uri", uri}};
        if (relative) artifact["uriBaseId"] = "%SRCROOT%";
        if (!r.io_error.empty()) {
            success = false;
            notifications.push_back({{"level", "error"},
                                     {"message", {{"text", r.path + ": " + r.io_error + "."}}},
                                     {"locations", json::array({{{"physicalLocation", {{"artifactLocation", artifact}}}}})}});
            continue;
        }
        auto location = [&](const SourceRange& range) {
            return json{{"physicalLocation", {{"artifactLocation", artifact}, {"region", region(range)}}}};
        };
        // Findings and suppressed findings, in source order.
        std::vector<std::pair<const Diagnostic*, const SuppressedDiagnostic*>> all;
        for (const auto& d : r.diagnostics) all.push_back({&d, nullptr});
        for (const auto& s : r.suppressed) all.push_back({&s.diagnostic, &s});
        std::stable_sort(all.begin(), all.end(),
                         [](const auto& a, const auto& b) { return diagnostic_less(*a.first, *b.first); });
        for (const auto& [dp, sp] : all) {
            const Diagnostic& d = *dp;
            std::string text = d.message;
            json related = json::array();
            int next_id = 1;
            for (const auto& n : d.notes) {
                text += "\nNote: " + n.message;
                if (n.range) {
                    related.push_back(
                        {{"id", next_id++}, {"message", {{"text", n.message}}}, {"physicalLocation", location(*n.range)["physicalLocation"]}});
                }
            }
            json res = {{"ruleId", d.rule},
                        {"ruleIndex", rule_index[d.rule]},
                        {"level", sarif_level(d.severity)},
                        {"message", {{"text", text}}},
                        {"locations", json::array({location(d.range)})},
                        {"partialFingerprints", {{std::string(kFingerprintKey), d.fingerprint}}}};
            if (!related.empty()) res["relatedLocations"] = std::move(related);
            if (!d.fixes.empty()) {
                json fixes = json::array();
                for (const auto& f : d.fixes) {
                    json replacements = json::array();
                    for (const auto& e : f.edits)
                        replacements.push_back(
                            {{"deletedRegion", region(e.range)}, {"insertedContent", {{"text", e.replacement}}}});
                    fixes.push_back({{"description", {{"text", f.title}}},
                                     {"artifactChanges", json::array({{{"artifactLocation", artifact},
                                                                       {"replacements", std::move(replacements)}}})}});
                }
                res["fixes"] = std::move(fixes);
            }
            if (sp) {
                json s = {{"kind", sp->kind == SuppressedDiagnostic::Kind::Baseline ? "external" : "inSource"}};
                if (!sp->reason.empty()) s["justification"] = sp->reason;
                if (sp->directive) s["location"] = location(*sp->directive);
                res["suppressions"] = json::array({std::move(s)});
            }
            results_json.push_back(std::move(res));
        }
    }

    json invocation = {{"executionSuccessful", success}};
    if (!notifications.empty()) invocation["toolExecutionNotifications"] = std::move(notifications);
    std::error_code ec;
    fs::path root = fs::absolute(options.root, ec).lexically_normal();
    invocation["workingDirectory"] = {{"uri", file_uri(root, true)}};

    json run = {{"tool",
                 {{"driver",
                   {{"name", "osplint"},
                    {"fullName", "osplint, static analyzer for Okuma OSP part programs"},
                    {"version", std::string(version())},
                    {"semanticVersion", std::string(version())},
                    {"informationUri", std::string(kProjectUri)},
                    {"rules", std::move(rules)}}}}},
                {"invocations", json::array({std::move(invocation)})},
                {"originalUriBaseIds", {{"%SRCROOT%", {{"uri", file_uri(root, true)}}}}},
                {"columnKind", "utf16CodeUnits"},
                {"results", std::move(results_json)}};
    json log = {{"$schema", std::string(kSarifSchema)}, {"version", "2.1.0"}, {"runs", json::array({std::move(run)})}};
    return log.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace osplint
