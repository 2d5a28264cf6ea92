// Running the engine in the tests with every block's states kept.
#pragma once

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "api/check.h"
#include "api/config.h"
#include "engine/record.h"

namespace osplint::testing {

struct Analysis {
    std::vector<BlockRecord> blocks;  // every block the rules saw, in order
    FileResult result;                // the findings (sorted)
    EngineStats stats;

    // The record of the block on a 1-based line.
    const BlockRecord& at(uint32_t line) const {
        for (const auto& b : blocks)
            if (b.block.line == line) return b;
        FAIL("no block on line " << line);
        return blocks.front();
    }
    // Findings of a rule on a line, or anywhere.
    size_t findings(std::string_view rule, uint32_t line) const {
        size_t n = 0;
        for (const auto& d : result.diagnostics)
            if (d.rule == rule && d.range.start.line == line) ++n;
        return n;
    }
    size_t findings(std::string_view rule) const {
        size_t n = 0;
        for (const auto& d : result.diagnostics)
            if (d.rule == rule) ++n;
        return n;
    }
};

// Analyses `text` with only `rules` (none: the states only).
inline Analysis analyze_text(const std::string& path, const std::string& text, const Config& config,
                             std::vector<std::string> rules = {}) {
    Analysis a;
    BlockRecorder rec;
    AnalysisOptions options;
    options.observer = &rec;
    options.stats = &a.stats;
    options.only_rules = std::move(rules);
    if (options.only_rules.empty()) options.run_rules = false;
    a.result = check_text(path, text, config, options);
    a.blocks = std::move(rec.blocks);
    return a;
}

}  // namespace osplint::testing
