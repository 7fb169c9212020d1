// The emulated formats decide most plane-sphere and ray-triangle tests from a
// double evaluation with an error bound (intersect.hpp, EmulatedBound). Those
// decisions, and every distance, must equal the operation-by-operation
// emulation bit for bit: checked here on cases packed around the decision
// boundaries, over formats of every width, both rounding modes, flushing,
// small exponent ranges (overflow, underflow) and the PSI without
// normalisation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "raplas/core/intersect.hpp"
#include "raplas/core/numfmt.hpp"

namespace {

using namespace raplas;
using Rng = std::mt19937_64;

double uni(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
Vec3d unit(Rng& rng) {
    for (;;) {
        Vec3d v{uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1)};
        const double l = length(v);
        if (l > 0.1 && l < 1) return v / l;
    }
}

const char* const kFormats[] = {"fp1-7-16",           "fp1-7-16-rtz",  "fp1-7-16-psiunnorm", "fp1-7-16-rtz-psiunnorm",
                                "fp1-8-15",           "fp1-6-17",      "fp1-5-10",           "fp1-4-3-ftz",
                                "fp1-4-6-rtz-psiunnorm", "fp1-8-2",    "fp1-8-23-rtz",       "fp1-11-25"};

// A scale well inside the format's range (up to 2^+-40), or near the range's
// edges now and then.
double scale(Rng& rng, const NumFormat& f) {
    const int k = int(rng() % 10);
    if (k == 0) return f.max_finite() * uni(rng, 0.01, 0.3);
    if (k == 1) return f.min_normal() * uni(rng, 1, 1e4);
    const int span = std::min(40, ((1 << (f.exp_bits - 1)) - 1) / 4);
    return std::ldexp(1.0, int(rng() % unsigned(2 * span + 1)) - span);
}

TEST(EmulationShortcuts, PlaneSphereDecisionsEqualTheEmulation) {
    for (const char* name : kFormats) {
        const ArithSoft a{NumFormat::parse(name), true};
        Rng rng(7);
        int shortcut = 0, emulated = 0;
        for (int i = 0; i < 40000; ++i) {
            const double sc = scale(rng, a.f);
            const Vec3d n = unit(rng);
            const Vec3d c = Vec3d{uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1)} * sc;
            const double r = sc * uni(rng, 1e-3, 0.5);
            // |d| = r (1 + e) with e from exactly 0 to far away
            const double es[] = {0, 1e-9, -1e-9, 1e-6, -1e-6, 1e-4, -1e-4, 1e-2, -1e-2, 0.5, -0.9};
            const double e = es[rng() % 11] * (rng() % 2 ? 1 : uni(rng, 0, 1));
            const double side = rng() % 2 ? 1 : -1;
            const Plane p{to_f(n), float(-dot(n, c) + side * r * (1 + e))};
            const Sphere s{to_f(c), float(r)};
            const PlaneA<ArithSoft> pa = load(a, p);
            const SphereA<ArithSoft> sa = load(a, s);
            const bool want = plane_hits_sphere_ops(a, pa, sa);
            ASSERT_EQ(plane_hits_sphere(a, pa, sa), want) << name << " case " << i;
            SphereSoA<ArithSoft> soa;
            soa.push_back(sa);
            std::uint32_t mask = 0;
            plane_masks(a, &pa, 1, soa, 0, 1, &mask);
            ASSERT_EQ(mask != 0, want) << name << " case " << i;
            const int q = plane_sphere_shortcut(EmulatedBound(a.f), pa.nx, pa.ny, pa.nz, pa.w, sa.cx, sa.cy, sa.cz, sa.r);
            (q < 0 ? emulated : shortcut) += 1;
        }
        // both paths were exercised (formats of few fraction bits rarely allow a shortcut)
        if (a.f.man_bits >= 10) {
            EXPECT_GT(shortcut, 5000) << name;
            EXPECT_GT(emulated, 1000) << name;
        }
    }
}

TEST(EmulationShortcuts, RayTriangleResultsEqualTheEmulation) {
    for (const char* name : kFormats) {
        const ArithSoft a{NumFormat::parse(name), true};
        Rng rng(8);
        int certain_miss = 0, certain_inside = 0, emulated = 0, hits = 0;
        for (int i = 0; i < 40000; ++i) {
            const double sc = scale(rng, a.f);
            const Vec3d p0 = Vec3d{uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1)} * sc;
            const Vec3d p1 = p0 + unit(rng) * (sc * uni(rng, 0.01, 1)), p2 = p0 + unit(rng) * (sc * uni(rng, 0.01, 1));
            const Vec3d e1 = p1 - p0, e2 = p2 - p0;
            const TriangleRec tr{to_f(p0), to_f(e1), to_f(e2), to_f(cross(e1, e2))};
            // a target near an edge or a vertex (barycentrics packed around 0 and 1), or anywhere
            const double es[] = {0, 1e-9, -1e-9, 1e-6, -1e-6, 1e-4, -1e-4, 1e-2, -1e-2, 0.3, -0.5};
            const double u = rng() % 3 ? es[rng() % 11] : uni(rng, -0.5, 1.5);
            const double v = rng() % 2 ? 1 - u + es[rng() % 11] : uni(rng, -0.5, 1.5);
            const Vec3d target = p0 + e1 * u + e2 * v;
            Vec3d dir = unit(rng);
            if (rng() % 5 == 0) dir = normalize(dir - normalize(cross(e1, e2)) * dot(dir, normalize(cross(e1, e2))) * (1 - 1e-5));  // grazing
            const Vec3f o = to_f(target - dir * (sc * uni(rng, 0.1, 4)));
            const Ray ray{o, to_f(target - to_d(o)), 0.0f, rng() % 4 ? 3.4e38f : float(uni(rng, 0.5, 1.5))};
            const RayA<ArithSoft> ra = load(a, ray);
            const TriA<ArithSoft> ta = load(a, tr);
            double t_want = -7, t_got = -7;
            const bool want = ray_hits_triangle_ops(a, ra, ta, t_want);
            const bool got = ray_hits_triangle(a, ra, ta, t_got);
            ASSERT_EQ(got, want) << name << " case " << i;
            ASSERT_EQ(t_got, t_want) << name << " case " << i;
            hits += want;
            const int q = ray_triangle_shortcut(EmulatedBound(a.f), ra, ta);
            (q == 0 ? certain_miss : q == 1 ? certain_inside : emulated) += 1;
        }
        if (a.f.man_bits >= 10) {
            EXPECT_GT(certain_miss, 2000) << name;
            EXPECT_GT(certain_inside, 50) << name;
            EXPECT_GT(emulated, 5000) << name;
            EXPECT_GT(hits, 1000) << name;
        }
    }
}

}  // namespace

namespace {

TEST(EmulationShortcuts, WatertightResultsEqualTheEmulation) {
    for (const char* base : kFormats) {
        const std::string name = std::string(base) + "-wt";
        const ArithSoft a{NumFormat::parse(name), true};
        Rng rng(9);
        int certain = 0, hits = 0;
        for (int i = 0; i < 30000; ++i) {
            const double sc = scale(rng, a.f);
            const Vec3d p0 = Vec3d{uni(rng, -1, 1), uni(rng, -1, 1), uni(rng, -1, 1)} * sc;
            const Vec3d p1 = p0 + unit(rng) * (sc * uni(rng, 0.01, 1)), p2 = p0 + unit(rng) * (sc * uni(rng, 0.01, 1));
            const Vec3d e1 = p1 - p0, e2 = p2 - p0;
            const TriangleRec tr{to_f(p0), to_f(e1), to_f(e2), to_f(cross(e1, e2)), to_f(p1), to_f(p2)};
            const double es[] = {0, 1e-9, -1e-9, 1e-6, -1e-6, 1e-4, -1e-4, 1e-2, -1e-2, 0.3, -0.5};
            const double u = rng() % 3 ? es[rng() % 11] : uni(rng, -0.5, 1.5);
            const double v = rng() % 2 ? 1 - u + es[rng() % 11] : uni(rng, -0.5, 1.5);
            const Vec3d target = p0 + e1 * u + e2 * v;
            const Vec3f o = to_f(target - unit(rng) * (sc * uni(rng, 0.1, 4)));
            const Ray ray{o, to_f(target - to_d(o)), 0.0f, 3.4e38f};
            const RayA<ArithSoft> ra = load(a, ray);
            const TriA<ArithSoft> ta = load(a, tr);
            double t_want = -7, t_got = -7;
            const bool want = ray_hits_triangle_watertight(a, ra, ta, t_want);
            ASSERT_EQ(ray_hits_triangle(a, ra, ta, t_got), want) << name << " case " << i;
            ASSERT_EQ(t_got, t_want) << name << " case " << i;
            hits += want;
            certain += watertight_certain_miss(EmulatedBound(a.f), ra, ta);
        }
        // the shortcut must carry most misses where the format's range holds
        // the cases (fp1-5-10 overflows on a third of them)
        if (a.f.man_bits >= 10 && a.f.exp_bits >= 6) {
            EXPECT_GT(certain, 3000) << name;
            EXPECT_GT(hits, 1000) << name;
        }
    }
}

}  // namespace
