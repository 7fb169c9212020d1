// Equality of the bits, not the values: -0.0 and 0.0 differ, a NaN equals
// itself. For "bit for bit the same" checks of floating-point data.
#pragma once

#include <cstring>
#include <vector>

namespace raplas {

template <class T>
bool same_bits(const T& a, const T& b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace raplas
