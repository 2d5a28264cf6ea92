#include "output/report.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace osplint {
namespace {

const char* color_of(Severity s) {
    switch (s) {
        case Severity::Error: return "\x1b[1;31m";
        case Severity::Warning: return "\x1b[1;33m";
        case Severity::Info: return "\x1b[1;36m";
    }
    return "";
}

// Replaces control characters so that a report never carries raw escapes or
// NULs from the checked file to a terminal.
std::string printable(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (unsigned char c : s) {
        if (c == '\t') out += ' ';
        else if (c < 0x20 || c == 0x7f) out += "\xEF\xBF\xBD";  // U+FFFD
        else out += static_cast<char>(c);
    }
    return out;
}

nlohmann::ordered_json position_json(const Position& p) {
    return {{"line", p.line}, {"column", p.cp_col + 1}};
}

nlohmann::ordered_json range_json(const SourceRange& r) {
    return {{"start", position_json(r.start)}, {"end", position_json(r.end)}};
}

}  // namespace

Summary summarize(const std::vector<FileResult>& results) {
    Summary s;
    s.files = results.size();
    for (const auto& r : results)
        for (const auto& d : r.diagnostics) {
            if (d.severity == Severity::Error) ++s.error;
            else if (d.severity == Severity::Warning) ++s.warning;
            else ++s.info;
        }
    return s;
}

std::string render_text_diagnostic(const std::string& path, const Diagnostic& d, const TextOptions& o) {
    const char* bold = o.color ? "\x1b[1m" : "";
    const char* reset = o.color ? "\x1b[0m" : "";
    const char* blue = o.color ? "\x1b[1;34m" : "";
    std::string out = fmt::format("{}{}:{}:{}:{} {}{}[{}]{}: {}{}{}\n", bold, printable(path), d.range.start.line,
                                  d.range.start.cp_col + 1, reset, o.color ? color_of(d.severity) : "",
                                  severity_name(d.severity), d.rule, reset, bold, printable(d.message), reset);
    if (!d.line_text.empty() || d.range.start.line) {
        std::string line = printable(d.line_text);
        std::string num = std::to_string(d.range.start.line);
        std::string pad(num.size(), ' ');
        out += fmt::format("{} {} |{} {}\n", blue, num, reset, line);
        // Caret under the range (on the first line of the range), counted in code points.
        uint32_t start = d.range.start.cp_col;
        uint32_t end = d.range.end.line == d.range.start.line ? d.range.end.cp_col : start + 1;
        if (end <= start) end = start + 1;
        out += fmt::format("{} {} |{} {}{}{}{}\n", blue, pad, reset, std::string(start, ' '),
                           o.color ? color_of(d.severity) : "", std::string(end - start, '^'), reset);
        for (const auto& n : d.notes) {
            if (n.range && n.range->start.line != d.range.start.line)
                out += fmt::format("{} {} ={} note: {} (line {})\n", blue, pad, reset, printable(n.message),
                                   n.range->start.line);
            else
                out += fmt::format("{} {} ={} note: {}\n", blue, pad, reset, printable(n.message));
        }
        for (const auto& f : d.fixes) out += fmt::format("{} {} ={} fix: {}\n", blue, pad, reset, printable(f.title));
    }
    return out;
}

std::string render_summary(const Summary& s) {
    auto plural = [](size_t n, const char* word) { return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s"); };
    return fmt::format("{}, {}, {} in {}\n", plural(s.error, "error"), plural(s.warning, "warning"),
                       plural(s.info, "info"), plural(s.files, "file"));
}

std::string render_text(const std::vector<FileResult>& results, const TextOptions& o) {
    std::string out;
    for (const auto& r : results) {
        if (!r.io_error.empty()) continue;  // reported on stderr by the caller
        for (const auto& d : r.diagnostics) {
            out += render_text_diagnostic(r.path, d, o);
            out += "\n";
        }
    }
    out += render_summary(summarize(results));
    return out;
}

std::string render_json(const std::vector<FileResult>& results) {
    nlohmann::ordered_json files = nlohmann::ordered_json::array();
    for (const auto& r : results) {
        nlohmann::ordered_json diags = nlohmann::ordered_json::array();
        for (const auto& d : r.diagnostics) {
            nlohmann::ordered_json notes = nlohmann::ordered_json::array();
            for (const auto& n : d.notes) {
                nlohmann::ordered_json jn = {{"message", n.message}};
                if (n.range) jn["range"] = range_json(*n.range);
                notes.push_back(std::move(jn));
            }
            nlohmann::ordered_json fixes = nlohmann::ordered_json::array();
            for (const auto& f : d.fixes) {
                nlohmann::ordered_json edits = nlohmann::ordered_json::array();
                for (const auto& e : f.edits)
                    edits.push_back({{"range", range_json(e.range)}, {"replacement", e.replacement}});
                fixes.push_back({{"title", f.title}, {"edits", std::move(edits)}});
            }
            diags.push_back({{"rule", d.rule},
                             {"name", d.name},
                             {"severity", severity_name(d.severity)},
                             {"message", d.message},
                             {"range", range_json(d.range)},
                             {"notes", std::move(notes)},
                             {"fixes", std::move(fixes)},
                             {"fingerprint", d.fingerprint}});
        }
        nlohmann::ordered_json jf = {{"path", r.path}, {"diagnostics", std::move(diags)}};
        if (!r.io_error.empty()) jf["error"] = r.io_error;
        files.push_back(std::move(jf));
    }
    Summary s = summarize(results);
    nlohmann::ordered_json root = {{"version", 1},
                           {"tool", {{"name", "osplint"}, {"version", std::string(version())}}},
                           {"files", std::move(files)},
                           {"summary", {{"files", s.files}, {"error", s.error}, {"warning", s.warning}, {"info", s.info}}}};
    // Invalid UTF-8 in messages (quoted source text) is replaced, never fatal.
    return root.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace osplint
