#include "raplas/core/cull.hpp"

namespace raplas::cull_detail {

// plane_misses_node's test (the same bound) over a row of planes, branch-free.
__attribute__((target_clones("avx2", "default"))) std::uint64_t planes_may_hit_node(const PlanesD& p,
                                                                                   std::uint32_t first,
                                                                                   std::uint32_t count,
                                                                                   const SphereTree::Node& nd,
                                                                                   const ArithBounds& b) {
    const double u = std::max(b.rel, 0x1p-52);
    const double reach = nd.cnorm + nd.r, ur = u * nd.r + 16 * b.abs;
    const double cx = nd.cx, cy = nd.cy, cz = nd.cz, r = nd.r;
    std::uint8_t hit[128];
    for (std::uint32_t i = 0; i < count; ++i) {
        const std::uint32_t k = first + i;
        const double d = p.nx[k] * cx + p.ny[k] * cy + p.nz[k] * cz + p.w[k];
        const double slack = 8 * u * (p.nnorm[k] * reach + p.aw[k]) + ur;
        hit[i] = !(std::fabs(d) > p.a[k] * r + slack);
    }
    std::uint64_t m = 0;
    for (std::uint32_t i = 0; i < count; ++i) m |= std::uint64_t(hit[i]) << i;
    return m;
}

}  // namespace raplas::cull_detail
