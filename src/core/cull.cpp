#include "raplas/core/cull.hpp"

namespace raplas::cull_detail {

// plane_misses_node over a row of planes, branch-free so that it vectorises.
__attribute__((target_clones("avx2", "default"))) std::uint64_t planes_may_hit_node(const PlanesD& p,
                                                                                   std::uint32_t first,
                                                                                   std::uint32_t count,
                                                                                   const SphereTree::Node& nd,
                                                                                   const ArithBounds& b) {
    std::uint8_t hit[128];
    for (std::uint32_t i = 0; i < count; ++i) hit[i] = !plane_misses_node(p, first + i, nd, b);
    std::uint64_t m = 0;
    for (std::uint32_t i = 0; i < count; ++i) m |= std::uint64_t(hit[i]) << i;
    return m;
}

namespace {
template <class T>
inline void leaf_masks(const LeafSpheres<T>& l, const PlaneA<ArithNative<T>>* planes, std::uint32_t mask,
                       std::uint32_t* out) {
    constexpr std::uint32_t k = SphereTree::kLeaf;
    std::uint32_t m[k] = {};
    for (; mask; mask &= mask - 1) {
        const std::uint32_t p = static_cast<std::uint32_t>(__builtin_ctz(mask));
        const PlaneA<ArithNative<T>> pl = planes[p];
        for (std::uint32_t i = 0; i < k; ++i) {
            const T d = ((pl.nx * l.cx[i] + pl.ny * l.cy[i]) + pl.nz * l.cz[i]) + pl.w;
            m[i] |= std::uint32_t(std::fabs(d) <= l.r[i]) << p;
        }
    }
    for (std::uint32_t i = 0; i < k; ++i) out[i] = m[i];
}
}  // namespace

__attribute__((target_clones("avx2", "default"))) void leaf_plane_masks(const LeafSpheres<float>& l,
                                                                        const PlaneA<ArithF32>* planes,
                                                                        std::uint32_t mask, std::uint32_t* out) {
    leaf_masks(l, planes, mask, out);
}
__attribute__((target_clones("avx2", "default"))) void leaf_plane_masks(const LeafSpheres<double>& l,
                                                                        const PlaneA<ArithF64>* planes,
                                                                        std::uint32_t mask, std::uint32_t* out) {
    leaf_masks(l, planes, mask, out);
}

}  // namespace raplas::cull_detail
