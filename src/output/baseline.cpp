#include "output/baseline.h"

#include "support/io.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace osplint {

std::string baseline_path(const std::string& checked_path, const fs::path& baseline_file) {
    std::error_code ec;
    fs::path abs = fs::absolute(fs::path(checked_path), ec).lexically_normal();
    fs::path dir = fs::absolute(baseline_file, ec).parent_path().lexically_normal();
    if (ec) return fs::path(checked_path).generic_string();
    fs::path rel = abs.lexically_relative(dir);
    if (rel.empty()) rel = abs;
    return rel.generic_string();
}

Baseline make_baseline(const std::vector<FileResult>& results, const fs::path& baseline_file) {
    Baseline b;
    b.tool_version = std::string(version());
    for (const auto& r : results) {
        if (!r.io_error.empty()) continue;
        std::string path = baseline_path(r.path, baseline_file);
        for (const auto& d : r.diagnostics) b.entries.push_back({path, d.rule, d.fingerprint});
    }
    std::sort(b.entries.begin(), b.entries.end(), [](const BaselineEntry& x, const BaselineEntry& y) {
        return std::tie(x.path, x.rule, x.fingerprint) < std::tie(y.path, y.rule, y.fingerprint);
    });
    return b;
}

std::string render_baseline(const Baseline& baseline) {
    // One entry per line: reviewable, and diffs stay small when findings change.
    auto str = [](const std::string& s) {
        return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    };
    std::string out = "{\n  \"version\": 1,\n  \"tool\": {\"name\": \"osplint\", \"version\": " +
                      str(baseline.tool_version) + "},\n  \"entries\": [";
    for (size_t i = 0; i < baseline.entries.size(); ++i) {
        const auto& e = baseline.entries[i];
        out += i ? ",\n    " : "\n    ";
        out += "{\"path\": " + str(e.path) + ", \"rule\": " + str(e.rule) + ", \"fingerprint\": " +
               str(e.fingerprint) + "}";
    }
    out += baseline.entries.empty() ? "]\n}\n" : "\n  ]\n}\n";
    return out;
}

Baseline parse_baseline(std::string_view text, const std::string& origin) {
    auto fail = [&](const std::string& why) -> std::runtime_error {
        return std::runtime_error("baseline " + origin + ": " + why);
    };
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        throw fail(std::string("not valid JSON (") + e.what() + ")");
    }
    if (!j.is_object()) throw fail("expected a JSON object");
    if (!j.contains("version")) throw fail("no \"version\" (this osplint reads baseline version 1)");
    // Compared as JSON values: 4294967297 is not 1, whatever an int would make of it.
    if (!j["version"].is_number_integer() || j["version"] != nlohmann::json(1))
        throw fail("unsupported version " +
                   j["version"].dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).substr(0, 40) +
                   " (this osplint reads baseline version 1)");
    Baseline b;
    if (j.contains("tool") && j["tool"].is_object() && j["tool"].contains("version") &&
        j["tool"]["version"].is_string())
        b.tool_version = j["tool"]["version"].get<std::string>();
    if (!j.contains("entries") || !j["entries"].is_array()) throw fail("missing the \"entries\" array");
    size_t i = 0;
    for (const auto& e : j["entries"]) {
        auto field = [&](const char* name) {
            if (!e.is_object() || !e.contains(name) || !e[name].is_string())
                throw fail("entry " + std::to_string(i) + " lacks the string \"" + name + "\"");
            return e[name].get<std::string>();
        };
        b.entries.push_back({field("path"), field("rule"), field("fingerprint")});
        ++i;
    }
    return b;
}

Baseline load_baseline(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error("baseline " + file.string() + ": cannot be read");
    std::ostringstream ss;
    ss << in.rdbuf();
    return parse_baseline(ss.str(), file.string());
}

void write_baseline(const Baseline& baseline, const fs::path& file) {
    std::string error;
    if (!write_file_atomically(file.string(), render_baseline(baseline), error))
        throw std::runtime_error("baseline " + file.string() + ": not written: " + error);
}

namespace {

std::string reason_for(const fs::path& baseline_file) {
    return "recorded in the baseline " + baseline_file.filename().string();
}

// Collects what a filter passes on, per file.
class Collect final : public DiagnosticSink {
public:
    explicit Collect(std::vector<FileResult>& out) : out_(out) {}
    void begin_file(const std::string& path) override {
        out_.emplace_back();
        out_.back().path = path;
    }
    void diagnostic(Diagnostic&& d) override { out_.back().diagnostics.push_back(std::move(d)); }
    void suppressed(SuppressedDiagnostic&& s) override { out_.back().suppressed.push_back(std::move(s)); }
    void end_file(const std::string&, const std::string& io_error) override { out_.back().io_error = io_error; }

private:
    std::vector<FileResult>& out_;
};

}  // namespace

BaselineFilter::BaselineFilter(DiagnosticSink& next, const Baseline& baseline, const fs::path& baseline_file)
    : next_(next), file_(baseline_file), reason_(reason_for(baseline_file)) {
    for (const auto& e : baseline.entries) ++remaining_[{e.path, e.rule, e.fingerprint}];
}

void BaselineFilter::begin_file(const std::string& path) {
    path_ = baseline_path(path, file_);
    next_.begin_file(path);
}

void BaselineFilter::diagnostic(Diagnostic&& d) {
    auto it = remaining_.find({path_, d.rule, d.fingerprint});
    if (it == remaining_.end() || it->second == 0) {
        next_.diagnostic(std::move(d));
        return;
    }
    --it->second;
    ++moved_;
    SuppressedDiagnostic s;
    s.kind = SuppressedDiagnostic::Kind::Baseline;
    s.reason = reason_;
    s.diagnostic = std::move(d);
    next_.suppressed(std::move(s));
}

BaselineRecorder::BaselineRecorder(DiagnosticSink& next, Baseline& baseline, const fs::path& baseline_file)
    : next_(next), baseline_(baseline), file_(baseline_file), reason_(reason_for(baseline_file)) {
    baseline_.tool_version = std::string(version());
}

void BaselineRecorder::begin_file(const std::string& path) {
    path_ = baseline_path(path, file_);
    next_.begin_file(path);
}

void BaselineRecorder::diagnostic(Diagnostic&& d) {
    baseline_.entries.push_back({path_, d.rule, d.fingerprint});
    SuppressedDiagnostic s;
    s.kind = SuppressedDiagnostic::Kind::Baseline;
    s.reason = reason_;
    s.diagnostic = std::move(d);
    next_.suppressed(std::move(s));
}

void BaselineRecorder::end_file(const std::string& path, const std::string& io_error) {
    if (!io_error.empty()) unreadable_.push_back(path);
    next_.end_file(path, io_error);
}

size_t apply_baseline(std::vector<FileResult>& results, const Baseline& baseline, const fs::path& baseline_file) {
    std::vector<FileResult> out;
    Collect collect(out);
    BaselineFilter filter(collect, baseline, baseline_file);
    for (auto& r : results) {
        filter.begin_file(r.path);
        for (auto& d : r.diagnostics) filter.diagnostic(std::move(d));
        for (auto& s : r.suppressed) filter.suppressed(std::move(s));
        filter.end_file(r.path, r.io_error);
    }
    for (auto& r : out)
        std::stable_sort(r.suppressed.begin(), r.suppressed.end(),
                         [](const SuppressedDiagnostic& a, const SuppressedDiagnostic& b) {
                             return diagnostic_less(a.diagnostic, b.diagnostic);
                         });
    results = std::move(out);
    return filter.moved();
}

}  // namespace osplint
