#include "raplas/core/row_hits.hpp"

namespace raplas {

__attribute__((target_clones("avx2", "default"))) bool row_hits(const float o[3], float tmin, float tmax,
                                                                const float* dx, const float* dy, const float* dz,
                                                                std::size_t count, const TriA<ArithF32>& tr,
                                                                std::uint8_t* hit, float* t) {
    return rays_hit_triangle_native<float>(o, tmin, tmax, dx, dy, dz, count, tr, hit, t);
}
__attribute__((target_clones("avx2", "default"))) bool row_hits(const double o[3], double tmin, double tmax,
                                                                const double* dx, const double* dy, const double* dz,
                                                                std::size_t count, const TriA<ArithF64>& tr,
                                                                std::uint8_t* hit, double* t) {
    return rays_hit_triangle_native<double>(o, tmin, tmax, dx, dy, dz, count, tr, hit, t);
}

}  // namespace raplas
