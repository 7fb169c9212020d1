// The two intersection tests of RAPLAS, as pure functions over an Arith policy
// (numfmt.hpp). Used unchanged by the front end and by the SystemC intersector
// models, so timing can never change an answer. No dependencies.
#pragma once

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "raplas/core/numfmt.hpp"
#include "raplas/core/vec.hpp"

namespace raplas {

// Records as stored in the machine's memories. All are float32 values: the
// canonical data every number format starts from (conversion is the format's
// own rounding, see load()).
struct Sphere {
    Vec3f c;
    float r = 0;
};

// Plane n·x + w = 0 with |n| = 1 (normalised by the host).
struct Plane {
    Vec3f n;
    float w = 0;
};

// Triangle Memory record: first vertex, two edges and the (unnormalised) normal
// E = E1 x E2, precomputed by the host (paper §4: "location vectors V0, V1 and
// V2, edge vectors E1 and E2, and normal vector E"). The division-free test
// reads V0, E1, E2, E; the watertight test (watertight.hpp) V0, V1, V2, the
// mesh's own vertices, so that triangles sharing an edge share its data.
struct TriangleRec {
    Vec3f v0, e1, e2, n;
    Vec3f v1{}, v2{};  // the mesh vertices V1, V2 (read by the watertight test)
};

// A ray and the open interval (tmin, tmax) of its parameter; the point at
// parameter t is o + t*d (d is not normalised).
struct Ray {
    Vec3f o, d;
    float tmin = 0;
    float tmax = 0;
};

// Nearest hit: t in the intersector's format, tri = Triangle Memory index
// (-1: none). Ties in t go to the smaller index, so the result does not depend
// on the order in which triangles are tested.
struct Hit {
    double t = 0;
    std::int32_t tri = -1;
    bool operator==(const Hit& o) const { return tri == o.tri && (tri < 0 || t == o.t); }
    bool operator!=(const Hit& o) const { return !(*this == o); }
};

inline void keep_nearest(Hit& best, double t, std::int32_t tri) {
    if (best.tri < 0 || t < best.t || (t == best.t && tri < best.tri)) {
        best.t = t;
        best.tri = tri;
    }
}

// ---- values converted into a format ---------------------------------------

template <class A> struct SphereA { typename A::T cx, cy, cz, r; };
template <class A> struct PlaneA { typename A::T nx, ny, nz, w; };
// The record as the selected RTI test reads it: division-free V0, E1, E2, E;
// watertight V0 and, in e1 and e2, V1 and V2, and in n[0] a flag the host
// derives from the record: 0 for a zero-area triangle (E = 0 exactly), else 1.
template <class A> struct TriA { typename A::T v0[3], e1[3], e2[3], n[3]; };
// The ray; for the watertight test also its per-ray precomputation: the axis
// kz of the largest |D| component, kx and ky (swapped when D[kz] < 0), and
// the shear sx = D[kx]/D[kz], sy = D[ky]/D[kz], sz = 1/D[kz] in the format.
template <class A> struct RayA {
    typename A::T o[3], d[3], tmin, tmax;
    typename A::T sx{}, sy{}, sz{};
    int kx = 0, ky = 1, kz = 2;
};

template <class A> inline SphereA<A> load(const A& a, const Sphere& s) {
    return {a.cvt(s.c.x), a.cvt(s.c.y), a.cvt(s.c.z), a.cvt(s.r)};
}
template <class A> inline PlaneA<A> load(const A& a, const Plane& p) {
    return {a.cvt(p.n.x), a.cvt(p.n.y), a.cvt(p.n.z), a.cvt(p.w)};
}
template <class A> inline TriA<A> load(const A& a, const TriangleRec& t) {
    TriA<A> r;
    const bool wt = rti_of(a) == RtiTest::watertight;
    for (int i = 0; i < 3; ++i) {
        const std::size_t k = static_cast<std::size_t>(i);
        r.v0[i] = a.cvt(t.v0[k]);
        r.e1[i] = a.cvt(wt ? t.v1[k] : t.e1[k]);
        r.e2[i] = a.cvt(wt ? t.v2[k] : t.e2[k]);
        r.n[i] = a.cvt(t.n[k]);
    }
    if (wt) {
        const bool zero_area = t.n.x == 0.0f && t.n.y == 0.0f && t.n.z == 0.0f;
        r.n[0] = a.cvt(zero_area ? 0.0 : 1.0);
        r.n[1] = r.n[2] = a.cvt(0.0);
    }
    return r;
}
template <class A> inline RayA<A> load(const A& a, const Ray& ray) {
    RayA<A> r;
    for (int i = 0; i < 3; ++i) {
        r.o[i] = a.cvt(ray.o[static_cast<std::size_t>(i)]);
        r.d[i] = a.cvt(ray.d[static_cast<std::size_t>(i)]);
    }
    r.tmin = a.cvt(ray.tmin);
    r.tmax = a.cvt(ray.tmax);
    if (rti_of(a) == RtiTest::watertight) {
        const double d[3] = {ray.d.x, ray.d.y, ray.d.z};
        int kz = 0;  // largest |D| component (the first on ties)
        if (std::fabs(d[1]) > std::fabs(d[kz])) kz = 1;
        if (std::fabs(d[2]) > std::fabs(d[kz])) kz = 2;
        int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
        if (d[kz] < 0) std::swap(kx, ky);  // keep the winding
        r.kx = kx;
        r.ky = ky;
        r.kz = kz;
        r.sx = a.div(r.d[kx], r.d[kz]);
        r.sy = a.div(r.d[ky], r.d[kz]);
        r.sz = a.div(a.cvt(1.0), r.d[kz]);
    }
    return r;
}

// ---- Eq. 1: plane-sphere test (3 mul + 3 add, then |d| <= r) --------------

// The PSI's sum ((x + y) + z) + w. An emulated format with psi_normalize off
// uses adders without normalisation (ArithSoft::sum_unnormalized).
template <class A>
inline typename A::T psi_sum(const A& a, typename A::T x, typename A::T y, typename A::T z, typename A::T w) {
    return a.add(a.add(a.add(x, y), z), w);
}
inline double psi_sum(const ArithSoft& a, double x, double y, double z, double w) {
    if (a.f.psi_normalize) return a.add(a.add(a.add(x, y), z), w);
    const double terms[4] = {x, y, z, w};
    return a.sum_unnormalized(terms, 4);
}

// Eq. 1 operation by operation in the format.
template <class A>
inline bool plane_hits_sphere_ops(const A& a, const PlaneA<A>& p, const SphereA<A>& s) {
    auto d = psi_sum(a, a.mul(p.nx, s.cx), a.mul(p.ny, s.cy), a.mul(p.nz, s.cz), p.w);
    return std::fabs(d) <= s.r;  // |.| is a sign-bit clear: exact in every format
}

template <class A>
inline bool plane_hits_sphere(const A& a, const PlaneA<A>& p, const SphereA<A>& s) {
    return plane_hits_sphere_ops(a, p, s);
}

// ---- exact shortcuts for emulated formats ----------------------------------
// An emulated operation costs nanoseconds, and most tests are far from their
// decision. The same expression in double, with a bound on how far the
// emulated format's result can be from it, decides those exactly; only tests
// near the boundary (and every ray-triangle hit, for its exact t) run
// emulated. Decisions and distances equal the operation-by-operation ones bit
// for bit (checked by tests/unit/test_numfmt.cpp on boundary cases).
//
// Bound: every value in these expressions passes through at most six
// roundings (sub, mul, sub, mul, add, add), each with relative error at most
// 2^-M (unit roundoff, or for an adder without normalisation the quantum of
// its larger operand, still within 2^-M of every partial sum's magnitude), so
// the result is within 8 * 2^-M * S of the exact value, where S is the same
// expression over absolute values; subnormal results and flushes add at most
// the smallest normal per operation, carried through the later products. The
// double evaluation itself errs by below 1e-15 * S. Overflow is excluded by
// requiring S <= max_finite / 16.
struct EmulatedBound {
    double k = 0, eta = 0, smax = 0;
    explicit EmulatedBound(const NumFormat& f) {
        // powers of two from their bit patterns (cheap: built for every test)
        auto pow2 = [](int e) {
            const std::uint64_t b = std::uint64_t(e + 1023) << 52;
            double d;
            std::memcpy(&d, &b, sizeof d);
            return d;
        };
        const int bias = (1 << (f.exp_bits - 1)) - 1;
        k = 8 * pow2(-f.man_bits) + 1e-15;
        eta = pow2(1 - bias);                 // smallest normal
        smax = pow2(bias - 4);                // below max_finite / 16
    }
};

// 1: certainly hit, 0: certainly missed, -1: run it emulated.
inline int plane_sphere_shortcut(const EmulatedBound& b, double nx, double ny, double nz, double w, double cx,
                                 double cy, double cz, double r) {
    const double px = nx * cx, py = ny * cy, pz = nz * cz;  // exact in double (<= 26-bit significands)
    const double d = std::fabs(((px + py) + pz) + w);
    const double S = std::fabs(px) + std::fabs(py) + std::fabs(pz) + std::fabs(w);
    const double B = b.k * S + 8 * b.eta;
    if (!(S <= b.smax)) return -1;
    if (d + B <= r) return 1;
    if (d - B > r) return 0;
    return -1;
}

inline bool plane_hits_sphere(const ArithSoft& a, const PlaneA<ArithSoft>& p, const SphereA<ArithSoft>& s) {
    const int q = plane_sphere_shortcut(EmulatedBound(a.f), p.nx, p.ny, p.nz, p.w, s.cx, s.cy, s.cz, s.r);
    return q >= 0 ? q == 1 : plane_hits_sphere_ops(a, p, s);
}

// Spheres of a format in structure-of-arrays layout, for the batched test below.
template <class A> struct SphereSoA {
    std::vector<typename A::T> cx, cy, cz, r;
    std::size_t size() const { return r.size(); }
    void push_back(const SphereA<A>& s) { cx.push_back(s.cx); cy.push_back(s.cy); cz.push_back(s.cz); r.push_back(s.r); }
};

// Eq. 1 for many spheres at once: bit p of masks[i] is set when plane p
// (p < np <= 64) hits sphere first+i. Same operations in the same order as
// plane_hits_sphere, laid out so the compiler can vectorise over spheres.
template <class A, class Mask>
inline void plane_masks(const A& a, const PlaneA<A>* planes, std::uint32_t np, const SphereSoA<A>& s,
                        std::size_t first, std::size_t count, Mask* masks) {
    using T = typename A::T;
    const T* cx = s.cx.data() + first;
    const T* cy = s.cy.data() + first;
    const T* cz = s.cz.data() + first;
    const T* r = s.r.data() + first;
    for (std::size_t i = 0; i < count; ++i) masks[i] = 0;
    for (std::uint32_t p = 0; p < np; ++p) {
        const PlaneA<A> pl = planes[p];
        for (std::size_t i = 0; i < count; ++i) {
            const T d = psi_sum(a, a.mul(pl.nx, cx[i]), a.mul(pl.ny, cy[i]), a.mul(pl.nz, cz[i]), pl.w);
            masks[i] |= Mask(std::fabs(d) <= r[i]) << p;
        }
    }
}

// Emulated formats: the shortcut over every sphere (branch-free, so it
// vectorises like the native formats), then the emulated test for the few
// plane-sphere pairs it leaves open. Formats whose values are all float32
// values (at most 8 exponent and 23 fraction bits) evaluate the shortcut in
// float32, four spheres per vector, with the float32 evaluation's own error
// (below 2^-19 * S over these few operations, rounding of the comparison
// sums included) added to the bound.
template <class Mask>
inline void plane_masks(const ArithSoft& a, const PlaneA<ArithSoft>* planes, std::uint32_t np,
                        const SphereSoA<ArithSoft>& s, std::size_t first, std::size_t count, Mask* masks) {
    constexpr std::size_t kBlock = 256;
    const EmulatedBound b(a.f);
    const bool in_float = a.f.exp_bits <= 8 && a.f.man_bits <= 23;
    const float kf = float(b.k + std::ldexp(1.0, -19));
    const float etaf = float(8 * std::max(b.eta, double(std::ldexp(1.0f, -126))));
    const float smaxf = float(std::min(b.smax, 1e37));
    for (std::size_t start = 0; start < count; start += kBlock) {
        const std::size_t n = std::min(kBlock, count - start);
        const double* cx = s.cx.data() + first + start;
        const double* cy = s.cy.data() + first + start;
        const double* cz = s.cz.data() + first + start;
        const double* r = s.r.data() + first + start;
        Mask* m = masks + start;
        Mask open[kBlock];
        for (std::size_t i = 0; i < n; ++i) m[i] = open[i] = 0;
        if (in_float) {
            float fx[kBlock], fy[kBlock], fz[kBlock], fr[kBlock];  // exact copies
            for (std::size_t i = 0; i < n; ++i) {
                fx[i] = float(cx[i]);
                fy[i] = float(cy[i]);
                fz[i] = float(cz[i]);
                fr[i] = float(r[i]);
            }
            for (std::uint32_t p = 0; p < np; ++p) {
                const float nx = float(planes[p].nx), ny = float(planes[p].ny), nz = float(planes[p].nz),
                            w = float(planes[p].w);
                for (std::size_t i = 0; i < n; ++i) {
                    const float px = nx * fx[i], py = ny * fy[i], pz = nz * fz[i];
                    const float d = std::fabs(((px + py) + pz) + w);
                    const float S = std::fabs(px) + std::fabs(py) + std::fabs(pz) + std::fabs(w);
                    const float B = kf * S + etaf;
                    const bool ok = S <= smaxf;
                    const bool hit = ok & (d + B <= fr[i]);
                    const bool miss = ok & (d - B > fr[i]);
                    m[i] |= Mask(hit) << p;
                    open[i] |= Mask(!hit & !miss) << p;
                }
            }
        } else {
            for (std::uint32_t p = 0; p < np; ++p) {
                const PlaneA<ArithSoft> pl = planes[p];
                for (std::size_t i = 0; i < n; ++i) {  // plane_sphere_shortcut, without branches
                    const double px = pl.nx * cx[i], py = pl.ny * cy[i], pz = pl.nz * cz[i];
                    const double d = std::fabs(((px + py) + pz) + pl.w);
                    const double S = std::fabs(px) + std::fabs(py) + std::fabs(pz) + std::fabs(pl.w);
                    const double B = b.k * S + 8 * b.eta;
                    const bool ok = S <= b.smax;
                    const bool hit = ok & (d + B <= r[i]);
                    const bool miss = ok & (d - B > r[i]);
                    m[i] |= Mask(hit) << p;
                    open[i] |= Mask(!hit & !miss) << p;
                }
            }
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (!open[i]) continue;
            const SphereA<ArithSoft> sp{cx[i], cy[i], cz[i], r[i]};
            for (Mask o = open[i]; o; o &= o - 1) {
                const unsigned p = unsigned(__builtin_ctzll(std::uint64_t(o)));
                m[i] |= Mask(plane_hits_sphere_ops(a, planes[p], sp)) << p;
            }
        }
    }
}

// A sphere hit by at least one valid row plane and one valid column plane.
// Packed to 20 bytes (4-byte alignment): a frame's trace holds one per sphere
// a group hits, hundreds of millions at 512 x 512 (docs/MEMORY.md). Read the
// masks by value: a reference to rows or cols would be misaligned.
#pragma pack(push, 4)
struct SphereHitRec {
    std::uint32_t sphere;
    std::uint64_t rows, cols;  // plane-hit masks (only valid planes can hit)
};
#pragma pack(pop)
static_assert(sizeof(SphereHitRec) == 20);

// A run of consecutive Sphere Memory indices [first, first + count).
struct SphereRun {
    std::uint32_t first = 0, count = 0;
    std::uint32_t end() const { return first + count; }
    bool operator==(const SphereRun& o) const { return first == o.first && count == o.count; }
};

// In a list of sphere hits in sphere order, the first at or after sphere s.
inline std::vector<SphereHitRec>::const_iterator first_hit_from(const std::vector<SphereHitRec>& hits, std::uint32_t s) {
    return std::lower_bound(hits.begin(), hits.end(), s, [](const SphereHitRec& h, std::uint32_t x) { return h.sphere < x; });
}

// In a list of runs in sphere order, the first that ends after sphere s
// (holds s, or comes after it).
inline std::vector<SphereRun>::const_iterator first_run_from(const std::vector<SphereRun>& runs, std::uint32_t s) {
    return std::lower_bound(runs.begin(), runs.end(), s, [](const SphereRun& r, std::uint32_t x) { return r.end() <= x; });
}

// Appends spheres [first, first + count) (ascending: past the last run's) to
// a list of runs.
inline void add_to_runs(std::vector<SphereRun>& runs, std::uint32_t first, std::uint32_t count = 1) {
    if (!runs.empty() && runs.back().end() == first) runs.back().count += count;
    else runs.push_back({first, count});
}
// add_to_runs for each sphere base + k whose bit k of `bits` is set, a
// stretch of set bits at a time.
inline void add_bits_to_runs(std::vector<SphereRun>& runs, std::uint32_t base, std::uint32_t bits) {
    while (bits) {
        const auto k = static_cast<std::uint32_t>(__builtin_ctz(bits));
        const auto len = static_cast<std::uint32_t>(__builtin_ctzll(~(std::uint64_t(bits) >> k)));
        add_to_runs(runs, base + k, len);
        bits = static_cast<std::uint32_t>(bits & ~(((std::uint64_t(1) << len) - 1) << k));
    }
}

// Steps 5-6 decision for one ray group: every sphere whose row mask and
// column mask are both non-empty, in sphere order. planes[0, n) are the row
// planes, planes[n, 2n) the column planes. With `pairless`, also the spheres
// cut by valid row planes only or valid column planes only (they give no
// (ray, triangle) pair), as runs in sphere order.
template <class A>
inline void group_sphere_hits(const A& a, const PlaneA<A>* planes, std::uint32_t n, std::uint64_t row_valid,
                              std::uint64_t col_valid, const SphereSoA<A>& s, std::vector<SphereHitRec>& out,
                              std::vector<SphereRun>* pairless = nullptr) {
    constexpr std::size_t kChunk = 512;
    out.clear();
    if (pairless) pairless->clear();
    auto run = [&](auto* rows, auto* cols) {  // 32-bit masks vectorise twice as wide when n <= 32
        for (std::size_t first = 0; first < s.size(); first += kChunk) {
            const std::size_t count = std::min(kChunk, s.size() - first);
            plane_masks(a, planes, n, s, first, count, rows);
            if (pairless) plane_masks(a, planes + n, n, s, first, count, cols);
            for (std::size_t i = 0; i < count; ++i) {
                const std::uint64_t rm = std::uint64_t(rows[i]) & row_valid;
                std::uint64_t cm = 0;
                if (pairless) {
                    cm = std::uint64_t(cols[i]) & col_valid;
                    if (!rm || !cm) {
                        if (rm | cm) add_to_runs(*pairless, std::uint32_t(first + i));
                        continue;
                    }
                } else {
                    if (!rm) continue;
                    const SphereA<A> sp{s.cx[first + i], s.cy[first + i], s.cz[first + i], s.r[first + i]};
                    for (std::uint32_t h = 0; h < n; ++h) cm |= std::uint64_t(plane_hits_sphere(a, planes[n + h], sp)) << h;
                    cm &= col_valid;
                }
                if (cm) out.push_back({std::uint32_t(first + i), rm, cm});
            }
        }
    };
    if (n <= 32) {
        std::uint32_t rows[kChunk], cols[kChunk];
        run(rows, cols);
    } else {
        std::uint64_t rows[kChunk], cols[kChunk];
        run(rows, cols);
    }
}

// ---- Eq. 2: division-free ray-triangle test --------------------------------
// With T = O - V0, det = D·E, t' = -E·T, u' = (D x T)·E2, v' = -(D x T)·E1
// (all scaled by det, so no division decides the hit). Back faces (det < 0)
// flip every sign. The edge rule is inclusive (u' >= 0, v' >= 0,
// u' + v' <= det): a ray through a shared edge hits both triangles rather than
// neither; docs/MODEL.md. Returns true and t = t'/det when the hit lies in
// (tmin, tmax). Operation count: 18 mul, 15 add/sub, 1 div (only on a hit).
template <class A>
inline bool ray_hits_triangle_ops(const A& a, const RayA<A>& r, const TriA<A>& tr, double& t_out) {
    using T = typename A::T;
    const T tx = a.sub(r.o[0], tr.v0[0]), ty = a.sub(r.o[1], tr.v0[1]), tz = a.sub(r.o[2], tr.v0[2]);
    const T cx = a.sub(a.mul(r.d[1], tz), a.mul(r.d[2], ty));
    const T cy = a.sub(a.mul(r.d[2], tx), a.mul(r.d[0], tz));
    const T cz = a.sub(a.mul(r.d[0], ty), a.mul(r.d[1], tx));
    T det = a.add(a.add(a.mul(r.d[0], tr.n[0]), a.mul(r.d[1], tr.n[1])), a.mul(r.d[2], tr.n[2]));
    if (det == T(0) || !(std::fabs(det) == std::fabs(det))) return false;  // parallel, or NaN
    T u = a.add(a.add(a.mul(cx, tr.e2[0]), a.mul(cy, tr.e2[1])), a.mul(cz, tr.e2[2]));
    T v = -a.add(a.add(a.mul(cx, tr.e1[0]), a.mul(cy, tr.e1[1])), a.mul(cz, tr.e1[2]));
    const bool back = det < T(0);
    if (back) {
        det = -det;
        u = -u;
        v = -v;
    }
    if (!(u >= T(0)) || !(v >= T(0)) || !(a.add(u, v) <= det)) return false;
    T tp = -a.add(a.add(a.mul(tr.n[0], tx), a.mul(tr.n[1], ty)), a.mul(tr.n[2], tz));
    if (back) tp = -tp;
    const T t = a.div(tp, det);
    if (!(t > r.tmin) || !(t < r.tmax)) return false;
    t_out = static_cast<double>(t);
    return true;
}

template <class A>
inline bool ray_hits_triangle_watertight(const A& a, const RayA<A>& r, const TriA<A>& tr, double& t_out);

// The RTI's test of the policy's format: Eq. 2, or the watertight test.
template <class A>
inline bool ray_hits_triangle(const A& a, const RayA<A>& r, const TriA<A>& tr, double& t_out) {
    if (rti_of(a) == RtiTest::watertight) return ray_hits_triangle_watertight(a, r, tr, t_out);
    return ray_hits_triangle_ops(a, r, tr, t_out);
}

// Eq. 2 for `count` rays of one group against one triangle, in a native
// format (float or double): the rays share the origin o and the interval
// (tmin, tmax) and have the directions (dx[i], dy[i], dz[i]). The operations
// are those of ray_hits_triangle_ops in the same order (the terms of the
// origin, T = O - V0 and E . T, computed once for all rays), so hit[i] and,
// where hit[i], t[i] are bit-identical to it (test_intersect.cpp checks it on
// random and degenerate cases). Branch-free, so that the compiler vectorises
// the loop over the rays. Returns whether any ray hits.
template <class T>
inline bool rays_hit_triangle_native(const T o[3], T tmin, T tmax, const T* dx, const T* dy, const T* dz,
                                     std::size_t count, const TriA<ArithNative<T>>& tr, std::uint8_t* hit, T* t) {
    const T tx = o[0] - tr.v0[0], ty = o[1] - tr.v0[1], tz = o[2] - tr.v0[2];
    const T tp0 = -((tr.n[0] * tx + tr.n[1] * ty) + tr.n[2] * tz);
    const T n0 = tr.n[0], n1 = tr.n[1], n2 = tr.n[2];
    const T a0 = tr.e1[0], a1 = tr.e1[1], a2 = tr.e1[2];
    const T b0 = tr.e2[0], b1 = tr.e2[1], b2 = tr.e2[2];
    std::uint8_t any = 0;
    for (std::size_t i = 0; i < count; ++i) {
        const T d0 = dx[i], d1 = dy[i], d2 = dz[i];
        const T cx = d1 * tz - d2 * ty;
        const T cy = d2 * tx - d0 * tz;
        const T cz = d0 * ty - d1 * tx;
        const T det0 = (d0 * n0 + d1 * n1) + d2 * n2;
        const T u0 = (cx * b0 + cy * b1) + cz * b2;
        const T v0 = -((cx * a0 + cy * a1) + cz * a2);
        const bool back = det0 < T(0);
        const T det = back ? -det0 : det0;
        const T u = back ? -u0 : u0;
        const T v = back ? -v0 : v0;
        const T tp = back ? -tp0 : tp0;
        const T ti = tp / det;
        // det != 0 and not NaN, u, v >= 0, u + v <= det, tmin < t < tmax
        const std::uint8_t h = (det0 != T(0)) & (det == det) & (u >= T(0)) & (v >= T(0)) & (u + v <= det) & (ti > tmin) & (ti < tmax);
        hit[i] = h;
        any |= h;
        t[i] = ti;
    }
    return any != 0;
}

// Component bounds of a set of ray directions: lo[i] <= d[i] <= hi[i].
template <class T> struct DirectionBox { T lo[3], hi[3]; };

// Whether rays_hit_triangle_native, for every ray with origin o, interval (tmin, tmax), tmin >= 0,
// and a direction inside `box`, certainly finds no hit: a proof, so that a caller may skip the
// test and keep bit-identical answers. Each of Eq. 2's computed quantities (det, u', v',
// u' + v' - det) is a linear function of D rounded a few times; its exact range over the box,
// widened by a bound on that rounding (a few units in the last place of the sum of the terms'
// magnitudes, plus a tiny absolute term for underflow), decides when it excludes a hit for
// every ray: t' = 0, a t' whose sign differs from det's (t <= 0), t >= tmax, or the hit on the
// far side of an edge. t' = -E.(O - V0) is the kernel's own value (it is shared by the rays).
// Anything undecided, NaN or infinite answers false. Costs about as much as testing 4 rays.
template <class T>
inline bool rays_certainly_miss_triangle_native(const T o[3], T tmin, T tmax, const DirectionBox<T>& box,
                                                const TriA<ArithNative<T>>& tr) {
    if (!(tmin >= T(0))) return false;
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(box.lo[i]) || !std::isfinite(box.hi[i])) return false;
    const T tx = o[0] - tr.v0[0], ty = o[1] - tr.v0[1], tz = o[2] - tr.v0[2];
    const T tp0 = -((tr.n[0] * tx + tr.n[1] * ty) + tr.n[2] * tz);
    if (!(tp0 > T(0)) && !(tp0 < T(0))) return true;  // t' = 0 (t = 0 <= tmin) or NaN: no ray hits
    // Unit roundoff of T; the bounds below are computed in double (exact products for float).
    constexpr double u = std::is_same_v<T, float> ? 0x1p-24 : 0x1p-53;
    constexpr double tiny = std::is_same_v<T, float> ? 0x1p-120 : 0x1p-1000;
    const double dmax[3] = {std::max(std::fabs(double(box.lo[0])), std::fabs(double(box.hi[0]))),
                            std::max(std::fabs(double(box.lo[1])), std::fabs(double(box.hi[1]))),
                            std::max(std::fabs(double(box.lo[2])), std::fabs(double(box.hi[2])))};
    // exact range of D.w over the box (up to double rounding, covered by the slack below)
    auto range = [&](const double w[3], double& lo, double& hi) __attribute__((always_inline)) {
        lo = hi = 0;
        for (int i = 0; i < 3; ++i) {
            const double a = double(box.lo[i]) * w[i], b = double(box.hi[i]) * w[i];
            lo += std::min(a, b);
            hi += std::max(a, b);
        }
    };
    const double nn[3] = {double(tr.n[0]), double(tr.n[1]), double(tr.n[2])};
    double dlo, dhi;
    range(nn, dlo, dhi);
    const double sd = dmax[0] * std::fabs(nn[0]) + dmax[1] * std::fabs(nn[1]) + dmax[2] * std::fabs(nn[2]);
    // the kernel's intermediates stay far from overflow (its inf or NaN would escape the bounds)
    constexpr double big = std::is_same_v<T, float> ? 1e36 : 1e300;
    if (!(sd < big)) return false;
    const double ed = 8 * u * sd + tiny;
    dlo -= ed;
    dhi += ed;  // every computed det in [dlo, dhi]
    if (tp0 > T(0) && dhi <= 0) return true;  // det <= 0 for every ray: t < 0 or no hit
    if (tp0 < T(0) && dlo >= 0) return true;
    const bool front = dlo > 0;
    if (!front && !(dhi < 0)) return false;  // the sign of det is undecided (or NaN)
    // t >= tmax for every ray: |t'| / max|det| >= tmax, and rounding is monotone
    const double q = std::fabs(double(tp0)) / (front ? dhi : -dlo);
    if (q * (1 - 0x1p-50) >= double(tmax)) return true;
    // u' = D.(T x E2), v' = -D.(T x E1), computed through C = D x T
    const double t[3] = {double(tx), double(ty), double(tz)};
    const double e1[3] = {double(tr.e1[0]), double(tr.e1[1]), double(tr.e1[2])};
    const double e2[3] = {double(tr.e2[0]), double(tr.e2[1]), double(tr.e2[2])};
    const double U[3] = {t[1] * e2[2] - t[2] * e2[1], t[2] * e2[0] - t[0] * e2[2], t[0] * e2[1] - t[1] * e2[0]};
    const double V[3] = {t[1] * e1[2] - t[2] * e1[1], t[2] * e1[0] - t[0] * e1[2], t[0] * e1[1] - t[1] * e1[0]};
    // |C_i| <= ca_i, and the computed u' is within about 5 u of sum ca_i |E2_i|
    const double ca[3] = {dmax[1] * std::fabs(t[2]) + dmax[2] * std::fabs(t[1]),
                          dmax[2] * std::fabs(t[0]) + dmax[0] * std::fabs(t[2]),
                          dmax[0] * std::fabs(t[1]) + dmax[1] * std::fabs(t[0])};
    const double ua = ca[0] * std::fabs(e2[0]) + ca[1] * std::fabs(e2[1]) + ca[2] * std::fabs(e2[2]);
    const double va = ca[0] * std::fabs(e1[0]) + ca[1] * std::fabs(e1[1]) + ca[2] * std::fabs(e1[2]);
    const double eu = 16 * u * ua + tiny * (1 + std::fabs(e2[0]) + std::fabs(e2[1]) + std::fabs(e2[2]));
    const double ev = 16 * u * va + tiny * (1 + std::fabs(e1[0]) + std::fabs(e1[1]) + std::fabs(e1[2]));
    if (!(ua < big && va < big && ca[0] < big && ca[1] < big && ca[2] < big)) return false;
    double ulo, uhi, vlo, vhi;
    range(U, ulo, uhi);  // u' = D.U
    range(V, vlo, vhi);  // v' = -D.V
    if (front ? uhi + eu < 0 : ulo - eu > 0) return true;   // u < 0 for every ray
    if (front ? vlo - ev > 0 : vhi + ev < 0) return true;   // v < 0 for every ray
    // u' + v' - det = D.(U - V - E), the sum rounded once more
    const double W[3] = {U[0] - V[0] - nn[0], U[1] - V[1] - nn[1], U[2] - V[2] - nn[2]};
    double wlo, whi;
    range(W, wlo, whi);
    const double ew = eu + ev + ed + 4 * u * (ua + va + eu + ev);
    if (front ? wlo - ew > 0 : whi + ew < 0) return true;  // u + v > det for every ray
    return false;
}

bool watertight_certain_miss(const EmulatedBound& b, const RayA<ArithSoft>& r, const TriA<ArithSoft>& tr);

// Eq. 2 in an emulated format decided from double (see EmulatedBound):
// 0 when the format certainly rejects the pair on u', v' or det, 1 when it
// certainly finds it inside (u' >= 0, v' >= 0, u' + v' <= det), -1 otherwise.
inline int ray_triangle_shortcut(const EmulatedBound& b, const RayA<ArithSoft>& r, const TriA<ArithSoft>& tr) {
    double t[3], ta[3], dmax = 0, e1max = 0, e2max = 0;
    for (int i = 0; i < 3; ++i) {
        t[i] = r.o[i] - tr.v0[i];
        ta[i] = std::fabs(r.o[i]) + std::fabs(tr.v0[i]);
        dmax = std::max(dmax, std::fabs(r.d[i]));
        e1max = std::max(e1max, std::fabs(tr.e1[i]));
        e2max = std::max(e2max, std::fabs(tr.e2[i]));
    }
    const double* d = r.d;
    const double c[3] = {d[1] * t[2] - d[2] * t[1], d[2] * t[0] - d[0] * t[2], d[0] * t[1] - d[1] * t[0]};
    const double ca[3] = {std::fabs(d[1]) * ta[2] + std::fabs(d[2]) * ta[1], std::fabs(d[2]) * ta[0] + std::fabs(d[0]) * ta[2],
                          std::fabs(d[0]) * ta[1] + std::fabs(d[1]) * ta[0]};
    const double det = d[0] * tr.n[0] + d[1] * tr.n[1] + d[2] * tr.n[2];
    const double deta = std::fabs(d[0] * tr.n[0]) + std::fabs(d[1] * tr.n[1]) + std::fabs(d[2] * tr.n[2]);
    const double u = c[0] * tr.e2[0] + c[1] * tr.e2[1] + c[2] * tr.e2[2];
    const double ua = ca[0] * std::fabs(tr.e2[0]) + ca[1] * std::fabs(tr.e2[1]) + ca[2] * std::fabs(tr.e2[2]);
    const double v = -(c[0] * tr.e1[0] + c[1] * tr.e1[1] + c[2] * tr.e1[2]);
    const double va = ca[0] * std::fabs(tr.e1[0]) + ca[1] * std::fabs(tr.e1[1]) + ca[2] * std::fabs(tr.e1[2]);
    const double big = std::max(std::max(std::max(ua, va), std::max(deta, ca[0] + ca[1] + ca[2])), ta[0] + ta[1] + ta[2]);
    if (!(big <= b.smax)) return -1;  // may overflow (or NaN)
    // absolute errors from underflow, carried through the later products
    const double tiny = 64 * b.eta * (1 + dmax) * (1 + std::max(e1max, e2max));
    const double bd = b.k * deta + tiny, bu = b.k * ua + tiny, bv = b.k * va + tiny;
    if (!(std::fabs(det) > bd)) return -1;  // sign of det, or det = 0, undecided
    const double s = det > 0 ? 1.0 : -1.0;
    const double uu = s * u, vv = s * v, dd = std::fabs(det);
    if (uu + bu < 0 || vv + bv < 0) return 0;
    // u' + v' <= det in the format: u' + v' is rounded once more
    const double bsum = bu + bv + bd + b.k * (ua + va);
    if ((uu + vv) - dd > bsum) return 0;
    if (uu - bu >= 0 && vv - bv >= 0 && (uu + vv) - dd + bsum <= 0) return 1;
    return -1;
}

inline bool ray_hits_triangle(const ArithSoft& a, const RayA<ArithSoft>& r, const TriA<ArithSoft>& tr, double& t_out) {
    if (a.f.rti == RtiTest::watertight) {
        if (tr.n[0] != 0 && watertight_certain_miss(EmulatedBound(a.f), r, tr)) return false;
        return ray_hits_triangle_watertight(a, r, tr, t_out);
    }
    const int q = ray_triangle_shortcut(EmulatedBound(a.f), r, tr);
    if (q == 0) return false;
    if (q < 0) return ray_hits_triangle_ops(a, r, tr, t_out);
    // Certainly inside: only det and t' decide, computed exactly as in ray_hits_triangle_ops.
    double det = a.add(a.add(a.mul(r.d[0], tr.n[0]), a.mul(r.d[1], tr.n[1])), a.mul(r.d[2], tr.n[2]));
    const double tx = a.sub(r.o[0], tr.v0[0]), ty = a.sub(r.o[1], tr.v0[1]), tz = a.sub(r.o[2], tr.v0[2]);
    double tp = -a.add(a.add(a.mul(tr.n[0], tx), a.mul(tr.n[1], ty)), a.mul(tr.n[2], tz));
    if (det < 0) {
        det = -det;
        tp = -tp;
    }
    const double t = a.div(tp, det);
    if (!(t > r.tmin) || !(t < r.tmax)) return false;
    t_out = t;
    return true;
}

}  // namespace raplas

#include "raplas/core/watertight.hpp"  // the watertight kernel (needs the types above)
