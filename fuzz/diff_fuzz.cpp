// libFuzzer target: the input bytes as a part program, through both front
// ends, the outline and the engine; any difference from the reference aborts.
//
//   * parse_program_file (tree-sitter) and parse_program_file_fast give equal
//     Blocks and programs (lines with syntax errors included: both front ends
//     parse such a line on its own);
//   * the outline read fast equals the outline of the full parse;
//   * the engine, reading the input in chunks of a size taken from the input
//     and holding loops in memory or reading them again, gives the reference
//     analysis's result (tests/unit/reference.h), every field.
//
// Build and run with fuzz/run.sh.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "api/check.h"
#include "reference.h"
#include "syntax/frontend.h"
#include "syntax/frontend_fast.h"
#include "syntax/outline.h"

using namespace osplint;
using namespace osplint::testing;

namespace {

[[noreturn]] void divergence(const std::string& what) {
    std::fprintf(stderr, "==== DIVERGENCE ====\n%s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

// The default configuration, or one with travel limits (OSP301 then looks
// at every move, and the walk with the rules checks plain moves from their
// values) and OSP003 on (the sequence names of those moves go to it from
// their values too), as a bit of the input says.
const Config& config_for(bool travel) {
    static const Config plain;
    static const Config limited = [] {
        Config c;
        c.travel['X'] = TravelLimit{-300, 300};
        c.travel['Y'] = TravelLimit{-200, 200};
        c.travel['Z'] = TravelLimit{-300, 100};
        c.rule_severity["OSP003"] = Severity::Warning;  // off by default; the names of plain moves too
        return c;
    }();
    return travel ? limited : plain;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > (1u << 16)) return 0;
    const std::string text(reinterpret_cast<const char*>(data), size);
    const ProgramFile ts = parse_program_file("fuzz.min", text);
    const ProgramFile fast = parse_program_file_fast("fuzz.min", text);
    if (ts.blocks.size() != fast.blocks.size())
        divergence("block count " + std::to_string(ts.blocks.size()) + " vs " + std::to_string(fast.blocks.size()));
    for (size_t k = 0; k < ts.blocks.size(); ++k) {
        const Block& a = ts.blocks[k];
        const Block& b = fast.blocks[k];
        if (a == b) continue;
        divergence("line " + std::to_string(a.line) + " '" + std::string(ts.source.line_text(a.line)) +
                   "'\n-- tree-sitter:\n" + dump_block(a) + "-- fast:\n" + dump_block(b));
    }
    if (!(ts.programs == fast.programs)) divergence("programs differ");

    OutlineOptions oo;
    oo.chunk_size = size > 2 ? 1 + data[size - 2] % 97 : 1;
    MemorySource src(text);
    const std::string outline = dump_outline(outline_file(src, oo));
    const std::string expected_outline = dump_outline(reference_outline(ts));
    if (outline != expected_outline)
        divergence("outline\n-- reference:\n" + expected_outline + "-- engine:\n" + outline);

    const std::string path = size > 0 && (data[0] & 1) ? "fuzz.ssb" : "fuzz.min";
    const Config& config = config_for(size > 0 && (data[0] & 4));
    const std::string expected = dump_result(reference_check(path, text, config));
    AnalysisOptions options;
    options.chunk_size = size > 1 ? 1 + data[size - 1] % 61 : 1;
    options.held_loop_blocks = size > 0 && (data[0] & 2) ? 0 : 8192;
    const std::string small = dump_result(check_text(path, text, config, options));
    if (small != expected)
        divergence("check (chunk " + std::to_string(options.chunk_size) + ", held " +
                   std::to_string(options.held_loop_blocks) + ")\n-- reference:\n" + expected + "-- engine:\n" + small);
    options.chunk_size = size_t(1) << 20;
    options.held_loop_blocks = 8192;
    const std::string large = dump_result(check_text(path, text, config, options));
    if (large != expected) divergence("check (chunk 1 MiB)\n-- reference:\n" + expected + "-- engine:\n" + large);
    return 0;
}
