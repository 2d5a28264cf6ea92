// What both front ends share (frontend.h): the split of blocks into programs
// and the value of a decimal literal, so that they agree on both.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
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

std::optional<double> decimal_literal_value(std::string_view digits) {
    double v = 0;
    const char* first = digits.data();
    const char* last = first + digits.size();
    const auto res = std::from_chars(first, last, v, std::chars_format::fixed);
    if (res.ec == std::errc::result_out_of_range) {
        // Out of the range of a double: tiny when the whole part is zero
        // (`.000...1`, `0.000...1`), which is 0 as near as a double gets; huge
        // otherwise, and then the literal has no value.
        const std::string_view whole = digits.substr(0, digits.find('.'));
        const bool tiny = whole.find_first_not_of('0') == std::string_view::npos;
        if (tiny) return 0.0;
        return std::nullopt;
    }
    if (!std::isfinite(v)) return std::nullopt;
    return v;
}

std::string number_too_large_message(std::string_view literal) {
    const size_t digits = static_cast<size_t>(std::count_if(literal.begin(), literal.end(), [](char c) {
        return c != '.' && c != '#' && c != 'H' && c != 'h';
    }));
    std::string shown(literal);
    if (shown.size() > 24) shown = shown.substr(0, 12) + "..." + shown.substr(shown.size() - 8);
    return "the number " + shown + " (" + std::to_string(digits) + " digits) is too large to be read as a value";
}

}  // namespace osplint
