// Sphere culling for the plane-sphere step: a tree of bounding spheres over
// contiguous ranges of Sphere Memory lets a ray group skip, with a proof, the
// spheres that none of its row planes (or none of its column planes) can hit
// in the intersector's number format. The spheres that remain get the exact
// Eq. 1 test of intersect.hpp, so the result of group_sphere_hits_culled()
// equals group_sphere_hits() bit for bit, in every format. The machine itself
// still tests every sphere (the counts of plane tests are the hardware's);
// culling only makes the simulator faster. No dependencies.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "raplas/core/bits.hpp"
#include "raplas/core/intersect.hpp"
#include "raplas/core/numfmt.hpp"

namespace raplas {

// Error bounds of an arithmetic for the culling proof: one operation's
// relative error is at most `rel`, and results below `abs` in magnitude may be
// flushed or rounded by up to `abs`; `max` is the largest finite value.
struct ArithBounds {
    double rel = 0, abs = 0, max = 0;
};
inline ArithBounds arith_bounds(const ArithF64&) { return {std::ldexp(1.0, -53), 0x1p-1022, 1.7976931348623157e308}; }
inline ArithBounds arith_bounds(const ArithF32&) { return {std::ldexp(1.0, -24), 0x1p-126, 3.4028234663852886e38}; }
inline ArithBounds arith_bounds(const ArithSoft& a) {
    // An adder without post-normalisation keeps the larger operand's exponent:
    // it loses at most one more bit than a normalising one (relative to the
    // larger operand), which the factor 2 covers.
    return {a.f.unit_roundoff() * (a.normalize_add ? 1.0 : 2.0), a.f.min_normal(), a.f.max_finite()};
}

// A binary tree over Sphere Memory: every node covers a contiguous index
// range [lo, hi) and holds a sphere (in double) enclosing all its spheres.
// Leaves hold at most kLeaf spheres. Nodes are in pre-order: a node's left
// child follows it, `right` is the index of its right child.
class SphereTree {
public:
    static constexpr std::uint32_t kLeaf = 8;
    // 32 bytes, two to a cache line: a group's walk reads thousands of them.
    // The centre is rounded to float, the radius is measured from that float
    // centre and rounded up, and |centre| is rounded up: the node still holds
    // its spheres (the tests read it in double).
    struct alignas(32) Node {
        float cx, cy, cz, r;
        float cnorm;  // >= |centre|
        std::uint32_t lo, hi, right;
    };

    SphereTree() = default;
    explicit SphereTree(const std::vector<Sphere>& spheres) {
        if (spheres.empty()) return;
        nodes_.reserve(2 * (spheres.size() / kLeaf + 1));
        build(spheres, 0, static_cast<std::uint32_t>(spheres.size()));
    }
    const std::vector<Node>& nodes() const { return nodes_; }
    bool empty() const { return nodes_.empty(); }

private:
    std::vector<Node> nodes_;

    // The least float at or above x (x >= 0, finite).
    static float up_to_float(double x) {
        const float f = float(x);
        return double(f) >= x ? f : std::nextafter(f, HUGE_VALF);
    }

    std::uint32_t build(const std::vector<Sphere>& s, std::uint32_t lo, std::uint32_t hi) {
        // Centre of the bounding box of the spheres, radius reaching the
        // farthest sphere surface (computed in double, rounded up below).
        double mn[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, mx[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        for (std::uint32_t i = lo; i < hi; ++i) {
            const double c[3] = {s[i].c.x, s[i].c.y, s[i].c.z};
            for (int k = 0; k < 3; ++k) {
                mn[k] = std::min(mn[k], c[k] - double(s[i].r));
                mx[k] = std::max(mx[k], c[k] + double(s[i].r));
            }
        }
        Node n{};
        n.cx = float(0.5 * (mn[0] + mx[0]));
        n.cy = float(0.5 * (mn[1] + mx[1]));
        n.cz = float(0.5 * (mn[2] + mx[2]));
        const double cx = n.cx, cy = n.cy, cz = n.cz;  // (the float centre, exactly)
        double r = 0;
        for (std::uint32_t i = lo; i < hi; ++i) {
            const double dx = s[i].c.x - cx, dy = s[i].c.y - cy, dz = s[i].c.z - cz;
            r = std::max(r, std::sqrt(dx * dx + dy * dy + dz * dz) + double(s[i].r));
        }
        n.r = up_to_float(r * (1 + 0x1p-40));  // cover the rounding of the distances above
        n.cnorm = up_to_float(std::sqrt(cx * cx + cy * cy + cz * cz) * (1 + 0x1p-50));
        n.lo = lo;
        n.hi = hi;
        n.right = 0;
        const auto self = static_cast<std::uint32_t>(nodes_.size());
        nodes_.push_back(n);
        if (hi - lo > kLeaf) {
            // Split so that the left part is a whole number of leaves: ranges
            // stay aligned with the sphere builder's leaf order.
            const std::uint32_t leaves = (hi - lo + kLeaf - 1) / kLeaf;
            const std::uint32_t mid = lo + (leaves / 2) * kLeaf;
            build(s, lo, mid);
            const std::uint32_t right = build(s, mid, hi);
            nodes_[self].right = right;
        }
        return self;
    }
};

namespace cull_detail {

// A group's planes as the proof sees them (structure of arrays, so that
// many are tested at once): their float32 records in double, |n| (rounded
// up), and the parts of the error bound that depend only on the plane. Eight
// spare entries past the 128th let a vector of eight read past the last plane.
struct PlanesD {
    double nx[136], ny[136], nz[136], w[136], aw[136], nnorm[136], a[136];  // aw = |w|, a = max(|n|, 1)
};

// True when no sphere of node `nd` can be hit by plane `k` in an arithmetic
// with bounds `b`: the double distance from the node centre exceeds the
// node radius by more than any rounding of the exact test could make up.
//
// For a sphere (c, r) inside the node (|c - C| + r <= R),
// |n.c + w| - r >= |n.C + w| - max(|n|, 1) R.
// The format's result d' differs from n.c + w by at most
// 8 u (|n| |c| + |w|) + 8 abs (inputs rounded into the format, three
// products, three sums: a (1+u)^6 bound, doubled for safety, plus flushing),
// and its radius r' from r by at most u r + abs; |c| <= |C| + R, r <= R. The
// distance computed here in double is itself within 4 * 2^-53 (|n||C|+|w|).
inline bool plane_misses_node(const PlanesD& p, std::uint32_t k, const SphereTree::Node& nd, const ArithBounds& b) {
    const double d = p.nx[k] * nd.cx + p.ny[k] * nd.cy + p.nz[k] * nd.cz + p.w[k];
    const double u = std::max(b.rel, 0x1p-52);
    const double scale = p.nnorm[k] * (nd.cnorm + nd.r) + p.aw[k];
    const double slack = 8 * u * scale + u * nd.r + 16 * b.abs;
    return std::fabs(d) > p.a[k] * nd.r + slack;
}

// The same test for planes [first, first + count) at once (count <= 64): bit
// i of the result is set when plane first + i may hit the node (the test
// above does not prove a miss). src/core/cull.cpp: eight planes per AVX-512
// vector or four per AVX2 vector where the machine has them, else plane by
// plane.
std::uint64_t planes_may_hit_node(const PlanesD& p, std::uint32_t first, std::uint32_t count, const SphereTree::Node& nd,
                                  const ArithBounds& b);

// A leaf's spheres: kLeaf consecutive entries of each array (a leaf with
// fewer spheres is copied into LeafSpheres, padded with radius -1, which no
// plane hits), and Eq. 1 for the planes of `mask` (at most 32) against all
// of them in vector lanes: out[i] bit p set when plane p hits sphere i,
// bit-identical to plane_hits_sphere (the same operations; no FMA).
// src/core/cull.cpp.
template <class T>
struct LeafView {
    const T *cx, *cy, *cz, *r;
};
template <class T>
struct LeafSpheres {
    T cx[SphereTree::kLeaf], cy[SphereTree::kLeaf], cz[SphereTree::kLeaf], r[SphereTree::kLeaf];
    LeafView<T> view() const { return {cx, cy, cz, r}; }
};
void leaf_plane_masks(const LeafView<float>& l, const PlaneA<ArithF32>* planes, std::uint32_t mask, std::uint32_t* out);
void leaf_plane_masks(const LeafView<double>& l, const PlaneA<ArithF64>* planes, std::uint32_t mask, std::uint32_t* out);

}  // namespace cull_detail

// Whether culling can be proven for these values in this arithmetic: every
// magnitude that enters the test stays far below the format's largest finite
// value (an overflow could otherwise turn a radius into infinity).
template <class A>
inline bool culling_applies(const A& a, const SphereTree& tree, const Plane* planes, std::uint32_t np) {
    if (tree.empty()) return false;
    const ArithBounds b = arith_bounds(a);
    const auto& root = tree.nodes().front();
    double m = root.cnorm + root.r;
    for (std::uint32_t p = 0; p < np; ++p) {
        const double nn = std::fabs(planes[p].n.x) + std::fabs(planes[p].n.y) + std::fabs(planes[p].n.z);
        m = std::max(m, std::max(nn * (root.cnorm + root.r), double(std::fabs(planes[p].w))));
    }
    return std::isfinite(m) && 64 * m < b.max;
}

// group_sphere_hits() with culling: the same records, in the same (sphere)
// order, with the same masks. `planes` are the group's records (as loaded
// into `planes_a`): rows [0, n), columns [n, 2n). Falls back to the full
// test when culling_applies() is false. With `pairless` (the spheres cut by
// row planes only or column planes only), a node is skipped only when every
// row plane and every column plane misses it.
template <class A>
inline void group_sphere_hits_culled(const A& a, const Plane* planes, const PlaneA<A>* planes_a, std::uint32_t n,
                                     std::uint64_t row_valid, std::uint64_t col_valid, const SphereSoA<A>& s,
                                     const SphereTree& tree, std::vector<SphereHitRec>& out,
                                     std::vector<SphereRun>* pairless = nullptr) {
    if (!culling_applies(a, tree, planes, 2 * n)) {
        group_sphere_hits(a, planes_a, n, row_valid, col_valid, s, out, pairless);
        return;
    }
    out.clear();
    if (pairless) pairless->clear();
    const ArithBounds b = arith_bounds(a);
    thread_local cull_detail::PlanesD pd;
    for (std::uint32_t p = 0; p < 2 * n; ++p) {
        const double nx = planes[p].n.x, ny = planes[p].n.y, nz = planes[p].n.z;
        pd.nx[p] = nx;
        pd.ny[p] = ny;
        pd.nz[p] = nz;
        pd.w[p] = planes[p].w;
        pd.aw[p] = std::fabs(pd.w[p]);
        pd.nnorm[p] = std::sqrt(nx * nx + ny * ny + nz * nz) * (1 + 0x1p-50);
        pd.a[p] = std::max(pd.nnorm[p], 1.0);
    }
    const auto& nodes = tree.nodes();
    // Narrow a plane mask to the planes that may hit node nd: the planes
    // from its lowest to its highest bit in one vectorised test.
    auto narrow = [&](std::uint64_t mask, std::uint32_t base, const SphereTree::Node& nd) {
        if (!mask) return mask;
        const auto first = static_cast<std::uint32_t>(__builtin_ctzll(mask));
        const auto count = static_cast<std::uint32_t>(64 - __builtin_clzll(mask)) - first;
        return mask & (cull_detail::planes_may_hit_node(pd, base + first, count, nd, b) << first);
    };
    // Depth-first, left before right: leaves come in sphere order.
    struct Item {
        std::uint32_t node;
        std::uint64_t rows, cols;
    };
    Item stack[64];
    int top = 0;
    stack[top++] = {0, row_valid, col_valid};
    while (top > 0) {
        const Item it = stack[--top];
        const SphereTree::Node& nd = nodes[it.node];
        const std::uint64_t rows = narrow(it.rows, 0, nd);
        if (!rows && !pairless) continue;
        const std::uint64_t cols = narrow(it.cols, n, nd);
        if (!cols && (!pairless || !rows)) continue;
        if (nd.right) {
            stack[top++] = {nd.right, rows, cols};
            stack[top++] = {it.node + 1, rows, cols};
            continue;
        }
        // Leaf: the exact Eq. 1 test for the planes that may hit; in the
        // native formats all the leaf's spheres at once, plane by plane.
        if constexpr (std::is_same_v<A, ArithF32> || std::is_same_v<A, ArithF64>) {
            if (n <= 32) {
                using T = typename A::T;
                const std::uint32_t count = nd.hi - nd.lo;
                cull_detail::LeafView<T> view{s.cx.data() + nd.lo, s.cy.data() + nd.lo, s.cz.data() + nd.lo,
                                              s.r.data() + nd.lo};
                cull_detail::LeafSpheres<T> padded;
                if (count < SphereTree::kLeaf) {
                    for (std::uint32_t k = 0; k < SphereTree::kLeaf; ++k) {
                        const bool in = k < count;
                        const std::size_t i = in ? nd.lo + k : nd.lo;
                        padded.cx[k] = s.cx[i];
                        padded.cy[k] = s.cy[i];
                        padded.cz[k] = s.cz[i];
                        padded.r[k] = in ? s.r[i] : T(-1);
                    }
                    view = padded.view();
                }
                std::uint32_t rms[SphereTree::kLeaf], cms[SphereTree::kLeaf];
                cull_detail::leaf_plane_masks(view, planes_a, std::uint32_t(rows), rms);
                cull_detail::leaf_plane_masks(view, planes_a + n, std::uint32_t(cols), cms);
                for (std::uint32_t k = 0; k < count; ++k) {
                    const std::uint64_t rm = rms[k], cm = cms[k];
                    if (rm && cm) out.push_back({nd.lo + k, rm, cm});
                    else if (pairless && (rm | cm)) add_to_runs(*pairless, nd.lo + k);
                }
                continue;
            }
        }
        for (std::uint32_t i = nd.lo; i < nd.hi; ++i) {
            const SphereA<A> sp{s.cx[i], s.cy[i], s.cz[i], s.r[i]};
            std::uint64_t rm = 0;
            for (std::uint64_t m = rows; m; m &= m - 1) {
                const std::uint32_t p = static_cast<std::uint32_t>(__builtin_ctzll(m));
                rm |= std::uint64_t(plane_hits_sphere(a, planes_a[p], sp)) << p;
            }
            if (!rm && !pairless) continue;
            std::uint64_t cm = 0;
            for (std::uint64_t m = cols; m; m &= m - 1) {
                const std::uint32_t p = static_cast<std::uint32_t>(__builtin_ctzll(m));
                cm |= std::uint64_t(plane_hits_sphere(a, planes_a[n + p], sp)) << p;
            }
            if (rm && cm) out.push_back({i, rm, cm});
            else if (pairless && (rm | cm)) add_to_runs(*pairless, i);
        }
    }
}

}  // namespace raplas
