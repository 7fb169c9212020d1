#include "raplas/core/row_hits.hpp"

#include <immintrin.h>

#include "raplas/core/cpu.hpp"

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

namespace {

// AVX2 lanes of one width: L values of T per vector.
struct Lanes8f {
    using T = float;
    using V = __m256;
    static constexpr std::uint32_t L = 8;
    __attribute__((target("avx2"))) static V set1(T x) { return _mm256_set1_ps(x); }
    __attribute__((target("avx2"))) static V load(const T* p, std::uint32_t valid) {
        if (valid >= L) return _mm256_loadu_ps(p);
        const __m256i idx = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        return _mm256_maskload_ps(p, _mm256_cmpgt_epi32(_mm256_set1_epi32(int(valid)), idx));
    }
    __attribute__((target("avx2"))) static void store(T* p, V v, std::uint32_t valid) {
        if (valid >= L) return _mm256_storeu_ps(p, v);
        const __m256i idx = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        _mm256_maskstore_ps(p, _mm256_cmpgt_epi32(_mm256_set1_epi32(int(valid)), idx), v);
    }
    __attribute__((target("avx2"))) static V add(V a, V b) { return _mm256_add_ps(a, b); }
    __attribute__((target("avx2"))) static V sub(V a, V b) { return _mm256_sub_ps(a, b); }
    __attribute__((target("avx2"))) static V mul(V a, V b) { return _mm256_mul_ps(a, b); }
    __attribute__((target("avx2"))) static V div(V a, V b) { return _mm256_div_ps(a, b); }
    __attribute__((target("avx2"))) static V bxor(V a, V b) { return _mm256_xor_ps(a, b); }
    __attribute__((target("avx2"))) static V band(V a, V b) { return _mm256_and_ps(a, b); }
    template <int C>
    __attribute__((target("avx2"))) static V cmp(V a, V b) {
        return _mm256_cmp_ps(a, b, C);
    }
    __attribute__((target("avx2"))) static std::uint32_t bits(V m) { return std::uint32_t(_mm256_movemask_ps(m)); }
};
struct Lanes4d {
    using T = double;
    using V = __m256d;
    static constexpr std::uint32_t L = 4;
    __attribute__((target("avx2"))) static V set1(T x) { return _mm256_set1_pd(x); }
    __attribute__((target("avx2"))) static V load(const T* p, std::uint32_t valid) {
        if (valid >= L) return _mm256_loadu_pd(p);
        const __m256i idx = _mm256_setr_epi64x(0, 1, 2, 3);
        return _mm256_maskload_pd(p, _mm256_cmpgt_epi64(_mm256_set1_epi64x(valid), idx));
    }
    __attribute__((target("avx2"))) static void store(T* p, V v, std::uint32_t valid) {
        if (valid >= L) return _mm256_storeu_pd(p, v);
        const __m256i idx = _mm256_setr_epi64x(0, 1, 2, 3);
        _mm256_maskstore_pd(p, _mm256_cmpgt_epi64(_mm256_set1_epi64x(valid), idx), v);
    }
    __attribute__((target("avx2"))) static V add(V a, V b) { return _mm256_add_pd(a, b); }
    __attribute__((target("avx2"))) static V sub(V a, V b) { return _mm256_sub_pd(a, b); }
    __attribute__((target("avx2"))) static V mul(V a, V b) { return _mm256_mul_pd(a, b); }
    __attribute__((target("avx2"))) static V div(V a, V b) { return _mm256_div_pd(a, b); }
    __attribute__((target("avx2"))) static V bxor(V a, V b) { return _mm256_xor_pd(a, b); }
    __attribute__((target("avx2"))) static V band(V a, V b) { return _mm256_and_pd(a, b); }
    template <int C>
    __attribute__((target("avx2"))) static V cmp(V a, V b) {
        return _mm256_cmp_pd(a, b, C);
    }
    __attribute__((target("avx2"))) static std::uint32_t bits(V m) { return std::uint32_t(_mm256_movemask_pd(m)); }
};

// rays_hit_triangle_native, lane for lane: unary minus is a sign flip (xor
// with -0.0), C++'s != is the unordered not-equal, the other comparisons
// ordered, as in the scalar code.
template <class W>
__attribute__((target("avx2"))) bool rows_avx2(const typename W::T o[3], typename W::T tmin, typename W::T tmax,
                                               const typename W::T* dx, const typename W::T* dy,
                                               const typename W::T* dz, std::uint32_t n, std::uint64_t rows,
                                               std::uint64_t cols, const TriA<ArithNative<typename W::T>>& tr,
                                               std::uint64_t* hits, typename W::T* t) {
    using T = typename W::T;
    using V = typename W::V;
    const T tx = o[0] - tr.v0[0], ty = o[1] - tr.v0[1], tz = o[2] - tr.v0[2];
    const T tp0 = -((tr.n[0] * tx + tr.n[1] * ty) + tr.n[2] * tz);
    const V vtx = W::set1(tx), vty = W::set1(ty), vtz = W::set1(tz), vtp0 = W::set1(tp0);
    const V n0 = W::set1(tr.n[0]), n1 = W::set1(tr.n[1]), n2 = W::set1(tr.n[2]);
    const V a0 = W::set1(tr.e1[0]), a1 = W::set1(tr.e1[1]), a2 = W::set1(tr.e1[2]);
    const V b0 = W::set1(tr.e2[0]), b1 = W::set1(tr.e2[1]), b2 = W::set1(tr.e2[2]);
    const V zero = W::set1(T(0)), sign = W::set1(T(-0.0)), vmin = W::set1(tmin), vmax = W::set1(tmax);
    const std::uint32_t h0 = std::uint32_t(__builtin_ctzll(cols)), h1 = 64 - std::uint32_t(__builtin_clzll(cols));
    std::uint64_t any = 0;
    for (std::uint64_t rm = rows; rm; rm &= rm - 1) {
        const std::uint32_t v = std::uint32_t(__builtin_ctzll(rm));
        std::uint64_t row = 0;
        for (std::uint32_t h = h0; h < h1; h += W::L) {
            // Whole vectors while the row has room (lanes past the last column
            // of `cols` are computed and dropped); a partial one at its end.
            const std::uint32_t valid = n - h;
            const std::size_t i = std::size_t(v) * n + h;
            const V d0 = W::load(dx + i, valid), d1 = W::load(dy + i, valid), d2 = W::load(dz + i, valid);
            const V cx = W::sub(W::mul(d1, vtz), W::mul(d2, vty));
            const V cy = W::sub(W::mul(d2, vtx), W::mul(d0, vtz));
            const V cz = W::sub(W::mul(d0, vty), W::mul(d1, vtx));
            const V det0 = W::add(W::add(W::mul(d0, n0), W::mul(d1, n1)), W::mul(d2, n2));
            const V u0 = W::add(W::add(W::mul(cx, b0), W::mul(cy, b1)), W::mul(cz, b2));
            const V v0 = W::bxor(W::add(W::add(W::mul(cx, a0), W::mul(cy, a1)), W::mul(cz, a2)), sign);
            const V flip = W::band(W::template cmp<_CMP_LT_OQ>(det0, zero), sign);
            const V det = W::bxor(det0, flip), u = W::bxor(u0, flip), vv = W::bxor(v0, flip);
            const V ti = W::div(W::bxor(vtp0, flip), det);
            V m = W::template cmp<_CMP_NEQ_UQ>(det0, zero);
            m = W::band(m, W::template cmp<_CMP_EQ_OQ>(det, det));
            m = W::band(m, W::template cmp<_CMP_GE_OQ>(u, zero));
            m = W::band(m, W::template cmp<_CMP_GE_OQ>(vv, zero));
            m = W::band(m, W::template cmp<_CMP_LE_OQ>(W::add(u, vv), det));
            m = W::band(m, W::template cmp<_CMP_GT_OQ>(ti, vmin));
            m = W::band(m, W::template cmp<_CMP_LT_OQ>(ti, vmax));
            const std::uint32_t b = W::bits(m);
            if (b) {
                row |= std::uint64_t(b) << h;
                W::store(t + i, ti, valid);
            }
        }
        hits[v] = row & cols;
        any |= hits[v];
    }
    return any != 0;
}

// rows_avx2 for float with sixteen lanes: a row of a 16 x 16 group in one
// vector. The same IEEE operations lane for lane; the comparisons give mask
// registers, ANDed as the AVX2 version ANDs its masks, and the sign flip of
// a negative determinant is -0.0 where the mask says so.
__attribute__((target("avx512f,avx512dq"))) bool rows_avx512(const float o[3], float tmin, float tmax,
                                                             const float* dx, const float* dy, const float* dz,
                                                             std::uint32_t n, std::uint64_t rows, std::uint64_t cols,
                                                             const TriA<ArithF32>& tr, std::uint64_t* hits, float* t) {
    using V = __m512;
    constexpr std::uint32_t L = 16;
    const float tx = o[0] - tr.v0[0], ty = o[1] - tr.v0[1], tz = o[2] - tr.v0[2];
    const float tp0 = -((tr.n[0] * tx + tr.n[1] * ty) + tr.n[2] * tz);
    const V vtx = _mm512_set1_ps(tx), vty = _mm512_set1_ps(ty), vtz = _mm512_set1_ps(tz), vtp0 = _mm512_set1_ps(tp0);
    const V n0 = _mm512_set1_ps(tr.n[0]), n1 = _mm512_set1_ps(tr.n[1]), n2 = _mm512_set1_ps(tr.n[2]);
    const V a0 = _mm512_set1_ps(tr.e1[0]), a1 = _mm512_set1_ps(tr.e1[1]), a2 = _mm512_set1_ps(tr.e1[2]);
    const V b0 = _mm512_set1_ps(tr.e2[0]), b1 = _mm512_set1_ps(tr.e2[1]), b2 = _mm512_set1_ps(tr.e2[2]);
    const V zero = _mm512_setzero_ps(), sign = _mm512_set1_ps(-0.0f), vmin = _mm512_set1_ps(tmin),
            vmax = _mm512_set1_ps(tmax);
    const std::uint32_t h0 = std::uint32_t(__builtin_ctzll(cols)), h1 = 64 - std::uint32_t(__builtin_clzll(cols));
    std::uint64_t any = 0;
    for (std::uint64_t rm = rows; rm; rm &= rm - 1) {
        const std::uint32_t v = std::uint32_t(__builtin_ctzll(rm));
        std::uint64_t row = 0;
        for (std::uint32_t h = h0; h < h1; h += L) {
            const std::uint32_t valid = n - h;
            const __mmask16 lanes = valid >= L ? __mmask16(0xffff) : __mmask16((1u << valid) - 1);
            const std::size_t i = std::size_t(v) * n + h;
            const V d0 = _mm512_maskz_loadu_ps(lanes, dx + i), d1 = _mm512_maskz_loadu_ps(lanes, dy + i),
                    d2 = _mm512_maskz_loadu_ps(lanes, dz + i);
            const V cx = _mm512_sub_ps(_mm512_mul_ps(d1, vtz), _mm512_mul_ps(d2, vty));
            const V cy = _mm512_sub_ps(_mm512_mul_ps(d2, vtx), _mm512_mul_ps(d0, vtz));
            const V cz = _mm512_sub_ps(_mm512_mul_ps(d0, vty), _mm512_mul_ps(d1, vtx));
            const V det0 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(d0, n0), _mm512_mul_ps(d1, n1)), _mm512_mul_ps(d2, n2));
            const V u0 = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(cx, b0), _mm512_mul_ps(cy, b1)), _mm512_mul_ps(cz, b2));
            const V v0 = _mm512_xor_ps(
                _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(cx, a0), _mm512_mul_ps(cy, a1)), _mm512_mul_ps(cz, a2)), sign);
            const V flip = _mm512_maskz_mov_ps(_mm512_cmp_ps_mask(det0, zero, _CMP_LT_OQ), sign);
            const V det = _mm512_xor_ps(det0, flip), u = _mm512_xor_ps(u0, flip), vv = _mm512_xor_ps(v0, flip);
            __mmask16 m = _mm512_mask_cmp_ps_mask(lanes, det0, zero, _CMP_NEQ_UQ);
            m = _mm512_mask_cmp_ps_mask(m, det, det, _CMP_EQ_OQ);
            m = _mm512_mask_cmp_ps_mask(m, u, zero, _CMP_GE_OQ);
            m = _mm512_mask_cmp_ps_mask(m, vv, zero, _CMP_GE_OQ);
            m = _mm512_mask_cmp_ps_mask(m, _mm512_add_ps(u, vv), det, _CMP_LE_OQ);
            // A division per lane costs as much in sixteen lanes as in eight:
            // none when no ray of the vector is inside the triangle's edges.
            if (!m) continue;
            const V ti = _mm512_div_ps(_mm512_xor_ps(vtp0, flip), det);
            m = _mm512_mask_cmp_ps_mask(m, ti, vmin, _CMP_GT_OQ);
            m = _mm512_mask_cmp_ps_mask(m, ti, vmax, _CMP_LT_OQ);
            if (m) {
                row |= std::uint64_t(m) << h;
                _mm512_mask_storeu_ps(t + i, lanes, ti);
            }
        }
        hits[v] = row & cols;
        any |= hits[v];
    }
    return any != 0;
}

template <class T>
bool rows_generic(const T o[3], T tmin, T tmax, const T* dx, const T* dy, const T* dz, std::uint32_t n,
                  std::uint64_t rows, std::uint64_t cols, const TriA<ArithNative<T>>& tr, std::uint64_t* hits, T* t) {
    std::uint8_t hb[64];
    bool any = false;
    for (std::uint64_t rm = rows; rm; rm &= rm - 1) {
        const std::uint32_t v = std::uint32_t(__builtin_ctzll(rm));
        const std::size_t base = std::size_t(v) * n;
        hits[v] = 0;
        if (!row_hits(o, tmin, tmax, dx + base, dy + base, dz + base, n, tr, hb, t + base)) continue;
        for (std::uint64_t cm = cols; cm; cm &= cm - 1) {
            const std::uint32_t h = std::uint32_t(__builtin_ctzll(cm));
            if (hb[h]) hits[v] |= std::uint64_t(1) << h;
        }
        any = any || hits[v];
    }
    return any;
}

}  // namespace

bool rows_hit_triangle(const float o[3], float tmin, float tmax, const float* dx, const float* dy, const float* dz,
                       std::uint32_t n, std::uint64_t rows, std::uint64_t cols, const TriA<ArithF32>& tr,
                       std::uint64_t* hits, float* t) {
    if (cpu_has_avx512() && cols) return rows_avx512(o, tmin, tmax, dx, dy, dz, n, rows, cols, tr, hits, t);
    const bool avx2 = cpu_has_avx2();
    if (avx2 && cols) return rows_avx2<Lanes8f>(o, tmin, tmax, dx, dy, dz, n, rows, cols, tr, hits, t);
    return rows_generic(o, tmin, tmax, dx, dy, dz, n, rows, cols, tr, hits, t);
}
bool rows_hit_triangle(const double o[3], double tmin, double tmax, const double* dx, const double* dy,
                       const double* dz, std::uint32_t n, std::uint64_t rows, std::uint64_t cols,
                       const TriA<ArithF64>& tr, std::uint64_t* hits, double* t) {
    const bool avx2 = cpu_has_avx2();
    if (avx2 && cols) return rows_avx2<Lanes4d>(o, tmin, tmax, dx, dy, dz, n, rows, cols, tr, hits, t);
    return rows_generic(o, tmin, tmax, dx, dy, dz, n, rows, cols, tr, hits, t);
}

}  // namespace raplas
