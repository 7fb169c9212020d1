// Sphere culling (core/cull.hpp) gives exactly the plane-hit records of the
// full test: seeded random sphere sets and plane pencils in every format,
// planes tangent to a sphere within a few ulps, and every group of every
// shared scene through the front end.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "raplas/core/cull.hpp"
#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/raygroups.hpp"
#include "raplas/frontend/tracer.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/params.hpp"
#include "shared_scenes.hpp"

namespace {

using namespace raplas;
using Rng = std::mt19937_64;

double uni(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
Vec3d rvec(Rng& rng, double lo, double hi) { return {uni(rng, lo, hi), uni(rng, lo, hi), uni(rng, lo, hi)}; }

bool same(const std::vector<SphereHitRec>& a, const std::vector<SphereHitRec>& b, std::string& why) {
    if (a.size() != b.size()) {
        why = "record counts " + std::to_string(a.size()) + " vs " + std::to_string(b.size());
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].sphere != b[i].sphere || a[i].rows != b[i].rows || a[i].cols != b[i].cols) {
            why = "record " + std::to_string(i) + ": sphere " + std::to_string(a[i].sphere) + " vs " +
                  std::to_string(b[i].sphere);
            return false;
        }
    return true;
}

// A pencil of n row planes and n column planes through `eye`, as a camera's
// ray-planes: row planes contain the eye's x axis, column planes its y axis.
std::vector<Plane> pencil(Rng& rng, Vec3d eye, std::uint32_t n, double spread) {
    const Vec3d fwd = normalize(rvec(rng, -1, 1)), side = normalize(cross(fwd, Vec3d{0.1, 1, 0.2}));
    const Vec3d up = cross(side, fwd);
    std::vector<Plane> planes(2 * n);
    const double a0 = uni(rng, -spread, spread), a1 = uni(rng, -spread, spread);
    for (std::uint32_t i = 0; i < 2 * n; ++i) {
        const double ang = (i < n ? a0 : a1) + spread * (double(i % n) / n - 0.5);
        // row plane normal turns around `side`, column plane normal around `up`
        const Vec3d nrm = i < n ? normalize(up * std::cos(ang) - fwd * std::sin(ang))
                                : normalize(side * std::cos(ang) - fwd * std::sin(ang));
        planes[i].n = to_f(nrm);
        planes[i].w = float(-dot(to_d(planes[i].n), eye));
    }
    return planes;
}

template <class A>
struct Checker {
    A a;
    std::uint64_t groups = 0, records = 0, culled_groups = 0, pairless = 0;

    void run(const std::vector<Sphere>& spheres, const std::vector<Plane>& planes, std::uint32_t n,
             std::uint64_t row_valid, std::uint64_t col_valid, const std::string& what) {
        SphereSoA<A> soa;
        for (const auto& s : spheres) soa.push_back(load(a, s));
        std::vector<PlaneA<A>> pa;
        for (const auto& p : planes) pa.push_back(load(a, p));
        const SphereTree tree(spheres);
        std::vector<SphereHitRec> full, culled;
        group_sphere_hits(a, pa.data(), n, row_valid, col_valid, soa, full);
        group_sphere_hits_culled(a, planes.data(), pa.data(), n, row_valid, col_valid, soa, tree, culled);
        std::string why;
        EXPECT_TRUE(same(full, culled, why)) << what << ": " << why;
        // With the pair-less spheres (icc.triangle_select = any): the same hit
        // records, and the same runs as a sphere-by-sphere scalar evaluation.
        std::vector<SphereHitRec> full_any, culled_any;
        std::vector<SphereRun> full_runs, culled_runs, scalar_runs;
        group_sphere_hits(a, pa.data(), n, row_valid, col_valid, soa, full_any, &full_runs);
        group_sphere_hits_culled(a, planes.data(), pa.data(), n, row_valid, col_valid, soa, tree, culled_any,
                                 &culled_runs);
        for (std::uint32_t i = 0; i < soa.size(); ++i) {
            const SphereA<A> sp{soa.cx[i], soa.cy[i], soa.cz[i], soa.r[i]};
            std::uint64_t rm = 0, cm = 0;
            for (std::uint32_t v = 0; v < n; ++v) rm |= std::uint64_t(plane_hits_sphere(a, pa[v], sp)) << v;
            for (std::uint32_t h = 0; h < n; ++h) cm |= std::uint64_t(plane_hits_sphere(a, pa[n + h], sp)) << h;
            rm &= row_valid;
            cm &= col_valid;
            if ((rm || cm) && !(rm && cm)) add_to_runs(scalar_runs, i);
        }
        EXPECT_TRUE(same(full, full_any, why)) << what << " (with pair-less spheres): " << why;
        EXPECT_TRUE(same(full, culled_any, why)) << what << " (culled, with pair-less spheres): " << why;
        EXPECT_EQ(full_runs, scalar_runs) << what << ": pair-less runs of the batched test";
        EXPECT_EQ(culled_runs, scalar_runs) << what << ": pair-less runs of the culled test";
        pairless += full_runs.size();
        ++groups;
        records += full.size();
        culled_groups += culling_applies(a, tree, planes.data(), 2 * n);
    }
};

template <class A>
void random_sets(Checker<A>& c, const std::string& fmt) {
    Rng rng(424242);
    for (int si = 0; si < 40; ++si) {
        // clusters of spheres at scales from 1e-6 to 1e7, near or far from the origin
        const double scale = std::pow(10.0, uni(rng, -6, 7));
        const Vec3d centre = (si % 3 == 0) ? rvec(rng, -1, 1) * (scale * 1000) : rvec(rng, -scale, scale);
        std::vector<Sphere> spheres;
        const int count = 1 + int(uni(rng, 0, 300));
        Vec3d p = centre;
        for (int i = 0; i < count; ++i) {
            p = p + rvec(rng, -0.05, 0.05) * scale;  // a coherent walk, as median-split order is
            Sphere s;
            s.c = to_f(p);
            s.r = float(scale * std::pow(10.0, uni(rng, -3, -0.5)));
            spheres.push_back(s);
        }
        const std::uint32_t n = std::uint32_t(1 + uni(rng, 0, 64));
        const std::uint64_t all = n == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
        for (int g = 0; g < 6; ++g) {
            const Vec3d eye = g % 2 ? centre + rvec(rng, -2, 2) * scale : to_d(spheres[rng() % spheres.size()].c);
            const auto planes = pencil(rng, eye, n, uni(rng, 0.001, 1.2));
            const std::uint64_t rv = g == 5 ? all & rng() : all, cv = g == 4 ? all & rng() : all;
            c.run(spheres, planes, n, rv, cv, fmt + " set " + std::to_string(si) + " group " + std::to_string(g));
        }
    }
}

// Planes tangent to a sphere that is a leaf of its own (the ninth of nine:
// its node sphere is the sphere itself), moved by -4..+4 ulps of w: the
// closest a plane can come to the culling bound.
template <class A>
void tangent_planes(Checker<A>& c, const std::string& fmt) {
    Rng rng(99);
    for (int k = 0; k < 200; ++k) {
        const double scale = std::pow(10.0, uni(rng, -5, 6));
        std::vector<Sphere> spheres;
        for (int i = 0; i < 9; ++i) {
            Sphere s;
            s.c = to_f(rvec(rng, -1, 1) * scale + Vec3d{3, -2, 1} * (k % 2 ? scale * 100 : 0));
            s.r = float(scale * uni(rng, 0.01, 0.3));
            spheres.push_back(s);
        }
        const Sphere& t = spheres[8];
        std::vector<Plane> planes(2);
        for (auto& pl : planes) {
            pl.n = to_f(normalize(rvec(rng, -1, 1)));
            const double side = (rng() & 1) ? 1.0 : -1.0;
            float w = float(-dot(to_d(pl.n), to_d(t.c)) + side * double(t.r));
            const int steps = int(rng() % 9) - 4;
            for (int s = 0; s < std::abs(steps); ++s) w = std::nextafter(w, steps > 0 ? HUGE_VALF : -HUGE_VALF);
            pl.w = w;
        }
        // with a through-the-centre plane sometimes as the column plane
        if (k % 3 == 0) planes[1].w = float(-dot(to_d(planes[1].n), to_d(t.c)));
        c.run(spheres, planes, 1, 1, 1, fmt + " tangent " + std::to_string(k));
    }
}

template <class A>
void all_cases(A a, const std::string& fmt, bool expect_culling = true) {
    Checker<A> c{a};
    random_sets(c, fmt);
    tangent_planes(c, fmt);
    EXPECT_GT(c.records, 1000u) << fmt << ": the planes hit spheres";
    EXPECT_GT(c.pairless, 100u) << fmt << ": some spheres are cut by rows only or columns only";
    if (expect_culling) {
        EXPECT_GT(c.culled_groups, c.groups * 3 / 4) << fmt << ": the culling path was taken";
    }
}

TEST(SphereCulling, SameRecordsAsTheFullTestFloat32) { all_cases(ArithF32{}, "float32"); }
TEST(SphereCulling, SameRecordsAsTheFullTestFloat64) { all_cases(ArithF64{}, "float64"); }
TEST(SphereCulling, SameRecordsAsTheFullTestReducedFormats) {
    for (const char* f : {"fp1-8-15", "fp1-7-16-rtz", "fp1-6-17-ftz", "fp1-8-10-rtz-ftz"})
        all_cases(ArithSoft{NumFormat::parse(f), true}, f);
    // without post-normalisation in the adder (the paper's PSI)
    all_cases(ArithSoft{NumFormat::parse("fp1-8-15"), false}, "fp1-8-15 unnormalised");
    // a format whose range the scenes exceed: culling must step aside
    all_cases(ArithSoft{NumFormat::parse("fp1-5-10"), true}, "fp1-5-10", false);
}

TEST(SphereCulling, TreeNodesEncloseTheirSpheresInSphereOrder) {
    Rng rng(3);
    std::vector<Sphere> spheres(1000);
    for (auto& s : spheres) {
        s.c = to_f(rvec(rng, -10, 10));
        s.r = float(uni(rng, 0.01, 2));
    }
    const SphereTree tree(spheres);
    std::uint32_t next_leaf_start = 0;
    for (std::size_t i = 0; i < tree.nodes().size(); ++i) {
        const auto& nd = tree.nodes()[i];
        for (std::uint32_t k = nd.lo; k < tree.hi(nd); ++k) {
            const Vec3d c = to_d(spheres[k].c);
            const double r = spheres[k].r;
            EXPECT_LE(std::fabs(c.x - nd.cx) + r, nd.ex) << "node " << i << " sphere " << k;
            EXPECT_LE(std::fabs(c.y - nd.cy) + r, nd.ey) << "node " << i << " sphere " << k;
            EXPECT_LE(std::fabs(c.z - nd.cz) + r, nd.ez) << "node " << i << " sphere " << k;
            EXPECT_LE(length(c) + r, tree.bound()) << "sphere " << k;
        }
        if (nd.right == 0) {  // leaves in pre-order cover the spheres in order
            EXPECT_EQ(nd.lo, next_leaf_start);
            EXPECT_LE(tree.hi(nd) - nd.lo, SphereTree::kLeaf);
            next_leaf_start = tree.hi(nd);
        } else {
            EXPECT_EQ(tree.nodes()[i + 1].lo, nd.lo);
            EXPECT_EQ(tree.hi(tree.nodes()[nd.right]), tree.hi(nd));
            EXPECT_EQ(tree.hi(tree.nodes()[i + 1]), tree.nodes()[nd.right].lo);
        }
    }
    EXPECT_EQ(next_leaf_start, 1000u);
}


// The node test over a span of planes (vectorised where the machine allows)
// answers, plane by plane, what the scalar proof answers: random boxes near
// and far from random planes, every span start and length up to 64.
TEST(SphereCulling, NodeTestOverASpanEqualsThePlaneByPlaneProof) {
    Rng rng(77);
    cull_detail::PlanesD pd{};
    const ArithBounds bounds[] = {arith_bounds(ArithF32{}), arith_bounds(ArithF64{})};
    for (int round = 0; round < 200; ++round) {
        const double scale = std::pow(10.0, uni(rng, -3, 4));
        const ArithBounds& b = bounds[round % 2];
        SphereTree::Node nd{};
        const Vec3d c = rvec(rng, -scale, scale);
        nd.cx = float(c.x);
        nd.cy = float(c.y);
        nd.cz = float(c.z);
        nd.ex = float(scale * std::pow(10.0, uni(rng, -4, 0)));
        nd.ey = float(scale * std::pow(10.0, uni(rng, -4, 0)));
        nd.ez = float(scale * std::pow(10.0, uni(rng, -4, 0)));
        for (std::uint32_t p = 0; p < 128; ++p) {
            Plane pl;
            pl.n = to_f(normalize(rvec(rng, -1, 1)) * uni(rng, 0.5, 1.5));
            pl.w = float(uni(rng, -scale, scale));
            if (p % 2 == 0) {
                // every other plane within a few slacks of the bound, on either side
                cull_detail::set_plane(pd, p, pl, 2 * scale, b);
                const double dot_c = pd.nx[p] * nd.cx + pd.ny[p] * nd.cy + pd.nz[p] * nd.cz;
                const double ext = pd.ax[p] * nd.ex + pd.ay[p] * nd.ey + pd.az[p] * nd.ez;
                pl.w = float(-dot_c + (rng() % 2 ? 1 : -1) * (ext + pd.slack[p] * uni(rng, 0, 2)));
            }
            cull_detail::set_plane(pd, p, pl, 2 * scale, b);
        }
        const std::uint32_t first = std::uint32_t(rng() % 65), count = 1 + std::uint32_t(rng() % 64);
        const std::uint64_t m = cull_detail::planes_may_hit_node(pd, first, count, nd);
        for (std::uint32_t i = 0; i < 64; ++i) {
            const bool may = i < count && !cull_detail::plane_misses_node(pd, first + i, nd);
            ASSERT_EQ(bool((m >> i) & 1), may) << "round " << round << " plane " << first + i;
        }
    }
}

// The proof is sound: a plane it says misses a node misses each of the
// node's spheres in the format too, also for planes placed just past the
// bound (random boxes of random spheres, normals of length 0.5 to 1.5).
TEST(SphereCulling, PlanesProvenToMissANodeMissItsSpheres) {
    Rng rng(91);
    std::uint64_t proven = 0;
    for (int round = 0; round < 400; ++round) {
        const double scale = std::pow(10.0, uni(rng, -2, 3));
        std::vector<Sphere> spheres(SphereTree::kLeaf);
        const Vec3d centre = rvec(rng, -scale, scale), extent = rvec(rng, 0, scale * 0.1);
        for (auto& s : spheres) {
            s.c = to_f(centre + Vec3d{uni(rng, -1, 1) * extent.x, uni(rng, -1, 1) * extent.y, uni(rng, -1, 1) * extent.z});
            s.r = float(scale * std::pow(10.0, uni(rng, -5, -2)));
        }
        const SphereTree tree(spheres);
        const SphereTree::Node& nd = tree.nodes().front();
        const ArithF32 a{};
        cull_detail::PlanesD pd{};
        for (int k = 0; k < 64; ++k) {
            Plane pl;
            pl.n = to_f(normalize(rvec(rng, -1, 1)) * uni(rng, 0.5, 1.5));
            // at the node's bound along the normal, give or take a little
            cull_detail::set_plane(pd, 0, Plane{pl.n, 0.f}, tree.bound(), arith_bounds(a));
            const double dot_c = pd.nx[0] * nd.cx + pd.ny[0] * nd.cy + pd.nz[0] * nd.cz;
            const double ext = pd.ax[0] * nd.ex + pd.ay[0] * nd.ey + pd.az[0] * nd.ez;
            pl.w = float(-dot_c + (rng() % 2 ? 1 : -1) * ext * (1 + uni(rng, -1e-3, 1e-3)));
            cull_detail::set_plane(pd, 0, pl, tree.bound(), arith_bounds(a));
            if (!cull_detail::plane_misses_node(pd, 0, nd)) continue;
            ++proven;
            const PlaneA<ArithF32> pa = load(a, pl);
            for (const Sphere& s : spheres)
                ASSERT_FALSE(plane_hits_sphere(a, pa, load(a, s))) << "round " << round << " plane " << k;
        }
    }
    EXPECT_GT(proven, 1000u);  // the proof does prove misses near the bound
}
// Groups of every shipped scene file (at 32 x 32 pixels, the scene's group
// sizes): the culled front end's records and hits equal the full test's. A
// scene whose mesh (a shared scene) is missing is skipped, or fails under CI=true.
class SphereCulling : public ::testing::TestWithParam<const char*> {};

TEST_P(SphereCulling, SameRecordsAndHitsAsTheFullTest) {
    namespace fs = std::filesystem;
    const std::string name = GetParam();
    ParamSet p = scene_params();
    p.load_file((fs::path(RAPLAS_SOURCE_DIR) / "scenes" / (name + ".toml")).string());
    RAPLAS_NEED_SHARED(raplas_test::shared_scene(p.get_string("mesh")));
    p.set("image.width=32");
    p.set("image.height=32");
    const Scene s = scene_from_params(p, "");
    {
        for (const char* fmt : {"float32", "fp1-8-15"}) {
            if (std::string(fmt) != "float32" && s.mesh.triangle_count() > 5000) continue;  // time
            const auto t0 = std::chrono::steady_clock::now();
            FrameOptions fo;
            fo.format = NumFormat::parse(fmt);
            fo.record = true;
            fo.pairless = true;
            fo.threads = 2;
            const Frame f = render_frame(s, fo);
            const Tracer full(f.spheres, fo.format, false);
            std::size_t groups = 0, records = 0;
            auto check = [&](const RayGroup& g, const GroupResult& got, const char* kind, std::size_t i) {
                GroupResult want;
                full.trace(g, want, true, false, true);
                std::string why;
                ASSERT_TRUE(same(want.sphere_list, got.sphere_list, why))
                    << name << " " << fmt << " " << kind << " group " << i << ": " << why;
                ASSERT_EQ(want.pairless, got.pairless) << name << " " << fmt << " " << kind << " group " << i;
                ASSERT_EQ(want.counts.pairless, got.counts.pairless);
                ASSERT_EQ(want.hits, got.hits) << name << " " << fmt << " " << kind << " group " << i;
                ASSERT_EQ(want.counts.rt_tests, got.counts.rt_tests);
                ++groups;
                records += want.sphere_list.size();
            };
            // every primary group and an even sample of the shadow groups (the
            // full test of every group of a frame is tools/check_culling.sh)
            for (std::size_t i = 0; i < f.primary.size(); ++i) check(f.primary[i], f.primary_results[i], "primary", i);
            const std::size_t step = f.shadow.size() / 24 + 1;
            for (std::size_t i = step / 2; i < f.shadow.size(); i += step)
                check(f.shadow[i], f.shadow_results[i], "shadow", i);
            EXPECT_GT(records, groups) << name << " " << fmt;
            std::printf("  %s %s: %zu groups, %zu records, %.1f s\n", name.c_str(), fmt, groups, records,
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
    }
}

INSTANTIATE_TEST_SUITE_P(ShippedScenes, SphereCulling,
                         ::testing::Values("bunny", "bunny_small", "conference", "sportscar", "cornell", "teapot"),
                         [](const ::testing::TestParamInfo<const char*>& info) { return std::string(info.param); });

}  // namespace
