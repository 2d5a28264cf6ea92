// What both front ends share (frontend.h): the split of blocks into programs
// and the value of a decimal literal, so that they agree on both.
#include <charconv>
#include <limits>
#include <string_view>

#include "syntax/frontend.h"

namespace osplint {

std::vector<Program> split_programs(const std::vector<Block>& blocks) {
    std::vector<Program> programs;
    if (blocks.empty()) return programs;
    // Lines before the first program name that hold nothing executable (tape
    // header, comments, blank lines) belong to the first program.
    size_t first = 0;
    while (first < blocks.size() && !blocks[first].program_name &&
           (blocks[first].is_empty() || blocks[first].kind != LineKind::Block))
        ++first;
    auto start = [&](size_t at, const Block& named) {
        Program p;
        if (named.program_name) {
            p.name = named.program_name->name;
            p.name_range = named.program_name->range;
        }
        p.first_block = static_cast<uint32_t>(at);
        programs.push_back(std::move(p));
    };
    if (first < blocks.size() && blocks[first].program_name)
        start(0, blocks[first]);
    else
        start(0, Block{});
    for (size_t i = first + 1; i < blocks.size(); ++i) {
        if (!blocks[i].program_name) continue;
        programs.back().end_block = static_cast<uint32_t>(i);
        start(i, blocks[i]);
    }
    programs.back().end_block = static_cast<uint32_t>(blocks.size());
    return programs;
}

double decimal_literal_value(std::string_view digits) {
    double v = 0;
    const char* first = digits.data();
    const char* last = first + digits.size();
    const auto res = std::from_chars(first, last, v, std::chars_format::fixed);
    if (res.ec == std::errc::result_out_of_range) {
        // Too many digits for a double: either huge or (all zeros after a
        // leading dot) tiny.
        const bool fraction_only = !digits.empty() && digits.front() == '.';
        return fraction_only ? 0.0 : std::numeric_limits<double>::infinity();
    }
    return v;
}

}  // namespace osplint
