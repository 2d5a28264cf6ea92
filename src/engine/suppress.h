// Suppression directives: which findings they silence (the syntax is in
// syntax/directive.h).
//
// The engine builds a SuppressionFilter from the directives the file's
// outline found before it walks the file, so that every finding is checked as
// soon as it is made: a finding a directive covers goes to the sink as
// suppressed, with the directive's reason; OSP001 (syntax-error) is never
// silenced. At the end of the file, `finish` gives the findings about the
// directives themselves: OSP901 (unknown-rule-in-suppression) for those that
// cannot be honoured, OSP902 (unused-suppression, off by default) for entries
// that silenced nothing.
#pragma once

#include <string>
#include <vector>

#include "engine/rule.h"
#include "osplint/diagnostic.h"
#include "semantics/config.h"
#include "syntax/directive.h"
#include "syntax/outline.h"

namespace osplint {

class SuppressionFilter {
public:
    SuppressionFilter(const FileOutline& outline, const RuleRegistry& rules, const Config& config,
                      const std::vector<std::string>& only_rules);

    bool empty() const { return entries_.empty(); }
    // Whether a directive silences `d`; if so, moves it into `out` with the directive.
    bool silence(Diagnostic& d, SuppressedDiagnostic& out);
    // Whether a directive would silence a finding of `d.rule` starting on
    // `d.range.start.line` (nothing is marked used).
    bool covers(const Diagnostic& d) const;
    // The findings about the directives (OSP901, OSP902), sorted.
    std::vector<Diagnostic> finish();
    // Which entries silenced something so far (to undo a speculative walk).
    std::vector<bool> used() const;
    void set_used(const std::vector<bool>& used);

private:
    struct Line {
        uint32_t line = 0;
        uint32_t line_start = 0;
        std::string text;
        std::string program;
        uint32_t target_line = 0;
    };
    // One rule ID of one directive that names a rule a directive can silence.
    struct Entry {
        std::string rule;
        size_t directive = 0;      // index into directives_
        size_t index = 0;          // position in the directive's ID list
        uint32_t target_line = 0;  // the line it silences; 0: none (or file scope)
        bool file_scope = false;
        bool used = false;
    };
    Diagnostic& make(const RuleMeta& meta, ByteRange range, const Line& l, std::string message);
    const Entry* find(const Diagnostic& d) const;
    bool runs(const RuleMeta& meta) const;

    const RuleRegistry& rules_;
    const Config& config_;
    std::vector<std::string> only_;
    const RuleMeta* unknown_meta_ = nullptr;  // OSP901
    const RuleMeta* unused_meta_ = nullptr;   // OSP902
    bool report_unknown_ = false;
    bool report_unused_ = false;
    std::vector<Line> lines_;
    std::vector<SuppressionDirective> directives_;
    std::vector<size_t> directive_line_;  // index into lines_
    std::vector<Entry> entries_;
    std::vector<Diagnostic> own_;         // OSP901 findings, then OSP902
    std::vector<std::pair<std::string, int>> occurrences_;
};

// The position of `offset` on a line whose start, number and text are known.
Position position_on_line(uint32_t line, uint32_t line_start, std::string_view text, uint32_t offset);

}  // namespace osplint
