// Stages between the engine and the report writers: each one a DiagnosticSink
// that passes what it keeps on to the next. The CLI chains them:
//
//   engine -> baseline (filter or record) -> counting -> [folding] -> limit -> writer(s)
//
// (folding happens in the engine unless a baseline needs every finding
// first). Counting sees every finding, or the count a folded finding carries,
// so the summary and the exit code count the findings shown only as a number.
#pragma once

#include <cstdint>
#include <map>
#include <unordered_map>
#include <optional>
#include <string>
#include <vector>

#include "osplint/diagnostic.h"
#include "engine/fold.h"
#include "output/writer.h"

namespace osplint {

// Counts files, findings by severity and suppressed findings.
class CountingSink final : public DiagnosticSink {
public:
    CountingSink(DiagnosticSink& next, Counts& counts) : next_(next), counts_(counts) {}
    bool wants_fingerprints() const override { return next_.wants_fingerprints(); }
    void begin_file(const std::string& path) override {
        ++counts_.files;
        next_.begin_file(path);
    }
    void diagnostic(Diagnostic&& d) override {
        // A finding the engine folded others into stands for them too.
        counts_.add(d.severity, 1 + d.folded);
        counts_.folded += d.folded;
        bool safe = false;
        for (const auto& f : d.fixes) safe = safe || f.safe;
        if (safe) ++counts_.fixable;
        else if (!d.fixes.empty()) ++counts_.unsafe_fixable;
        next_.diagnostic(std::move(d));
    }
    void suppressed(SuppressedDiagnostic&& s) override {
        ++counts_.suppressed;
        next_.suppressed(std::move(s));
    }
    void end_file(const std::string& path, const std::string& io_error) override {
        if (!io_error.empty()) ++counts_.unreadable;
        next_.end_file(path, io_error);
    }

private:
    DiagnosticSink& next_;
    Counts& counts_;
};

// Folds the findings of one kind beyond the first `keep` of a file into one
// (engine/fold.h) after a baseline has seen them all. Without a baseline the
// engine folds as the rules report (AnalysisOptions::fold), which spares
// building the findings that are only counted.
class FoldingSink final : public DiagnosticSink {
public:
    FoldingSink(DiagnosticSink& next, uint64_t keep, Counts& counts) : next_(next), folder_(keep), counts_(counts) {}
    bool wants_fingerprints() const override { return next_.wants_fingerprints(); }
    void begin_file(const std::string& path) override { next_.begin_file(path); }
    void diagnostic(Diagnostic&& d) override;
    void suppressed(SuppressedDiagnostic&& s) override { next_.suppressed(std::move(s)); }
    void end_file(const std::string& path, const std::string& io_error) override;

private:
    DiagnosticSink& next_;
    Folder folder_;
    Counts& counts_;
    std::unordered_map<uint64_t, SourceRange> last_;  // the range of the last folded finding of each kind
};

// Shows at most `max` findings of a file (`--max-findings N`); the others are
// counted, and shown as one: the first of them, with the count and a note.
class LimitSink final : public DiagnosticSink {
public:
    LimitSink(DiagnosticSink& next, uint64_t max, Counts& counts) : next_(next), max_(max), counts_(counts) {}
    bool wants_fingerprints() const override { return next_.wants_fingerprints(); }
    void begin_file(const std::string& path) override;
    void diagnostic(Diagnostic&& d) override;
    void suppressed(SuppressedDiagnostic&& s) override { next_.suppressed(std::move(s)); }
    void end_file(const std::string& path, const std::string& io_error) override;

private:
    DiagnosticSink& next_;
    uint64_t max_;
    Counts& counts_;
    uint64_t shown_ = 0;
    uint64_t omitted_ = 0;        // findings not shown, counting those they had folded
    uint64_t omitted_items_ = 0;  // findings not shown
    std::optional<Diagnostic> first_omitted_;
    SourceRange last_omitted_;
};

// Hands everything to two sinks (GitHub annotations on stdout and the text
// report on stderr).
class TeeSink final : public DiagnosticSink {
public:
    TeeSink(DiagnosticSink& a, DiagnosticSink& b) : a_(a), b_(b) {}
    bool wants_fingerprints() const override { return a_.wants_fingerprints() || b_.wants_fingerprints(); }
    void begin_file(const std::string& path) override {
        a_.begin_file(path);
        b_.begin_file(path);
    }
    void diagnostic(Diagnostic&& d) override {
        Diagnostic copy = d;
        a_.diagnostic(std::move(copy));
        b_.diagnostic(std::move(d));
    }
    void suppressed(SuppressedDiagnostic&& s) override {
        SuppressedDiagnostic copy = s;
        a_.suppressed(std::move(copy));
        b_.suppressed(std::move(s));
    }
    void end_file(const std::string& path, const std::string& io_error) override {
        a_.end_file(path, io_error);
        b_.end_file(path, io_error);
    }

private:
    DiagnosticSink& a_;
    DiagnosticSink& b_;
};

}  // namespace osplint
