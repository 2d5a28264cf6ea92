// Baselines: accept the findings a code base has today, report only new ones.
//
// The file is JSON:
//
//     {
//       "version": 1,
//       "tool": {"name": "osplint", "version": "0.1.0"},
//       "entries": [
//         {"path": "programs/PART1.MIN", "rule": "OSP104", "fingerprint": "3f0c..."},
//         ...
//       ]
//     }
//
// `path` is relative to the directory of the baseline file (with '/'), so the
// same baseline works from any working directory. A finding matches an entry
// with the same path, rule and fingerprint; the fingerprint is made of the
// rule, the program name, the block's text and its occurrence, never the line
// number, so edits elsewhere in the file do not bring old findings back. Each
// entry matches at most one finding.
#pragma once

#include <filesystem>
#include <map>
#include <tuple>
#include <string>
#include <vector>

#include "osplint/osplint.h"

namespace osplint {

struct BaselineEntry {
    std::string path;
    std::string rule;
    std::string fingerprint;
    friend bool operator==(const BaselineEntry&, const BaselineEntry&) = default;
};

struct Baseline {
    std::string tool_version;
    std::vector<BaselineEntry> entries;  // sorted
};

// The path of a checked file as a baseline at `baseline_file` records it.
std::string baseline_path(const std::string& checked_path, const std::filesystem::path& baseline_file);

// The current findings of `results` (not the suppressed ones).
Baseline make_baseline(const std::vector<FileResult>& results, const std::filesystem::path& baseline_file);
std::string render_baseline(const Baseline& baseline);
// Throws std::runtime_error with a message naming the file when it cannot be used.
Baseline parse_baseline(std::string_view text, const std::string& origin);
Baseline load_baseline(const std::filesystem::path& file);
// Writes atomically (temporary file + rename). Throws std::runtime_error.
void write_baseline(const Baseline& baseline, const std::filesystem::path& file);

// Moves the findings the baseline records to FileResult::suppressed (kind
// Baseline). Returns how many were moved.
size_t apply_baseline(std::vector<FileResult>& results, const Baseline& baseline,
                      const std::filesystem::path& baseline_file);

// In a stream of findings: those the baseline records go on as suppressed
// (kind Baseline), each entry matching at most one finding; the others go on
// as they are.
class BaselineFilter final : public DiagnosticSink {
public:
    BaselineFilter(DiagnosticSink& next, const Baseline& baseline, const std::filesystem::path& baseline_file);
    bool wants_fingerprints() const override { return true; }
    void begin_file(const std::string& path) override;
    void diagnostic(Diagnostic&& d) override;
    void suppressed(SuppressedDiagnostic&& s) override { next_.suppressed(std::move(s)); }
    void end_file(const std::string& path, const std::string& io_error) override { next_.end_file(path, io_error); }
    size_t moved() const { return moved_; }

private:
    DiagnosticSink& next_;
    std::filesystem::path file_;
    std::string reason_;
    std::map<std::tuple<std::string, std::string, std::string>, size_t> remaining_;
    std::string path_;  // the current file as the baseline records it
    size_t moved_ = 0;
};

// In a stream of findings: records each in `baseline` (the files that could
// not be read are noted in `unreadable`), then passes it on as accepted
// (suppressed, kind Baseline), as the baseline written at the end will.
class BaselineRecorder final : public DiagnosticSink {
public:
    BaselineRecorder(DiagnosticSink& next, Baseline& baseline, const std::filesystem::path& baseline_file);
    bool wants_fingerprints() const override { return true; }
    void begin_file(const std::string& path) override;
    void diagnostic(Diagnostic&& d) override;
    void suppressed(SuppressedDiagnostic&& s) override { next_.suppressed(std::move(s)); }
    void end_file(const std::string& path, const std::string& io_error) override;
    const std::vector<std::string>& unreadable() const { return unreadable_; }

private:
    DiagnosticSink& next_;
    Baseline& baseline_;
    std::filesystem::path file_;
    std::string reason_;
    std::string path_;
    std::vector<std::string> unreadable_;
};

}  // namespace osplint
