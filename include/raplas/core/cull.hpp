// Sphere culling for the plane-sphere step: a tree of bounding boxes over
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
// range [lo, hi) and holds an axis-aligned box (in float, read in double)
// enclosing all its spheres. Leaves hold at most kLeaf spheres. Nodes are in
// pre-order: a node's left child follows it, `right` is the index of its
// right child (0 for a leaf). A box is at least as tight as the sphere around
// it, and its test is cheaper: the error bound depends only on the plane
// (docs/PERFORMANCE.md, "Boxes in the culling tree": on the shipped scenes it
// proves as many misses as the bounding spheres did).
class SphereTree {
public:
    static constexpr std::uint32_t kLeaf = 8;
    // 32 bytes, two to a cache line: a group's walk reads thousands of them.
    // The centre is rounded to float and the half extents are measured from
    // that float centre and rounded up: every sphere (c, r) of the node has
    // |c_i - centre_i| + r <= e_i on each axis.
    struct alignas(32) Node {
        float cx, cy, cz;
        float ex, ey, ez;
        std::uint32_t lo;
        std::uint32_t right;
    };

    SphereTree() = default;
    explicit SphereTree(const std::vector<Sphere>& spheres) : size_(static_cast<std::uint32_t>(spheres.size())) {
        if (spheres.empty()) return;
        double m = 0;
        for (const Sphere& s : spheres) {
            const double x = s.c.x, y = s.c.y, z = s.c.z;
            m = std::max(m, std::sqrt(x * x + y * y + z * z) + double(s.r));
        }
        bound_ = up_to_float(m * (1 + 0x1p-40));
        nodes_.reserve(2 * (spheres.size() / kLeaf + 1));
        build(spheres, 0, size_);
    }
    const std::vector<Node>& nodes() const { return nodes_; }
    bool empty() const { return nodes_.empty(); }
    // End of a leaf's range: leaves start at multiples of kLeaf and are full
    // but for the last one. A node's range ends where its rightmost leaf's does.
    std::uint32_t leaf_end(const Node& leaf) const { return std::min(leaf.lo + kLeaf, size_); }
    std::uint32_t hi(const Node& nd) const { return nd.right ? hi(nodes_[nd.right]) : leaf_end(nd); }
    // At least |c| + r for every sphere (a bound on every magnitude the
    // exact test meets, for its error bound).
    double bound() const { return bound_; }

private:
    std::vector<Node> nodes_;
    std::uint32_t size_ = 0;
    double bound_ = 0;

    // The least float at or above x (x >= 0, finite).
    static float up_to_float(double x) {
        const float f = float(x);
        return double(f) >= x ? f : std::nextafter(f, HUGE_VALF);
    }

    std::uint32_t build(const std::vector<Sphere>& s, std::uint32_t lo, std::uint32_t hi) {
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
        double e[3] = {0, 0, 0};
        for (std::uint32_t i = lo; i < hi; ++i) {
            const double r = s[i].r;
            e[0] = std::max(e[0], std::fabs(s[i].c.x - cx) + r);
            e[1] = std::max(e[1], std::fabs(s[i].c.y - cy) + r);
            e[2] = std::max(e[2], std::fabs(s[i].c.z - cz) + r);
        }
        // (each |c - centre| + r above is one subtraction and one addition in
        // double: the margin covers their rounding)
        n.ex = up_to_float(e[0] * (1 + 0x1p-40));
        n.ey = up_to_float(e[1] * (1 + 0x1p-40));
        n.ez = up_to_float(e[2] * (1 + 0x1p-40));
        n.lo = lo;
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
// many are tested at once): their float32 records in double, the weights of
// the box's half extents, and the error bound, which depends only on the
// plane (and the tree's bound). Eight spare entries past the 128th let a
// vector of eight read past the last plane.
struct PlanesD {
    double nx[136], ny[136], nz[136], w[136];
    double ax[136], ay[136], az[136];  // |n_x| + max(0, 1 - |n|_1), |n_y|, |n_z|
    double slack[136];
};

// Plane k's entries of `p` from its record, for a tree of bound `m` and an
// arithmetic of bounds `b`.
//
// For a sphere (c, r) in a node of centre C and half extents e
// (|c_i - C_i| <= e_i - r), with S = |n_x| + |n_y| + |n_z|,
// |n.c + w| >= |n.C + w| - sum |n_i| (e_i - r) = |n.C + w| - sum |n_i| e_i + S r,
// so the exact test's |n.c + w| > r holds when
// |n.C + w| > sum |n_i| e_i + max(0, 1 - S) e_x (r <= e_x).
// The format's result d' differs from n.c + w by at most
// 8 u (|n| |c| + |w|) + 8 abs (inputs rounded into the format, three
// products, three sums: a (1+u)^6 bound, doubled for safety, plus flushing),
// and its radius r' from r by at most u r + abs; |n| <= S, |c|, r <= m. The
// node test's own double arithmetic (the dot product, with |C_i| <= m, the
// weighted extents, with e_i <= 2 m, and their sum: within 12 * 2^-53 of
// S m + |w|) takes 8 u more.
inline void set_plane(PlanesD& p, std::uint32_t k, const Plane& pl, double m, const ArithBounds& b) {
    const double nx = pl.n.x, ny = pl.n.y, nz = pl.n.z;
    p.nx[k] = nx;
    p.ny[k] = ny;
    p.nz[k] = nz;
    p.w[k] = pl.w;
    const double s1 = (std::fabs(nx) + std::fabs(ny) + std::fabs(nz)) * (1 + 0x1p-50);
    p.ax[k] = std::fabs(nx) + std::max(0.0, 1 - s1 * (1 - 0x1p-49));
    p.ay[k] = std::fabs(ny);
    p.az[k] = std::fabs(nz);
    const double u = std::max(b.rel, 0x1p-52);
    p.slack[k] = (16 * u * (s1 * m + std::fabs(p.w[k])) + u * m + 16 * b.abs) * (1 + 0x1p-50);
}

// True when no sphere of node `nd` can be hit by plane `k` in the arithmetic
// whose bound p.slack[k] holds: the double distance from the node centre
// exceeds the box's extent along the plane's normal by more than any rounding
// of the exact test could make up.
inline bool plane_misses_node(const PlanesD& p, std::uint32_t k, const SphereTree::Node& nd) {
    const double d = p.nx[k] * nd.cx + p.ny[k] * nd.cy + p.nz[k] * nd.cz + p.w[k];
    const double ext = p.ax[k] * nd.ex + p.ay[k] * nd.ey + p.az[k] * nd.ez;
    return std::fabs(d) > ext + p.slack[k];
}

// The same test for planes [first, first + count) at once (count <= 64): bit
// i of the result is set when plane first + i may hit the node (the test
// above does not prove a miss). src/core/cull.cpp: eight planes per AVX-512
// vector or four per AVX2 vector where the machine has them, else plane by
// plane.
std::uint64_t planes_may_hit_node(const PlanesD& p, std::uint32_t first, std::uint32_t count,
                                  const SphereTree::Node& nd);

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
    double m = tree.bound();
    for (std::uint32_t p = 0; p < np; ++p) {
        const double nn = std::fabs(planes[p].n.x) + std::fabs(planes[p].n.y) + std::fabs(planes[p].n.z);
        m = std::max(m, std::max(nn * tree.bound(), double(std::fabs(planes[p].w))));
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
    for (std::uint32_t p = 0; p < 2 * n; ++p) cull_detail::set_plane(pd, p, planes[p], tree.bound(), b);
    const auto& nodes = tree.nodes();
    // Narrow a plane mask to the planes that may hit node nd: the planes
    // from its lowest to its highest bit in one vectorised test.
    auto narrow = [&](std::uint64_t mask, std::uint32_t base, const SphereTree::Node& nd) {
        if (!mask) return mask;
        const auto first = static_cast<std::uint32_t>(__builtin_ctzll(mask));
        const auto count = static_cast<std::uint32_t>(64 - __builtin_clzll(mask)) - first;
        return mask & (cull_detail::planes_may_hit_node(pd, base + first, count, nd) << first);
    };
    // Depth-first, left before right: leaves come in sphere order.
    struct Item {
        std::uint32_t node;
        std::uint64_t rows, cols;
    };
    // Down the left children, the right ones stacked: the left child is taken
    // without a trip through the stack (a load right after the stores of its
    // push waits for them). The stack's bottom item ends the walk.
    constexpr std::uint32_t kEnd = ~std::uint32_t(0);
    Item stack[65];
    stack[0] = {kEnd, 0, 0};
    int top = 1;
    for (Item it{0, row_valid, col_valid}; it.node != kEnd; it = stack[--top]) {
        const SphereTree::Node* ndp;
        std::uint64_t rows, cols;
        bool may_hit;  // (some plane of each family may hit, or under `pairless` some plane at all)
        for (;;) {
            ndp = &nodes[it.node];
            rows = narrow(it.rows, 0, *ndp);
            cols = rows || pairless ? narrow(it.cols, n, *ndp) : 0;
            may_hit = cols || (pairless && rows);
            if (!may_hit || !ndp->right) break;
            stack[top++] = {ndp->right, rows, cols};
            it = {it.node + 1, rows, cols};
        }
        if (!may_hit) continue;
        const SphereTree::Node& nd = *ndp;
        // Leaf: the exact Eq. 1 test for the planes that may hit; in the
        // native formats all the leaf's spheres at once, plane by plane.
        if constexpr (std::is_same_v<A, ArithF32> || std::is_same_v<A, ArithF64>) {
            if (n <= 32) {
                using T = typename A::T;
                const std::uint32_t count = tree.leaf_end(nd) - nd.lo;
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
                // (a padded lane's masks are 0: no plane hits radius -1)
                std::uint32_t both = 0, any = 0;
                for (std::uint32_t k = 0; k < SphereTree::kLeaf; ++k) {
                    both |= std::uint32_t(rms[k] != 0 && cms[k] != 0) << k;
                    any |= std::uint32_t((rms[k] | cms[k]) != 0) << k;
                }
                for (std::uint32_t m = both; m; m &= m - 1) {
                    const auto k = static_cast<std::uint32_t>(__builtin_ctz(m));
                    out.push_back({nd.lo + k, rms[k], cms[k]});
                }
                if (pairless) add_bits_to_runs(*pairless, nd.lo, any & ~both);
                continue;
            }
        }
        for (std::uint32_t i = nd.lo, hi = tree.leaf_end(nd); i < hi; ++i) {
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
