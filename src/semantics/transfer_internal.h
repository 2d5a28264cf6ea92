// Helpers shared by the transfer function (transfer.cpp) and the resolution
// of the macro a block runs (transfer_call.cpp). Not part of the public
// interface: see transfer.h.
#pragma once

#include <string_view>

#include "syntax/model.h"

namespace osplint::transfer_detail {

inline bool is_axis_address(std::string_view a) {
    return a.size() == 1 && (a[0] == 'X' || a[0] == 'Y' || a[0] == 'Z' || a[0] == 'A' || a[0] == 'B' ||
                             a[0] == 'C' || a[0] == 'U' || a[0] == 'V' || a[0] == 'W');
}

inline bool has_axis_word(const Block& b) {
    for (const auto& w : b.words)
        if (is_axis_address(w.address)) return true;
    return false;
}

inline bool has_coord_calc(const Block& b) {
    for (const auto& s : b.statements)
        if (s.kind == StmtKind::CoordCalc) return true;
    return false;
}

}  // namespace osplint::transfer_detail
