// Watertight ray-triangle test (Woop, Benthin, Wald, "Watertight
// Ray/Triangle Intersection", JCGT 2(1), 2013) over the same Arith policies as
// the division-free test of Eq. 2, as an alternative for the Ray-Triangle
// Intersector (NumFormat::rti, format suffix -wt, numerics.rti_test).
// Included by intersect.hpp, which declares the types.
//
// Per ray, once (load() in intersect.hpp, Ray Memory): the axis kz of the
// largest |D| component, the other two kx, ky (swapped when D[kz] < 0 to keep
// the winding), and the shear sx = Dx/Dz, sy = Dy/Dz, sz = 1/Dz. Per test (after
// the host's zero-area flag, a one-bit record field): the
// three vertices relative to the origin, sheared so that the ray runs along +z
// through the 2D origin, and three 2D edge functions U, V, W. An edge shared
// by two triangles is computed from the same two sheared vertices in both, in
// the opposite order; since both rounding modes are symmetric
// (round(-x) = -round(x)) and rounding is monotonic, the two edge functions
// are exact negatives of each other and never have the wrong sign, so no ray
// can pass between the triangles, in any format, as long as nothing
// overflows and the format resolves the triangle at the ray's distance. The
// edge rule is inclusive, as in the division-free test: a ray through an edge
// or a vertex hits every triangle there (a double hit, never a gap).
//
// Operation count per test: 18 mul, 22 add/sub, 1 div (only on a hit),
// against 18 mul, 15 add/sub, 1 div for the division-free test; per ray 3 div
// (or one reciprocal and 2 mul) and the axis choice, once per ray group. The
// triangle record is V0, V1, V2: 9 values instead of 12 (V0, E1, E2, E).
#pragma once

#include <cmath>

#include "raplas/core/intersect.hpp"

namespace raplas {

// True and t (in units of the ray's D, as the division-free test) when the
// ray hits the triangle with t in (tmin, tmax). tr holds V0 and, in e1 and e2,
// V1 and V2 (load() with a watertight policy).
template <class A>
inline bool ray_hits_triangle_watertight(const A& a, const RayA<A>& r, const TriA<A>& tr, double& t_out) {
    using T = typename A::T;
    // A zero-area triangle is flagged by the host (its E is exactly 0): the
    // sheared vertices of collinear points need not stay collinear after
    // rounding, and such a triangle would otherwise be hit along its segment.
    if (tr.n[0] == T(0)) return false;
    const T* v[3] = {tr.v0, tr.e1, tr.e2};
    T x[3], y[3], z[3];  // sheared vertices
    for (int k = 0; k < 3; ++k) {
        const T px = a.sub(v[k][r.kx], r.o[r.kx]);
        const T py = a.sub(v[k][r.ky], r.o[r.ky]);
        z[k] = a.sub(v[k][r.kz], r.o[r.kz]);
        x[k] = a.sub(px, a.mul(r.sx, z[k]));
        y[k] = a.sub(py, a.mul(r.sy, z[k]));
    }
    // edge functions: U for edge V1-V2, V for V2-V0, W for V0-V1
    const T u = a.sub(a.mul(x[2], y[1]), a.mul(y[2], x[1]));
    const T vv = a.sub(a.mul(x[0], y[2]), a.mul(y[0], x[2]));
    const T w = a.sub(a.mul(x[1], y[0]), a.mul(y[1], x[0]));
    if (!(u == u) || !(vv == vv) || !(w == w)) return false;  // NaN (overflow)
    if ((u < T(0) || vv < T(0) || w < T(0)) && (u > T(0) || vv > T(0) || w > T(0))) return false;
    const T det = a.add(a.add(u, vv), w);
    if (det == T(0) || !(std::fabs(det) == std::fabs(det))) return false;
    const T tz = a.add(a.add(a.mul(u, a.mul(r.sz, z[0])), a.mul(vv, a.mul(r.sz, z[1]))), a.mul(w, a.mul(r.sz, z[2])));
    const T t = a.div(tz, det);
    if (!(t > r.tmin) || !(t < r.tmax)) return false;
    t_out = static_cast<double>(t);
    return true;
}

// Emulated formats: true when the watertight test certainly rejects the pair
// because one edge function is certainly negative and another certainly
// positive (see EmulatedBound in intersect.hpp; each edge function passes
// through five roundings after the per-ray shear, which is a value of the
// format). Pairs it leaves open run emulated.
inline bool watertight_certain_miss(const EmulatedBound& b, const RayA<ArithSoft>& r, const TriA<ArithSoft>& tr) {
    const double* v[3] = {tr.v0, tr.e1, tr.e2};
    double x[3], y[3], xa[3], ya[3];
    double big = 0;
    for (int k = 0; k < 3; ++k) {
        const double z = v[k][r.kz] - r.o[r.kz], za = std::fabs(v[k][r.kz]) + std::fabs(r.o[r.kz]);
        x[k] = (v[k][r.kx] - r.o[r.kx]) - r.sx * z;
        y[k] = (v[k][r.ky] - r.o[r.ky]) - r.sy * z;
        xa[k] = std::fabs(v[k][r.kx]) + std::fabs(r.o[r.kx]) + std::fabs(r.sx) * za;
        ya[k] = std::fabs(v[k][r.ky]) + std::fabs(r.o[r.ky]) + std::fabs(r.sy) * za;
        big = std::max(big, std::max(xa[k], ya[k]));
    }
    const double e[3] = {x[2] * y[1] - y[2] * x[1], x[0] * y[2] - y[0] * x[2], x[1] * y[0] - y[1] * x[0]};
    const double ea[3] = {xa[2] * ya[1] + ya[2] * xa[1], xa[0] * ya[2] + ya[0] * xa[2], xa[1] * ya[0] + ya[1] * xa[0]};
    if (!(big <= b.smax) || !(std::max(ea[0], std::max(ea[1], ea[2])) <= b.smax)) return false;
    const double tiny = 64 * b.eta * (1 + big);
    bool neg = false, pos = false;
    for (int k = 0; k < 3; ++k) {
        const double bound = b.k * ea[k] + tiny;
        neg = neg || e[k] < -bound;
        pos = pos || e[k] > bound;
    }
    return neg && pos;
}

}  // namespace raplas
