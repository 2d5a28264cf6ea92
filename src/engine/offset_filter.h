// A set of block offsets that answers "not in it" for most offsets in a few
// instructions: one bit per hashed offset, set for every offset added and
// cleared only all at once. The walk asks it before searching a map keyed
// by offset, once per block; a search that it lets through may still find
// nothing (another offset with the same bit). Internal to the engine.
#pragma once

#include <array>
#include <cstdint>

namespace osplint {

class OffsetFilter {
public:
    void add(uint32_t offset) {
        const uint32_t s = slot(offset);
        bits_[s >> 6] |= uint64_t(1) << (s & 63);
    }
    bool may_hold(uint32_t offset) const {
        const uint32_t s = slot(offset);
        return (bits_[s >> 6] >> (s & 63)) & 1;
    }
    void clear() { bits_.fill(0); }

private:
    static constexpr unsigned kBits = 16;  // 65,536 bits: 8 KiB
    static uint32_t slot(uint32_t offset) { return (offset * 2654435761u) >> (32 - kBits); }
    std::array<uint64_t, (size_t(1) << kBits) / 64> bits_{};
};

}  // namespace osplint
