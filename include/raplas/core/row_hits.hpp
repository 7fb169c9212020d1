// One triangle against a row of rays that share an origin and (tmin, tmax):
// rays_hit_triangle_native (intersect.hpp) compiled for AVX2 as well as the
// baseline; the loader picks one per machine. There is no FMA either way
// (-ffp-contract=off), so every hit and distance is bit-identical to the
// ray-by-ray division-free test. Used by the front end's tracer and by the
// models' Ray-Triangle Intersector in the compute functional mode.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "raplas/core/bits.hpp"
#include "raplas/core/intersect.hpp"

namespace raplas {

bool row_hits(const float o[3], float tmin, float tmax, const float* dx, const float* dy, const float* dz,
              std::size_t count, const TriA<ArithF32>& tr, std::uint8_t* hit, float* t);
bool row_hits(const double o[3], double tmin, double tmax, const double* dx, const double* dy, const double* dz,
              std::size_t count, const TriA<ArithF64>& tr, std::uint8_t* hit, double* t);

// One triangle against the rays of rows x cols of an n x n group (n <= 64)
// whose directions are dx, dy, dz (ray v * n + h): for every row v of
// `rows`, hits[v] gets bit h set when ray (v, h), h in `cols`, hits, and
// t[v * n + h] its distance. Every hit and distance is bit-identical to
// row_hits (the same operations in the same order); the triangle's own terms
// are computed once, only the columns from the lowest to the highest of
// `cols` are evaluated, and on a machine with AVX2 8 floats or 4 doubles per
// vector. Returns whether any ray hits. src/core/row_hits.cpp.
bool rows_hit_triangle(const float o[3], float tmin, float tmax, const float* dx, const float* dy, const float* dz,
                       std::uint32_t n, std::uint64_t rows, std::uint64_t cols, const TriA<ArithF32>& tr,
                       std::uint64_t* hits, float* t);
bool rows_hit_triangle(const double o[3], double tmin, double tmax, const double* dx, const double* dy,
                       const double* dz, std::uint32_t n, std::uint64_t rows, std::uint64_t cols,
                       const TriA<ArithF64>& tr, std::uint64_t* hits, double* t);

// Whether rays_certainly_miss_triangle_native is worth asking before rows_hit_triangle for a
// sphere's rows x cols: the proof costs about as much as four vectors of rays (8 floats or 4
// doubles each, AVX2), so a mask that at most four vectors cover is tested directly. The answers
// are the same either way.
template <class T>
inline bool miss_proof_pays(std::uint64_t rows, std::uint64_t cols) {
    if (!rows || !cols) return false;
    constexpr std::uint32_t lanes = 32 / sizeof(T);
    const std::uint32_t span = std::uint32_t(64 - __builtin_clzll(cols)) - std::uint32_t(__builtin_ctzll(cols));
    return std::uint32_t(bit_count(rows)) * ((span + lanes - 1) / lanes) > 4;
}

// The rays' directions by component (dx[i], dy[i], dz[i]), as row_hits takes them.
template <class A>
void directions_by_component(const std::vector<RayA<A>>& rays, std::vector<typename A::T>& dx,
                             std::vector<typename A::T>& dy, std::vector<typename A::T>& dz) {
    dx.resize(rays.size());
    dy.resize(rays.size());
    dz.resize(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        dx[i] = rays[i].d[0];
        dy[i] = rays[i].d[1];
        dz[i] = rays[i].d[2];
    }
}

// The direction bounds of the rays of a sphere's rows x columns in an N x N group, for
// rays_certainly_miss_triangle_native: each row's and each column's box are computed once per
// group; the rays of H x V lie inside the union of the boxes of H's rows from its lowest to
// its highest and inside the union of those of V's columns, so inside their intersection.
// Unions of runs of 2^k rows (columns) are kept too, so that any span's box is the union of
// two of them. No bound (finite() false) when a direction is not finite.
template <class T>
class GroupDirectionBoxes {
public:
    void build(const std::vector<T>& dx, const std::vector<T>& dy, const std::vector<T>& dz, std::uint32_t n) {
        n_ = n;
        levels_ = 1;
        while ((std::uint32_t(1) << levels_) <= n) ++levels_;
        rows_.assign(std::size_t(levels_) * n, empty());
        cols_.assign(std::size_t(levels_) * n, empty());
        finite_ = true;
        for (std::uint32_t v = 0; v < n; ++v)
            for (std::uint32_t h = 0; h < n; ++h) {
                const std::size_t i = std::size_t(v) * n + h;
                const T d[3] = {dx[i], dy[i], dz[i]};
                for (int c = 0; c < 3; ++c) {
                    finite_ = finite_ && std::isfinite(d[c]);
                    widen(rows_[v], c, d[c], d[c]);
                    widen(cols_[h], c, d[c], d[c]);
                }
            }
        for (std::uint32_t k = 1; k < levels_; ++k) {
            const std::uint32_t half = std::uint32_t(1) << (k - 1);
            for (std::uint32_t i = 0; i + 2 * half <= n; ++i)
                for (auto* t : {&rows_, &cols_}) {
                    DirectionBox<T> b = (*t)[std::size_t(k - 1) * n + i];
                    add(b, (*t)[std::size_t(k - 1) * n + i + half]);
                    (*t)[std::size_t(k) * n + i] = b;
                }
        }
    }
    bool finite() const { return finite_; }
    // rows, cols: non-empty masks
    DirectionBox<T> of(std::uint64_t rows, std::uint64_t cols) const {
        DirectionBox<T> r = span(rows_, rows), c = span(cols_, cols);
        for (int k = 0; k < 3; ++k) {
            r.lo[k] = std::max(r.lo[k], c.lo[k]);
            r.hi[k] = std::min(r.hi[k], c.hi[k]);
        }
        return r;
    }

private:
    // The union of the boxes from the lowest to the highest bit of `mask`.
    DirectionBox<T> span(const std::vector<DirectionBox<T>>& t, std::uint64_t mask) const {
        const auto lo = std::uint32_t(__builtin_ctzll(mask)), hi = 63 - std::uint32_t(__builtin_clzll(mask));
        const std::uint32_t k = 31 - std::uint32_t(__builtin_clz(hi - lo + 1));
        DirectionBox<T> b = t[std::size_t(k) * n_ + lo];
        add(b, t[std::size_t(k) * n_ + hi + 1 - (std::uint32_t(1) << k)]);
        return b;
    }
    static DirectionBox<T> empty() {
        DirectionBox<T> b;
        for (int k = 0; k < 3; ++k) {
            b.lo[k] = std::numeric_limits<T>::infinity();
            b.hi[k] = -std::numeric_limits<T>::infinity();
        }
        return b;
    }
    static void widen(DirectionBox<T>& b, int k, T lo, T hi) {
        b.lo[k] = std::min(b.lo[k], lo);
        b.hi[k] = std::max(b.hi[k], hi);
    }
    static void add(DirectionBox<T>& b, const DirectionBox<T>& o) {
        for (int k = 0; k < 3; ++k) widen(b, k, o.lo[k], o.hi[k]);
    }
    std::vector<DirectionBox<T>> rows_, cols_;  // level k, index i: the union of [i, i + 2^k)
    std::uint32_t n_ = 0, levels_ = 0;
    bool finite_ = false;
};

}  // namespace raplas
