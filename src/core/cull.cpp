#include "raplas/core/cull.hpp"

#include <immintrin.h>

#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>

#include "raplas/core/cpu.hpp"

namespace raplas::cull_detail {

namespace {

// GCC vector types of N lanes of T: a leaf's 8 floats fill one AVX2 register
// (8 doubles two; the baseline clone uses SSE2 registers). Every lane does
// the scalar code's IEEE operations in the same order (no FMA:
// -ffp-contract=off), so the results are those of the scalar tests, lane for
// lane.
template <class T, int N>
struct Vec {
    typedef T type __attribute__((vector_size(N * sizeof(T))));
};

// The helpers are always inlined, so no vector crosses a call; GCC warns
// about the ABI of such calls at the end of the file, hence no pop.
#pragma GCC diagnostic ignored "-Wpsabi"

template <class V, class T>
__attribute__((always_inline)) inline V load_v(const T* p) {
    V v;
    std::memcpy(&v, p, sizeof(V));
    return v;
}
template <class V, class T>
__attribute__((always_inline)) inline V splat(T x) {
    return V{} + x;
}
// |x| lane by lane, as std::fabs: the sign bit cleared.
template <class V, class I>
__attribute__((always_inline)) inline V abs_v(V x) {
    using Lane = std::remove_reference_t<decltype(std::declval<I>()[0])>;
    I bits;
    std::memcpy(&bits, &x, sizeof(V));
    bits &= I{} + std::numeric_limits<Lane>::max();
    std::memcpy(&x, &bits, sizeof(V));
    return x;
}

// plane_misses_node over planes [first, first + count), four per AVX2
// vector: the same operations in the same order, so the same answers.
__attribute__((target("avx2"))) std::uint64_t planes_missed_avx2(const PlanesD& p, std::uint32_t first,
                                                                  std::uint32_t count, const SphereTree::Node& nd) {
    const __m256d cx = _mm256_set1_pd(nd.cx), cy = _mm256_set1_pd(nd.cy), cz = _mm256_set1_pd(nd.cz);
    const __m256d ex = _mm256_set1_pd(nd.ex), ey = _mm256_set1_pd(nd.ey), ez = _mm256_set1_pd(nd.ez);
    const __m256d sign = _mm256_set1_pd(-0.0);
    std::uint64_t miss = 0;
    for (std::uint32_t i = 0; i < count; i += 4) {
        const std::uint32_t k = first + i;  // PlanesD holds spare entries past the last plane
        const __m256d d = _mm256_add_pd(
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(p.nx + k), cx),
                                        _mm256_mul_pd(_mm256_loadu_pd(p.ny + k), cy)),
                          _mm256_mul_pd(_mm256_loadu_pd(p.nz + k), cz)),
            _mm256_loadu_pd(p.w + k));
        const __m256d ext = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(p.ax + k), ex),
                                                        _mm256_mul_pd(_mm256_loadu_pd(p.ay + k), ey)),
                                          _mm256_mul_pd(_mm256_loadu_pd(p.az + k), ez));
        const __m256d limit = _mm256_add_pd(ext, _mm256_loadu_pd(p.slack + k));
        const __m256d gt = _mm256_cmp_pd(_mm256_andnot_pd(sign, d), limit, _CMP_GT_OQ);
        miss |= std::uint64_t(_mm256_movemask_pd(gt)) << i;
    }
    return miss;
}

// The same, eight planes per AVX-512 vector (|d| by _mm512_abs_pd, which
// clears the sign bit as the AVX2 version's andnot does).
__attribute__((target("avx512f"))) std::uint64_t planes_missed_avx512(const PlanesD& p, std::uint32_t first,
                                                                      std::uint32_t count, const SphereTree::Node& nd) {
    const __m512d cx = _mm512_set1_pd(nd.cx), cy = _mm512_set1_pd(nd.cy), cz = _mm512_set1_pd(nd.cz);
    const __m512d ex = _mm512_set1_pd(nd.ex), ey = _mm512_set1_pd(nd.ey), ez = _mm512_set1_pd(nd.ez);
    std::uint64_t miss = 0;
    for (std::uint32_t i = 0; i < count; i += 8) {
        const std::uint32_t k = first + i;  // PlanesD holds 8 spare entries past the last plane
        const __m512d d = _mm512_add_pd(
            _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(_mm512_loadu_pd(p.nx + k), cx),
                                        _mm512_mul_pd(_mm512_loadu_pd(p.ny + k), cy)),
                          _mm512_mul_pd(_mm512_loadu_pd(p.nz + k), cz)),
            _mm512_loadu_pd(p.w + k));
        const __m512d ext = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(_mm512_loadu_pd(p.ax + k), ex),
                                                        _mm512_mul_pd(_mm512_loadu_pd(p.ay + k), ey)),
                                          _mm512_mul_pd(_mm512_loadu_pd(p.az + k), ez));
        const __m512d limit = _mm512_add_pd(ext, _mm512_loadu_pd(p.slack + k));
        miss |= std::uint64_t(_mm512_cmp_pd_mask(_mm512_abs_pd(d), limit, _CMP_GT_OQ)) << i;
    }
    return miss;
}

std::uint64_t planes_missed_scalar(const PlanesD& p, std::uint32_t first, std::uint32_t count,
                                   const SphereTree::Node& nd) {
    std::uint64_t m = 0;
    for (std::uint32_t i = 0; i < count; ++i) m |= std::uint64_t(plane_misses_node(p, first + i, nd)) << i;
    return m;
}

}  // namespace

std::uint64_t planes_may_hit_node(const PlanesD& p, std::uint32_t first, std::uint32_t count,
                                  const SphereTree::Node& nd) {
    // Each version sets bit i when it proves plane first + i misses; the
    // vector ones may also set bits at and past `count` (lanes read past it).
    const std::uint64_t missed = cpu_has_avx512() ? planes_missed_avx512(p, first, count, nd)
                                 : cpu_has_avx2() ? planes_missed_avx2(p, first, count, nd)
                                                  : planes_missed_scalar(p, first, count, nd);
    const std::uint64_t all = count >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << count) - 1;
    return ~missed & all;
}

namespace {
template <class T>
__attribute__((always_inline)) inline void leaf_masks(const LeafView<T>& l, const PlaneA<ArithNative<T>>* planes,
                                                     std::uint32_t mask, std::uint32_t* out) {
    constexpr int k = static_cast<int>(SphereTree::kLeaf);
    using V = typename Vec<T, k>::type;
    using Lane = std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>;
    using I = typename Vec<Lane, k>::type;
    const V cx = load_v<V>(l.cx), cy = load_v<V>(l.cy), cz = load_v<V>(l.cz), r = load_v<V>(l.r);
    I m{};
    for (; mask; mask &= mask - 1) {
        const std::uint32_t p = static_cast<std::uint32_t>(__builtin_ctz(mask));
        const PlaneA<ArithNative<T>> pl = planes[p];
        const V d = ((splat<V>(pl.nx) * cx + splat<V>(pl.ny) * cy) + splat<V>(pl.nz) * cz) + splat<V>(pl.w);
        m |= (abs_v<V, I>(d) <= r) & (I{} + static_cast<Lane>(std::uint32_t(1) << p));
    }
    for (int i = 0; i < k; ++i) out[i] = static_cast<std::uint32_t>(m[i]);
}
}  // namespace

__attribute__((target_clones("avx2", "default"))) void leaf_plane_masks(const LeafView<float>& l,
                                                                        const PlaneA<ArithF32>* planes,
                                                                        std::uint32_t mask, std::uint32_t* out) {
    leaf_masks(l, planes, mask, out);
}
__attribute__((target_clones("avx2", "default"))) void leaf_plane_masks(const LeafView<double>& l,
                                                                        const PlaneA<ArithF64>* planes,
                                                                        std::uint32_t mask, std::uint32_t* out) {
    leaf_masks(l, planes, mask, out);
}

}  // namespace raplas::cull_detail
