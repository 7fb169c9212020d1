// What the machine running the simulator can do, for kernels written for
// AVX2 beside a baseline x86-64 version: asked once, the answer kept.
#pragma once

namespace raplas {

inline bool cpu_has_avx2() {
    static const bool avx2 = [] {
        __builtin_cpu_init();  // may run before the constructors that would call it
        return __builtin_cpu_supports("avx2") != 0;
    }();
    return avx2;
}

}  // namespace raplas
