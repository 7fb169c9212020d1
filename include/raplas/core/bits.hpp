// Bit counting for plane masks, inline: the baseline x86-64 target has no
// population-count instruction, and the compiler's builtin then calls a
// library routine.
#pragma once

#include <cstdint>

namespace raplas {

inline int bit_count(std::uint64_t x) {
    x = x - ((x >> 1) & 0x5555555555555555ULL);
    x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fULL;
    return static_cast<int>((x * 0x0101010101010101ULL) >> 56);
}

}  // namespace raplas
