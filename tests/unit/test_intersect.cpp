// Eq. 1 (plane-sphere) and Eq. 2 (ray-triangle) kernels, in float32, float64
// and an emulated 24-bit format.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "raplas/core/intersect.hpp"
#include "raplas/core/row_hits.hpp"
#include "raplas/core/numfmt.hpp"

namespace {

using raplas::ArithF32;
using raplas::ArithF64;
using raplas::ArithSoft;
using raplas::Hit;
using raplas::NumFormat;
using raplas::Plane;
using raplas::Ray;
using raplas::Sphere;
using raplas::TriangleRec;
using raplas::Vec3d;
using raplas::Vec3f;

// Factories so one typed test body covers every number format.
struct F32 {
    using A = ArithF32;
    static A make() { return A{}; }
};
struct F64 {
    using A = ArithF64;
    static A make() { return A{}; }
};
struct Soft24 {
    using A = ArithSoft;
    static A make() { return A{NumFormat::parse("fp1-7-16"), true}; }
};

TriangleRec tri(Vec3d a, Vec3d b, Vec3d c) {
    Vec3d e1 = b - a, e2 = c - a;
    return {raplas::to_f(a), raplas::to_f(e1), raplas::to_f(e2), raplas::to_f(raplas::cross(e1, e2))};
}

Ray ray(Vec3d o, Vec3d d, float tmin = 0.0f, float tmax = std::numeric_limits<float>::max()) {
    return Ray{raplas::to_f(o), raplas::to_f(d), tmin, tmax};
}

template <class P>
class IntersectKernel : public ::testing::Test {
protected:
    using A = typename P::A;
    A a = P::make();

    bool hits(const Ray& r, const TriangleRec& t, double& tt) const {
        return raplas::ray_hits_triangle(a, raplas::load(a, r), raplas::load(a, t), tt);
    }
    bool hits(const Ray& r, const TriangleRec& t) const {
        double tt;
        return hits(r, t, tt);
    }
    bool plane_sphere(const Plane& p, const Sphere& s) const {
        return raplas::plane_hits_sphere(a, raplas::load(a, p), raplas::load(a, s));
    }
    // Nearest hit over a list, in the given visiting order.
    Hit nearest(const Ray& r, const std::vector<TriangleRec>& tris, const std::vector<int>& order) const {
        Hit best;
        auto ra = raplas::load(a, r);
        for (int i : order) {
            double tt;
            if (raplas::ray_hits_triangle(a, ra, raplas::load(a, tris[static_cast<std::size_t>(i)]), tt))
                raplas::keep_nearest(best, tt, i);
        }
        return best;
    }
};

using Formats = ::testing::Types<F32, F64, Soft24>;
class FormatNames {
public:
    template <class T>
    static std::string GetName(int) {
        if (std::is_same<T, F32>::value) return "float32";
        if (std::is_same<T, F64>::value) return "float64";
        return "fp1_7_16";
    }
};
TYPED_TEST_SUITE(IntersectKernel, Formats, FormatNames);

// Unit right triangle in the z = 0 plane, normal +z.
const TriangleRec kTri = tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0});

TYPED_TEST(IntersectKernel, FrontHitGivesExactDistance) {
    double t = -1;
    ASSERT_TRUE(this->hits(ray({0.25, 0.25, 1}, {0, 0, -1}), kTri, t));
    EXPECT_EQ(t, 1.0);
    // d is not normalised: t scales with 1/|d|
    ASSERT_TRUE(this->hits(ray({0.25, 0.25, 3}, {0, 0, -2}), kTri, t));
    EXPECT_EQ(t, 1.5);
    // oblique ray
    ASSERT_TRUE(this->hits(ray({-0.75, -0.75, 2}, {0.5, 0.5, -1}), kTri, t));
    EXPECT_EQ(t, 2.0);
}

TYPED_TEST(IntersectKernel, BackFaceHitsToo) {
    double t = -1;
    ASSERT_TRUE(this->hits(ray({0.25, 0.25, -1}, {0, 0, 1}), kTri, t));
    EXPECT_EQ(t, 1.0);
    // same triangle with the opposite winding, hit from both sides
    const TriangleRec flipped = tri({0, 0, 0}, {0, 1, 0}, {1, 0, 0});
    ASSERT_TRUE(this->hits(ray({0.25, 0.25, 1}, {0, 0, -1}), flipped, t));
    EXPECT_EQ(t, 1.0);
    ASSERT_TRUE(this->hits(ray({0.25, 0.25, -4}, {0, 0, 2}), flipped, t));
    EXPECT_EQ(t, 2.0);
}

TYPED_TEST(IntersectKernel, MissesOutsideTheTriangle) {
    EXPECT_FALSE(this->hits(ray({0.75, 0.75, 1}, {0, 0, -1}), kTri));   // beyond the hypotenuse
    EXPECT_FALSE(this->hits(ray({-0.1, 0.5, 1}, {0, 0, -1}), kTri));    // left of the y edge
    EXPECT_FALSE(this->hits(ray({0.5, -0.1, 1}, {0, 0, -1}), kTri));    // below the x edge
    EXPECT_FALSE(this->hits(ray({2, 2, -1}, {0, 0, 1}), kTri));         // back side, outside
    EXPECT_FALSE(this->hits(ray({0.25, 0.25, 1}, {1, 1, -0.1}), kTri));  // reaches z = 0 far away
    // points just inside each edge are hits (the miss cases are not vacuous)
    EXPECT_TRUE(this->hits(ray({0.01, 0.5, 1}, {0, 0, -1}), kTri));
    EXPECT_TRUE(this->hits(ray({0.5, 0.01, 1}, {0, 0, -1}), kTri));
    EXPECT_TRUE(this->hits(ray({0.49, 0.49, 1}, {0, 0, -1}), kTri));
}

TYPED_TEST(IntersectKernel, RayParallelToTriangleNeverHits) {
    // in the triangle's plane, through its interior
    EXPECT_FALSE(this->hits(ray({-1, 0.25, 0}, {1, 0, 0}), kTri));
    // parallel above the plane
    EXPECT_FALSE(this->hits(ray({-1, 0.25, 0.5}, {1, 0, 0}), kTri));
    EXPECT_FALSE(this->hits(ray({-1, -1, 0.5}, {1, 1, 0}), kTri));
    // zero direction
    EXPECT_FALSE(this->hits(ray({0.25, 0.25, 1}, {0, 0, 0}), kTri));
}

TYPED_TEST(IntersectKernel, DegenerateTriangleNeverHits) {
    const TriangleRec line = tri({0, 0, 0}, {1, 1, 0}, {2, 2, 0});
    const TriangleRec point = tri({0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, 0.5, 0});
    EXPECT_FALSE(this->hits(ray({1, 1, 1}, {0, 0, -1}), line));
    EXPECT_FALSE(this->hits(ray({0.5, 0.5, 1}, {0, 0, -1}), point));
}

TYPED_TEST(IntersectKernel, NonFiniteRayNeverHits) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    Ray r = ray({0.25, 0.25, 1}, {0, 0, -1});
    r.d.z = nan;
    EXPECT_FALSE(this->hits(r, kTri));
    r = ray({0.25, 0.25, 1}, {0, 0, -1});
    r.o.x = nan;
    EXPECT_FALSE(this->hits(r, kTri));
}

TYPED_TEST(IntersectKernel, OpenIntervalTminTmax) {
    // the hit is at t = 1 exactly
    const Vec3d o{0.25, 0.25, 1}, d{0, 0, -1};
    EXPECT_TRUE(this->hits(ray(o, d, 0.0f, 2.0f), kTri));
    EXPECT_FALSE(this->hits(ray(o, d, 0.0f, 1.0f), kTri));   // t == tmax is excluded
    EXPECT_TRUE(this->hits(ray(o, d, 0.0f, 1.125f), kTri));
    EXPECT_FALSE(this->hits(ray(o, d, 0.0f, 0.5f), kTri));
    EXPECT_FALSE(this->hits(ray(o, d, 1.0f, 2.0f), kTri));   // t == tmin is excluded
    EXPECT_TRUE(this->hits(ray(o, d, 0.875f, 2.0f), kTri));
    EXPECT_FALSE(this->hits(ray(o, d, 1.5f, 4.0f), kTri));
    // behind the origin: t = -1
    EXPECT_FALSE(this->hits(ray({0.25, 0.25, -1}, {0, 0, -1}), kTri));
    EXPECT_TRUE(this->hits(ray({0.25, 0.25, -1}, {0, 0, -1}, -2.0f, 2.0f), kTri));
    // origin on the plane: t = 0 is not in (0, tmax)
    EXPECT_FALSE(this->hits(ray({0.25, 0.25, 0}, {0, 0, -1}), kTri));
}

TYPED_TEST(IntersectKernel, InclusiveEdgesAndVertices) {
    // Ray exactly through the triangle's own edges and corners: inclusive rule.
    EXPECT_TRUE(this->hits(ray({0, 0.5, 1}, {0, 0, -1}), kTri));    // on the y edge (u' = 0)
    EXPECT_TRUE(this->hits(ray({0.5, 0, 1}, {0, 0, -1}), kTri));    // on the x edge (v' = 0)
    EXPECT_TRUE(this->hits(ray({0.5, 0.5, 1}, {0, 0, -1}), kTri));  // on the hypotenuse (u'+v' = det)
    EXPECT_TRUE(this->hits(ray({0, 0, 1}, {0, 0, -1}), kTri));
    EXPECT_TRUE(this->hits(ray({1, 0, 1}, {0, 0, -1}), kTri));
    EXPECT_TRUE(this->hits(ray({0, 1, 1}, {0, 0, -1}), kTri));
}

TYPED_TEST(IntersectKernel, SharedEdgeOfAQuadIsNeverAGap) {
    // Unit square split along its diagonal; rays through the diagonal and
    // through the shared corners, from above and below, straight and oblique.
    const std::vector<TriangleRec> quad = {tri({0, 0, 0}, {1, 0, 0}, {1, 1, 0}), tri({0, 0, 0}, {1, 1, 0}, {0, 1, 0})};
    for (double s : {0.0, 0.125, 0.25, 0.5, 0.625, 0.875, 1.0}) {
        const Vec3d p{s, s, 0};
        for (Vec3d d : {Vec3d{0, 0, -1}, Vec3d{0, 0, 1}, Vec3d{0.25, -0.5, -1}, Vec3d{-0.75, 0.125, 1}}) {
            Ray r = ray(p - d * 2.0, d);
            double t0 = 0, t1 = 0;
            bool h0 = this->hits(r, quad[0], t0), h1 = this->hits(r, quad[1], t1);
            EXPECT_TRUE(h0 || h1) << "gap at s=" << s;
            // exact arithmetic here: the inclusive rule makes both triangles report it
            EXPECT_TRUE(h0 && h1) << "s=" << s;
            if (h0) { EXPECT_EQ(t0, 2.0); }
            if (h1) { EXPECT_EQ(t1, 2.0); }
        }
    }
}

TYPED_TEST(IntersectKernel, SharedEdgesOfRandomTiltedGridHaveNoGaps) {
    // A height field over an integer grid: z takes small integer values, so
    // every intermediate of Eq. 2 is exact even in the 24-bit format, and a
    // ray through a point of a shared edge must hit at least one of the two
    // triangles (both, with the inclusive rule).
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> zdist(-2, 2), kdist(0, 8), ddist(-4, 4);
    const int G = 4;
    double z[G + 1][G + 1];
    for (auto& row : z)
        for (double& v : row) v = zdist(rng);
    auto P = [&](int i, int j) { return Vec3d(i, j, z[i][j]); };
    // a ray in a triangle's plane never hits it (Eq. 2 has det = 0)
    auto parallel = [](const Vec3d& d, const TriangleRec& t) { return raplas::dot(d, raplas::to_d(t.n)) == 0; };
    int checked = 0;
    for (int i = 0; i < G; ++i) {
        for (int j = 0; j < G; ++j) {
            // cell split along (i,j)-(i+1,j+1)
            TriangleRec a = tri(P(i, j), P(i + 1, j), P(i + 1, j + 1));
            TriangleRec b = tri(P(i, j), P(i + 1, j + 1), P(i, j + 1));
            // and the shared edge with the right neighbour cell: (i+1,j)-(i+1,j+1)
            for (int rep = 0; rep < 6; ++rep) {
                double k = kdist(rng) / 8.0;
                Vec3d p = P(i, j) + (P(i + 1, j + 1) - P(i, j)) * k;
                Vec3d d{ddist(rng) / 8.0, ddist(rng) / 8.0, rep % 2 ? 1.0 : -1.0};
                if (parallel(d, a) || parallel(d, b)) continue;
                Ray r = ray(p - d * 2.0, d);
                double ta = 0, tb = 0;
                bool ha = this->hits(r, a, ta), hb = this->hits(r, b, tb);
                ASSERT_TRUE(ha || hb) << "gap on diagonal of cell " << i << "," << j << " k=" << k;
                EXPECT_TRUE(ha && hb);
                if (ha) { EXPECT_EQ(ta, 2.0); }
                if (hb) { EXPECT_EQ(tb, 2.0); }
                ++checked;
            }
            if (i + 1 < G) {
                // the neighbour cell's upper triangle holds the same edge
                TriangleRec dd = tri(P(i + 1, j), P(i + 2, j + 1), P(i + 1, j + 1));
                for (int rep = 0; rep < 4; ++rep) {
                    double k = kdist(rng) / 8.0;
                    Vec3d p = P(i + 1, j) + (P(i + 1, j + 1) - P(i + 1, j)) * k;
                    Vec3d d{ddist(rng) / 8.0, ddist(rng) / 8.0, rep % 2 ? 1.0 : -1.0};
                    if (parallel(d, a) || parallel(d, dd)) continue;
                    Ray r = ray(p - d * 2.0, d);
                    bool ha = this->hits(r, a), hd = this->hits(r, dd);
                    ASSERT_TRUE(ha || hd) << "gap between cells " << i << "," << j << " and " << i + 1 << "," << j;
                    EXPECT_TRUE(ha && hd);
                    ++checked;
                }
            }
        }
    }
    EXPECT_GT(checked, 100);
}

TYPED_TEST(IntersectKernel, AgreesWithDoubleReferenceAwayFromEdges) {
    // Random rays and triangles: wherever the exact (double) barycentrics are
    // clearly inside or clearly outside, the kernel agrees, and t is close.
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> U(-1, 1);
    const bool soft = std::is_same<TypeParam, Soft24>::value;
    const double margin = soft ? 0.05 : 1e-3;   // how clearly inside/outside a case must be
    const double ttol = soft ? 5e-3 : 1e-4;     // relative tolerance on t
    int hits = 0, misses = 0;
    for (int it = 0; it < 3000; ++it) {
        Vec3d a{U(rng), U(rng), U(rng)}, b{U(rng), U(rng), U(rng)}, c{U(rng), U(rng), U(rng)};
        Vec3d o{U(rng) * 3, U(rng) * 3, U(rng) * 3};
        Vec3d target = a * 0.3 + b * 0.3 + c * 0.4 + Vec3d{U(rng), U(rng), U(rng)} * 0.6;
        // reference from the float-rounded inputs, in double
        TriangleRec tr = tri(a, b, c);
        Ray r = ray(o, target - o);
        Vec3d v0 = raplas::to_d(tr.v0), e1 = raplas::to_d(tr.e1), e2 = raplas::to_d(tr.e2);
        Vec3d O = raplas::to_d(r.o), D = raplas::to_d(r.d);
        Vec3d pv = raplas::cross(D, e2);
        double det = raplas::dot(e1, pv);
        if (raplas::length(e1) < 0.3 || raplas::length(e2) < 0.3) continue;
        const Vec3d nrm = raplas::to_d(tr.n);
        if (std::fabs(raplas::dot(D, nrm)) < 0.05 * raplas::length(D) * raplas::length(nrm))
            continue;  // grazing
        if (std::fabs(det) < 1e-6) continue;
        Vec3d T = O - v0;
        double u = raplas::dot(T, pv) / det;
        Vec3d q = raplas::cross(T, e1);
        double v = raplas::dot(D, q) / det;
        double t = raplas::dot(e2, q) / det;
        const double m = std::min({u, v, 1 - u - v});
        if (std::fabs(m) < margin || std::fabs(t) < margin) continue;  // too close to call
        const bool expect = m > 0 && t > 0;
        double tt = 0;
        const bool got = this->hits(r, tr, tt);
        ASSERT_EQ(got, expect) << "iteration " << it << " u=" << u << " v=" << v << " t=" << t;
        if (got) {
            EXPECT_NEAR(tt, t, ttol * std::max(1.0, t)) << "iteration " << it;
            ++hits;
        } else {
            ++misses;
        }
    }
    EXPECT_GT(hits, 200);
    EXPECT_GT(misses, 200);
}

TYPED_TEST(IntersectKernel, KeepNearestTieBreakIsOrderIndependent) {
    // Three coplanar copies of the same triangle (indices 0..2) plus one
    // nearer and one farther: whatever the visiting order, the nearest wins,
    // and among equal distances the smaller index.
    const std::vector<TriangleRec> tris = {
        tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0}),       // 0: t = 1
        tri({0, 0, -1}, {1, 0, -1}, {0, 1, -1}),    // 1: t = 2
        tri({0, 0, 0}, {0, 1, 0}, {1, 0, 0}),       // 2: t = 1 (opposite winding)
        tri({-1, -1, 0}, {2, -1, 0}, {-1, 2, 0}),   // 3: t = 1, larger
        tri({0, 0, 0.5}, {1, 0, 0.5}, {0, 1, 0.5}), // 4: t = 0.5
    };
    const Ray r = ray({0.25, 0.25, 1}, {0, 0, -1});
    std::vector<int> order = {0, 1, 2, 3, 4};
    std::vector<int> without_near = {0, 1, 2, 3};
    do {
        Hit h = this->nearest(r, tris, order);
        EXPECT_EQ(h.tri, 4);
        EXPECT_EQ(h.t, 0.5);
    } while (std::next_permutation(order.begin(), order.end()));
    do {
        Hit h = this->nearest(r, tris, without_near);
        EXPECT_EQ(h.tri, 0);
        EXPECT_EQ(h.t, 1.0);
    } while (std::next_permutation(without_near.begin(), without_near.end()));
    std::vector<int> ties = {3, 2};
    EXPECT_EQ(this->nearest(r, tris, ties).tri, 2);
    std::vector<int> far_only = {1};
    EXPECT_EQ(this->nearest(r, tris, far_only).tri, 1);
}

TYPED_TEST(IntersectKernel, PlaneSphereBasic) {
    const Plane z0{{0, 0, 1}, 0};  // z = 0
    EXPECT_TRUE(this->plane_sphere(z0, Sphere{{0, 0, 0}, 0.5f}));
    EXPECT_TRUE(this->plane_sphere(z0, Sphere{{7, -3, 0.25}, 0.5f}));
    EXPECT_FALSE(this->plane_sphere(z0, Sphere{{0, 0, 2}, 1.0f}));
    EXPECT_FALSE(this->plane_sphere(z0, Sphere{{0, 0, -2}, 1.0f}));  // below: |d| counts
    EXPECT_TRUE(this->plane_sphere(z0, Sphere{{0, 0, -2}, 3.0f}));
    // tangent: |d| == r is a hit
    EXPECT_TRUE(this->plane_sphere(z0, Sphere{{0, 0, 2}, 2.0f}));
    EXPECT_TRUE(this->plane_sphere(z0, Sphere{{0, 0, -2}, 2.0f}));
    EXPECT_FALSE(this->plane_sphere(z0, Sphere{{0, 0, 2}, 1.96875f}));
    // offset plane z = 2 (w = -2)
    const Plane z2{{0, 0, 1}, -2};
    EXPECT_TRUE(this->plane_sphere(z2, Sphere{{0, 0, 0}, 2.0f}));
    EXPECT_FALSE(this->plane_sphere(z2, Sphere{{0, 0, 0}, 1.5f}));
    EXPECT_TRUE(this->plane_sphere(z2, Sphere{{5, 5, 5}, 3.0f}));
    EXPECT_FALSE(this->plane_sphere(z2, Sphere{{5, 5, 5}, 2.875f}));
    // zero radius: only a centre exactly on the plane
    EXPECT_TRUE(this->plane_sphere(z2, Sphere{{1, 1, 2}, 0.0f}));
    EXPECT_FALSE(this->plane_sphere(z2, Sphere{{1, 1, 2.5}, 0.0f}));
    // oblique unit normal (0.6, 0.8, 0): distance of (3, 4, 0) is 5
    const Plane ob{{0.6f, 0.8f, 0}, 0};
    EXPECT_TRUE(this->plane_sphere(ob, Sphere{{3, 4, 0}, 5.01f}));
    EXPECT_FALSE(this->plane_sphere(ob, Sphere{{3, 4, 0}, 4.99f}));
    EXPECT_TRUE(this->plane_sphere(ob, Sphere{{4, -3, 9}, 0.01f}));  // centre on the plane
    EXPECT_TRUE(this->plane_sphere(ob, Sphere{{-3, -4, 0}, 5.01f}));
    EXPECT_FALSE(this->plane_sphere(ob, Sphere{{-3, -4, 0}, 4.99f}));
}

TYPED_TEST(IntersectKernel, PlaneSphereAgreesWithDoubleAwayFromTheBoundary) {
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> U(-1, 1);
    const double rel = std::is_same<TypeParam, Soft24>::value ? 1e-3 : 1e-5;
    int in = 0, out = 0;
    for (int it = 0; it < 5000; ++it) {
        Vec3d n = raplas::normalize(Vec3d{U(rng), U(rng), U(rng)});
        Plane p{raplas::to_f(n), float(U(rng) * 10)};
        Sphere s{{float(U(rng) * 10), float(U(rng) * 10), float(U(rng) * 10)}, float((U(rng) + 1) * 4)};
        double d = std::fabs(double(p.n.x) * s.c.x + double(p.n.y) * s.c.y + double(p.n.z) * s.c.z + p.w);
        if (std::fabs(d - s.r) < rel * 40) continue;
        bool expect = d <= s.r;
        ASSERT_EQ(this->plane_sphere(p, s), expect) << "iteration " << it << " d=" << d << " r=" << s.r;
        (expect ? in : out)++;
    }
    EXPECT_GT(in, 500);
    EXPECT_GT(out, 500);
}

TYPED_TEST(IntersectKernel, BatchedPlaneTestsEqualTheScalarTest) {
    // plane_masks / group_sphere_hits (the vectorisable layout) against
    // plane_hits_sphere one pair at a time: random pairs plus exact tangents
    // (|d| == r), more spheres than one chunk, masks of 32 and 64 bits.
    using A = typename TestFixture::A;
    const A& a = this->a;
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> U(-1, 1);
    std::uniform_int_distribution<int> I(-4, 4);
    std::vector<raplas::SphereA<A>> spheres;
    raplas::SphereSoA<A> soa;
    for (int i = 0; i < 1300; ++i) {
        Sphere s;
        if (i % 3 == 0) {
            // small integers: tangent to the axis planes below exactly
            s = Sphere{{float(I(rng)), float(I(rng)), float(I(rng))}, float(std::abs(I(rng)) + 1)};
        } else {
            s = Sphere{{float(U(rng) * 4), float(U(rng) * 4), float(U(rng) * 4)}, float(U(rng) + 1.2)};
        }
        spheres.push_back(raplas::load(a, s));
        soa.push_back(spheres.back());
    }
    for (std::uint32_t n : {5u, 16u, 32u, 33u, 64u}) {
        std::vector<raplas::PlaneA<A>> planes;
        for (std::uint32_t p = 0; p < 2 * n; ++p) {
            Plane pl;
            if (p % 2 == 0) {
                // axis plane x, y or z = small integer
                const int axis = I(rng) & 3 ? int(p / 2 % 3) : 2;
                pl.n = Vec3f{axis == 0 ? 1.f : 0.f, axis == 1 ? 1.f : 0.f, axis == 2 ? 1.f : 0.f};
                pl.w = float(I(rng));
            } else {
                pl.n = raplas::to_f(raplas::normalize(Vec3d{U(rng), U(rng), U(rng)}));
                pl.w = float(U(rng) * 3);
            }
            planes.push_back(raplas::load(a, pl));
        }
        // rows: the first n planes, as a mask per sphere
        std::vector<std::uint64_t> masks(spheres.size());
        raplas::plane_masks(a, planes.data(), n, soa, 0, spheres.size(), masks.data());
        std::size_t tangent = 0;
        for (std::size_t i = 0; i < spheres.size(); ++i) {
            std::uint64_t want = 0;
            for (std::uint32_t p = 0; p < n; ++p) {
                want |= std::uint64_t(raplas::plane_hits_sphere(a, planes[p], spheres[i])) << p;
                const auto& pl = planes[p];
                const auto& s = spheres[i];
                tangent += std::fabs(double(pl.nx) * s.cx + double(pl.ny) * s.cy + double(pl.nz) * s.cz + pl.w) ==
                           double(s.r);
            }
            ASSERT_EQ(masks[i], want) << "n=" << n << " sphere " << i;
        }
        EXPECT_GT(tangent, 20u) << "n=" << n;
        // the whole group decision, with some rows and columns invalid
        const std::uint64_t full = n == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
        const std::uint64_t row_valid = full & ~std::uint64_t(0x6), col_valid = full >> 1;
        std::vector<raplas::SphereHitRec> got;
        raplas::group_sphere_hits(a, planes.data(), n, row_valid, col_valid, soa, got);
        std::vector<raplas::SphereHitRec> want;
        for (std::size_t i = 0; i < spheres.size(); ++i) {
            std::uint64_t rows = 0, cols = 0;
            for (std::uint32_t p = 0; p < n; ++p) {
                rows |= std::uint64_t(raplas::plane_hits_sphere(a, planes[p], spheres[i])) << p;
                cols |= std::uint64_t(raplas::plane_hits_sphere(a, planes[n + p], spheres[i])) << p;
            }
            rows &= row_valid;
            cols &= col_valid;
            if (rows && cols) want.push_back({std::uint32_t(i), rows, cols});
        }
        ASSERT_EQ(got.size(), want.size()) << "n=" << n;
        EXPECT_GT(want.size(), 50u);
        EXPECT_LT(want.size(), spheres.size());
        for (std::size_t k = 0; k < want.size(); ++k) {
            ASSERT_EQ(got[k].sphere, want[k].sphere) << "n=" << n;
            ASSERT_EQ(std::uint64_t{got[k].rows}, std::uint64_t{want[k].rows}) << "n=" << n;
            ASSERT_EQ(std::uint64_t{got[k].cols}, std::uint64_t{want[k].cols}) << "n=" << n;
        }
    }
}

TEST(IntersectEmulated, DistanceIsAValueOfTheFormat) {
    const NumFormat f = NumFormat::parse("fp1-7-16");
    const ArithSoft a{f, true};
    // a hit whose t = 1/3 is not representable
    double t = 0;
    const Ray r = ray({0.25, 0.25, 1}, {0, 0, -3});
    ASSERT_TRUE(raplas::ray_hits_triangle(a, raplas::load(a, r), raplas::load(a, kTri), t));
    EXPECT_EQ(f.round(t), t);
    EXPECT_NE(t, 1.0 / 3.0);
    EXPECT_NEAR(t, 1.0 / 3.0, 1.0 / 3.0 * f.unit_roundoff() * 2);
    // float32 would keep more bits than the format allows
    EXPECT_NE(double(float(1.0 / 3.0)), t);
}

TEST(IntersectEmulated, InputsAreRoundedIntoTheFormat) {
    // The triangle's left edge is at x = 1 + 2^-20 and the ray at
    // x = 1 + 2^-21: float32 holds both exactly (the ray passes left of the
    // edge and misses); in 17 significant bits both round to x = 1, so the
    // ray lies exactly on the edge and the inclusive rule makes it a hit.
    const double eps = std::ldexp(1.0, -20);
    const TriangleRec t = tri({1 + eps, -1, 0}, {3, -1, 0}, {1 + eps, 1, 0});
    const Ray r = ray({1 + eps / 2, 0, 1}, {0, 0, -1});
    const ArithSoft soft{NumFormat::parse("fp1-7-16"), true};
    const ArithF32 f32;
    EXPECT_EQ(soft.cvt(1 + eps), 1.0);
    EXPECT_EQ(soft.cvt(1 + eps / 2), 1.0);
    double tt = 0;
    EXPECT_FALSE(raplas::ray_hits_triangle(f32, raplas::load(f32, r), raplas::load(f32, t), tt));
    EXPECT_TRUE(raplas::ray_hits_triangle(soft, raplas::load(soft, r), raplas::load(soft, t), tt));
    EXPECT_EQ(tt, 1.0);
}

TEST(KeepNearest, SmallerTThenSmallerIndex) {
    Hit best;
    EXPECT_EQ(best.tri, -1);
    raplas::keep_nearest(best, 2.0, 5);
    EXPECT_EQ(best.tri, 5);
    EXPECT_EQ(best.t, 2.0);
    raplas::keep_nearest(best, 2.0, 7);  // tie, larger index: kept
    EXPECT_EQ(best.tri, 5);
    raplas::keep_nearest(best, 2.0, 3);  // tie, smaller index: replaces
    EXPECT_EQ(best.tri, 3);
    raplas::keep_nearest(best, 3.0, 0);  // farther: ignored even with index 0
    EXPECT_EQ(best.tri, 3);
    EXPECT_EQ(best.t, 2.0);
    raplas::keep_nearest(best, 1.5, 9);  // nearer: replaces
    EXPECT_EQ(best.tri, 9);
    EXPECT_EQ(best.t, 1.5);
}

TEST(KeepNearest, HitEqualityIgnoresTOfMisses) {
    Hit a, b;
    a.t = 1;
    b.t = 2;
    EXPECT_EQ(a, b);  // both misses
    a.tri = b.tri = 4;
    EXPECT_NE(a, b);
    b.t = 1;
    EXPECT_EQ(a, b);
    b.tri = 5;
    EXPECT_NE(a, b);
}

}  // namespace

// The row kernel of the front end (rays_hit_triangle_native: rays sharing an
// origin, vectorised) gives the same hit flags and the same t bits as the
// ray-by-ray test, on random rays, back faces, edges, parallel and degenerate
// triangles, and non-finite directions.
template <class T>
void row_kernel_matches_scalar() {
    using A = raplas::ArithNative<T>;
    const A a{};
    std::mt19937_64 rng(77);
    std::uniform_real_distribution<double> u(-2, 2);
    auto v = [&] { return Vec3d{u(rng), u(rng), u(rng)}; };
    std::vector<TriangleRec> tris;
    for (int i = 0; i < 200; ++i) tris.push_back(tri(v(), v(), v()));
    tris.push_back(tri({0, 0, 0}, {1, 0, 0}, {2, 0, 0}));     // collinear
    tris.push_back(tri({0, 0, 0}, {0, 0, 0}, {0, 1, 0}));     // repeated vertex
    tris.push_back(tri({0, 0, 1}, {1, 0, 1}, {0, 1, 1}));     // z = 1, hit edge-on below
    const std::size_t n = 64;
    std::uint64_t hits = 0, compared = 0;
    for (int g = 0; g < 40; ++g) {
        Ray r0;
        r0.o = raplas::to_f(g % 4 == 0 ? Vec3d{0.25, 0.25, -1} : v());
        r0.tmin = 0.0f;
        r0.tmax = g % 3 == 0 ? 1e30f : float(1 + u(rng) * 0.4);
        std::vector<T> dx(n), dy(n), dz(n);
        std::vector<raplas::RayA<A>> rays(n);
        for (std::size_t i = 0; i < n; ++i) {
            Ray r = r0;
            if (g % 4 == 0 && i < 8) {
                r.d = raplas::to_f(Vec3d{0.25 * double(i % 2), 0.25 * double(i / 2 % 2), 1.0});  // vertex, edges
            } else {
                r.d = raplas::to_f(v());
            }
            if (i == 9) r.d = Vec3f{0, 0, 0};  // det = 0
            if (i == 10) r.d.x = std::numeric_limits<float>::quiet_NaN();
            if (i == 11) r.d.y = std::numeric_limits<float>::infinity();
            rays[i] = raplas::load(a, r);
            dx[i] = rays[i].d[0];
            dy[i] = rays[i].d[1];
            dz[i] = rays[i].d[2];
        }
        for (const TriangleRec& t : tris) {
            const auto ta = raplas::load(a, t);
            std::vector<std::uint8_t> hit(n);
            std::vector<T> tt(n);
            const bool any = raplas::rays_hit_triangle_native<T>(rays[0].o, rays[0].tmin, rays[0].tmax, dx.data(),
                                                                 dy.data(), dz.data(), n, ta, hit.data(), tt.data());
            bool any_scalar = false;
            std::vector<std::uint8_t> scalar_hit(n);
            std::vector<double> scalar_t(n);
            for (std::size_t i = 0; i < n; ++i) {
                double ts = 0;
                const bool hs = raplas::ray_hits_triangle(a, rays[i], ta, ts);
                scalar_hit[i] = hs;
                scalar_t[i] = ts;
                any_scalar = any_scalar || hs;
                ASSERT_EQ(bool(hit[i]), hs) << "group " << g << " ray " << i;
                if (hs) {
                    ASSERT_EQ(static_cast<double>(tt[i]), ts) << "group " << g << " ray " << i;
                    ++hits;
                }
                ++compared;
            }
            ASSERT_EQ(any, any_scalar);
            // The same rays as an N x N group (ray v * N + h), whole triangle at
            // once (rows_hit_triangle): random row and column masks, group sizes
            // that fill vectors and sizes that leave a partial one.
            for (const std::uint32_t gn : {8u, 5u, 3u, 1u}) {
                const std::uint64_t all = (std::uint64_t(1) << gn) - 1;
                std::uint64_t rows = rng() & all, cols = rng() & all;
                if (!rows) rows = all;
                if (!cols) cols = std::uint64_t(1) << (gn - 1);
                std::uint64_t hm[64];
                std::vector<T> tg(std::size_t(gn) * gn);
                const bool anyg = raplas::rows_hit_triangle(rays[0].o, rays[0].tmin, rays[0].tmax, dx.data(), dy.data(),
                                                            dz.data(), gn, rows, cols, ta, hm, tg.data());
                bool want_any = false;
                for (std::uint64_t rm = rows; rm; rm &= rm - 1) {
                    const auto rv = std::uint32_t(__builtin_ctzll(rm));
                    for (std::uint32_t h = 0; h < gn; ++h) {
                        const std::size_t i = std::size_t(rv) * gn + h;
                        const bool want = ((cols >> h) & 1) && scalar_hit[i];
                        want_any = want_any || want;
                        ASSERT_EQ(bool((hm[rv] >> h) & 1), want) << "group " << g << " N " << gn << " ray " << i;
                        if (want) {
                            ASSERT_EQ(static_cast<double>(tg[i]), scalar_t[i]) << "group " << g << " ray " << i;
                        }
                    }
                    ASSERT_EQ(hm[rv] & ~cols, 0u);
                }
                ASSERT_EQ(anyg, want_any) << "group " << g << " N " << gn;
            }
        }
    }
    EXPECT_GT(hits, 1000u) << "the cases hit triangles";
    EXPECT_GT(compared, 400000u);
}

TEST(RowKernel, SameAsRayByRayFloat32) { row_kernel_matches_scalar<float>(); }
TEST(RowKernel, SameAsRayByRayFloat64) { row_kernel_matches_scalar<double>(); }

// rays_certainly_miss_triangle_native is a proof: whenever it says no ray of a direction box
// hits, the row kernel (and the ray-by-ray test) finds no hit for any ray in that box. The
// cases sit on the boundaries where rounding decides: rays through an edge or a vertex
// perturbed by a few units in the last place, a triangle's far end at t = tmax, an origin on
// the triangle's plane (t' about 0), rays nearly parallel to the plane; each as a single ray
// (a box of one direction) and as a small bundle. It must also prove something: most clear
// misses are certified.
template <class T>
void certified_misses_never_hit() {
    using A = raplas::ArithNative<T>;
    std::mt19937_64 rng(4242);
    std::uniform_real_distribution<double> u(-2, 2), w(0, 1);
    auto v = [&] { return Vec3d{u(rng), u(rng), u(rng)}; };
    const double ulp = std::is_same_v<T, float> ? 0x1p-23 : 0x1p-52;
    std::uint64_t certified = 0, hits = 0, clear_misses = 0, clear_certified = 0;
    for (int it = 0; it < 60000; ++it) {
        const Vec3d p0 = v(), p1 = v(), p2 = v();
        raplas::TriA<A> tr;
        const Vec3d e1 = p1 - p0, e2 = p2 - p0, nn = raplas::cross(e1, e2);
        for (int i = 0; i < 3; ++i) {
            const std::size_t k = std::size_t(i);
            tr.v0[i] = T(p0[k]);
            tr.e1[i] = T(e1[k]);
            tr.e2[i] = T(e2[k]);
            tr.n[i] = T(nn[k]);
        }
        const int kind = it % 6;
        // the target point on the triangle: a vertex, an edge or the inside
        const double b1 = kind == 0 ? 0.0 : w(rng), b2 = kind == 1 ? 1.0 - b1 : (kind == 0 ? 0.0 : w(rng) * (1 - b1));
        const Vec3d target = p0 + e1 * b1 + e2 * b2;
        Vec3d o = v();
        if (kind == 2) o = p0 + e1 * (w(rng) * 2 - 0.5) + e2 * (w(rng) * 2 - 0.5) + nn * (ulp * u(rng));  // on the plane
        if (kind == 3) {  // nearly parallel: the origin a hair off the plane, far out along it
            o = target + (e1 * u(rng) + e2 * u(rng)) * 4.0 + nn * (1e-5 * u(rng));
        }
        const Vec3d d0 = target - o;
        T oo[3] = {T(o.x), T(o.y), T(o.z)};
        const double len = std::sqrt(raplas::dot(d0, d0));
        const int bundle = it % 2 == 0 ? 1 : 8;
        const double spread = kind == 5 ? 1e-3 : ulp * 8;
        std::vector<T> dx, dy, dz;
        raplas::DirectionBox<T> box;
        for (int i = 0; i < 3; ++i) {
            box.lo[i] = std::numeric_limits<T>::infinity();
            box.hi[i] = -std::numeric_limits<T>::infinity();
        }
        for (int r = 0; r < bundle; ++r) {
            const Vec3d d = d0 + Vec3d{u(rng), u(rng), u(rng)} * (spread * len * (r == 0 && bundle > 1 ? 0 : 1));
            const T dd[3] = {T(d.x), T(d.y), T(d.z)};
            dx.push_back(dd[0]);
            dy.push_back(dd[1]);
            dz.push_back(dd[2]);
            for (int i = 0; i < 3; ++i) {
                box.lo[i] = std::min(box.lo[i], dd[i]);
                box.hi[i] = std::max(box.hi[i], dd[i]);
            }
        }
        // tmax: at the target (t = 1) give or take a few ulps, or unbounded
        const T tmax = it % 3 == 0 ? std::numeric_limits<T>::max() : T(1 + ulp * 4 * u(rng));
        std::vector<std::uint8_t> hit(dx.size());
        std::vector<T> tt(dx.size());
        const bool any = raplas::rays_hit_triangle_native<T>(oo, T(0), tmax, dx.data(), dy.data(), dz.data(), dx.size(), tr,
                                                             hit.data(), tt.data());
        const bool proof = raplas::rays_certainly_miss_triangle_native<T>(oo, T(0), tmax, box, tr);
        hits += any;
        certified += proof;
        ASSERT_FALSE(proof && any) << "case " << it << " kind " << kind << ": certified miss, but a ray hits";
        // a clear miss: the same bundle aimed well beside the triangle, or turned round
        const Vec3d away = kind % 2 ? o - d0 : o + (target - p0) * 3.0 + nn * 0.01;
        const Vec3d dm = away - o;
        raplas::DirectionBox<T> mb;
        for (int i = 0; i < 3; ++i) mb.lo[i] = mb.hi[i] = T(dm[std::size_t(i)]);
        std::uint8_t mh = 0;
        T mt = 0;
        const bool miss_hits = raplas::rays_hit_triangle_native<T>(oo, T(0), tmax, &mb.lo[0], &mb.lo[1], &mb.lo[2], 1, tr,
                                                                   &mh, &mt);
        if (!miss_hits) {
            ++clear_misses;
            clear_certified += raplas::rays_certainly_miss_triangle_native<T>(oo, T(0), tmax, mb, tr);
        } else {
            ASSERT_FALSE(raplas::rays_certainly_miss_triangle_native<T>(oo, T(0), tmax, mb, tr));
        }
    }
    EXPECT_GT(hits, 10000u) << "the cases hit";
    EXPECT_GT(certified, 5000u) << "boundary cases are certified too";
    EXPECT_GT(clear_certified, clear_misses * 8 / 10) << "clear misses are certified";
    // non-finite boxes and a negative tmin prove nothing
    const raplas::TriA<A> tr{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const T o[3] = {0, 0, 0};
    raplas::DirectionBox<T> behind{{T(0.1), T(0.1), T(-1)}, {T(0.2), T(0.2), T(-1)}};
    EXPECT_TRUE(raplas::rays_certainly_miss_triangle_native<T>(o, T(0), T(10), behind, tr));
    EXPECT_FALSE(raplas::rays_certainly_miss_triangle_native<T>(o, T(-1), T(10), behind, tr));
    behind.lo[0] = std::numeric_limits<T>::quiet_NaN();
    EXPECT_FALSE(raplas::rays_certainly_miss_triangle_native<T>(o, T(0), T(10), behind, tr));
}

TEST(CertifiedMiss, NeverHidesAHitFloat32) { certified_misses_never_hit<float>(); }
TEST(CertifiedMiss, NeverHidesAHitFloat64) { certified_misses_never_hit<double>(); }
