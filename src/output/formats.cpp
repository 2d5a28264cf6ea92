#include "output/formats.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "output/report.h"

namespace osplint {
namespace {

// One physical line of output: line breaks become blanks, other control
// characters U+FFFD, so a finding can never forge another line.
std::string one_line(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (unsigned char c : s) {
        if (c == '\n' || c == '\r' || c == '\t') out += ' ';
        else if (c < 0x20 || c == 0x7f) out += "\xEF\xBF\xBD";
        else out += static_cast<char>(c);
    }
    return out;
}

std::string_view gcc_severity(Severity s) {
    switch (s) {
        case Severity::Error: return "error";
        case Severity::Warning: return "warning";
        case Severity::Info: return "note";
    }
    return "error";
}

std::string_view github_command(Severity s) {
    switch (s) {
        case Severity::Error: return "error";
        case Severity::Warning: return "warning";
        case Severity::Info: return "notice";
    }
    return "error";
}

nlohmann::json range_json(const SourceRange& r) {
    return {{"start", {{"line", r.start.line}, {"column", r.start.cp_col + 1}}},
            {"end", {{"line", r.end.line}, {"column", r.end.cp_col + 1}}}};
}

}  // namespace

std::string render_gcc(const std::vector<FileResult>& results) {
    std::string out;
    for (const auto& r : results) {
        if (!r.io_error.empty()) continue;  // reported on stderr by the caller
        const std::string path = one_line(r.path);
        for (const auto& d : r.diagnostics)
            out += fmt::format("{}:{}:{}: {}: {} [{}]\n", path, d.range.start.line, d.range.start.cp_col + 1,
                               gcc_severity(d.severity), one_line(d.message), d.rule);
    }
    return out;
}

std::string github_escape_data(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        switch (c) {
            case '%': out += "%25"; break;
            case '\r': out += "%0D"; break;
            case '\n': out += "%0A"; break;
            default: out += c;
        }
    }
    return out;
}

std::string github_escape_property(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        switch (c) {
            case '%': out += "%25"; break;
            case '\r': out += "%0D"; break;
            case '\n': out += "%0A"; break;
            case ':': out += "%3A"; break;
            case ',': out += "%2C"; break;
            default: out += c;
        }
    }
    return out;
}

std::string render_github(const std::vector<FileResult>& results) {
    std::string out;
    for (Severity level : {Severity::Error, Severity::Warning, Severity::Info}) {
        for (const auto& r : results) {
            if (!r.io_error.empty()) continue;
            for (const auto& d : r.diagnostics) {
                if (d.severity != level) continue;
                std::string props = "file=" + github_escape_property(r.path);
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
                out += fmt::format("::{} {}::{}\n", github_command(d.severity), props, github_escape_data(message));
            }
        }
    }
    return out;
}

std::string render_json_report(const std::vector<FileResult>& results) {
    nlohmann::json root = nlohmann::json::parse(render_json(results));
    // The suppressed findings in exactly the shape of diagnostics: rendered by
    // the same renderer, then given their suppression.
    std::vector<FileResult> silenced;
    silenced.reserve(results.size());
    size_t count = 0;
    for (const auto& r : results) {
        FileResult s;
        s.path = r.path;
        for (const auto& sd : r.suppressed) s.diagnostics.push_back(sd.diagnostic);
        count += r.suppressed.size();
        silenced.push_back(std::move(s));
    }
    nlohmann::json shaped = nlohmann::json::parse(render_json(silenced));
    auto& files = root["files"];
    for (size_t i = 0; i < results.size() && i < files.size(); ++i) {
        nlohmann::json list = nlohmann::json::array();
        auto& diags = shaped["files"][i]["diagnostics"];
        for (size_t k = 0; k < results[i].suppressed.size() && k < diags.size(); ++k) {
            const auto& sd = results[i].suppressed[k];
            nlohmann::json entry = std::move(diags[k]);
            nlohmann::json how = {
                {"kind", sd.kind == SuppressedDiagnostic::Kind::Baseline ? "baseline" : "inSource"},
                {"reason", sd.reason},
                {"scope", sd.kind == SuppressedDiagnostic::Kind::Baseline ? "baseline"
                          : sd.file_scope                                 ? "file"
                                                                          : "block"}};
            if (sd.directive) how["directive"] = range_json(*sd.directive);
            entry["suppression"] = std::move(how);
            list.push_back(std::move(entry));
        }
        files[i]["suppressed"] = std::move(list);
    }
    root["summary"]["suppressed"] = count;
    return root.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace osplint
