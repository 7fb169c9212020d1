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
// group; the rays of H x V lie inside the union of H's row boxes and inside the union of V's
// column boxes, so inside their intersection. No bound (finite() false) when a direction is
// not finite.
template <class T>
class GroupDirectionBoxes {
public:
    void build(const std::vector<T>& dx, const std::vector<T>& dy, const std::vector<T>& dz, std::uint32_t n) {
        rows_.assign(n, empty());
        cols_.assign(n, empty());
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
    }
    bool finite() const { return finite_; }
    // rows, cols: non-empty masks
    DirectionBox<T> of(std::uint64_t rows, std::uint64_t cols) const {
        DirectionBox<T> r = empty(), c = empty();
        for (; rows; rows &= rows - 1) add(r, rows_[std::size_t(__builtin_ctzll(rows))]);
        for (; cols; cols &= cols - 1) add(c, cols_[std::size_t(__builtin_ctzll(cols))]);
        for (int k = 0; k < 3; ++k) {
            r.lo[k] = std::max(r.lo[k], c.lo[k]);
            r.hi[k] = std::min(r.hi[k], c.hi[k]);
        }
        return r;
    }

private:
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
    std::vector<DirectionBox<T>> rows_, cols_;
    bool finite_ = false;
};

}  // namespace raplas
