// libFuzzer target: the input bytes as a part program, through both front ends
// and both checks; any difference aborts.
//
//   * parse_program_file (tree-sitter) and parse_program_file_fast give equal
//     Blocks and programs (lines with syntax errors included: both front ends
//     parse such a line on its own).
//   * check_text and the streaming check (read in chunks of a size taken from
//     the input) give the same result, every field.
//
// Build and run with fuzz/run.sh.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "syntax/frontend.h"
#include "syntax/frontend_fast.h"
#include "osplint/osplint.h"
#include "engine/stream.h"

using namespace osplint;

namespace {

[[noreturn]] void divergence(const std::string& what) {
    std::fprintf(stderr, "==== DIVERGENCE ====\n%s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

const Config& config() {
    static const Config c;
    return c;
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

    const std::string path = size > 0 && (data[0] & 1) ? "fuzz.ssb" : "fuzz.min";
    const std::string expected = dump_result(check_text(path, text, config()));
    StreamOptions so;
    so.chunk_size = size > 1 ? 1 + data[size - 1] % 61 : 1;
    const std::string small = dump_result(check_text_fast(path, text, config(), {}, so));
    if (small != expected)
        divergence("check (chunk " + std::to_string(so.chunk_size) + ")\n-- check_text:\n" + expected +
                   "-- streaming:\n" + small);
    so.chunk_size = size_t(1) << 20;
    const std::string large = dump_result(check_text_fast(path, text, config(), {}, so));
    if (large != expected)
        divergence("check (chunk 1 MiB)\n-- check_text:\n" + expected + "-- streaming:\n" + large);
    return 0;
}
