// What the machine running the simulator can do, for kernels written for
// AVX2 beside a baseline x86-64 version: asked once, the answer kept. With
// RAPLAS_CPU_BASELINE set in the environment the baseline versions run on
// any machine (the tests run both; the answers are the same bit for bit).
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

}  // namespace raplas
