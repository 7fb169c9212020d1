// What the machine running the simulator can do, for kernels written for
// AVX2 (and some for AVX-512) beside a baseline x86-64 version: asked once,
// the answer kept. With RAPLAS_CPU_BASELINE set in the environment the
// baseline versions run on any machine, with RAPLAS_CPU_NO_AVX512 the AVX2
// ones on a machine with AVX-512 (the tests run every version the machine
// has; the answers are the same bit for bit).
#pragma once

#include <cstdlib>

namespace raplas {

inline bool cpu_has_avx2() {
    static const bool avx2 = [] {
        if (std::getenv("RAPLAS_CPU_BASELINE")) return false;
        __builtin_cpu_init();  // may run before the constructors that would call it
        return __builtin_cpu_supports("avx2") != 0;
    }();
    return avx2;
}

// AVX-512 F and DQ (every AVX-512 processor but the first Xeon Phi).
inline bool cpu_has_avx512() {
    static const bool avx512 = [] {
        if (!cpu_has_avx2() || std::getenv("RAPLAS_CPU_NO_AVX512")) return false;
        return __builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512dq") != 0;
    }();
    return avx512;
}

}  // namespace raplas
