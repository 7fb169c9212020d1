// Seeded property tests of the front end: culling through spheres and
// ray-planes never changes a nearest hit, bounding spheres really bound, and
// every ray lies in its row and column planes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/raygroups.hpp"
#include "raplas/frontend/spheres.hpp"
#include "raplas/frontend/tracer.hpp"
#include "raplas/scene/mesh.hpp"
#include "raplas/scene/scene.hpp"
#include "shared_scenes.hpp"

namespace {

using namespace raplas;

using Rng = std::mt19937_64;

double uni(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
int irand(Rng& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
Vec3d rvec(Rng& rng, double lo, double hi) { return {uni(rng, lo, hi), uni(rng, lo, hi), uni(rng, lo, hi)}; }

// A soup of `count` triangles around `center` within `size`: mostly small,
// some large, some slivers, some degenerate (zero area), some sharing
// vertices with earlier triangles.
Mesh random_soup(Rng& rng, int count, Vec3d center, double size) {
    Mesh m;
    m.source = "<random>";
    m.materials.push_back(Material{});
    for (int i = 0; i < count; ++i) {
        const int kind = irand(rng, 0, 9);
        Vec3d a = center + rvec(rng, -size, size);
        double s = kind < 6 ? size * 0.1 : (kind < 8 ? size * 0.8 : size * 0.3);
        Vec3d b = a + rvec(rng, -s, s), c = a + rvec(rng, -s, s);
        if (kind == 8) c = a + (b - a) * uni(rng, 0, 1);           // degenerate: collinear
        if (kind == 9) c = a + (b - a) * 0.5 + rvec(rng, -1e-4 * s, 1e-4 * s);  // sliver
        auto base = static_cast<std::uint32_t>(m.vertices.size());
        if (kind == 7 && base >= 3) {
            // share an edge with an earlier triangle
            const auto& t = m.triangles[static_cast<std::size_t>(irand(rng, 0, int(m.triangles.size()) - 1))];
            m.vertices.push_back(to_f(to_d(m.vertices[t[0]]) + rvec(rng, -s, s)));
            m.triangles.push_back({t[1], t[0], base});
        } else {
            m.vertices.push_back(to_f(a));
            m.vertices.push_back(to_f(b));
            m.vertices.push_back(to_f(c));
            m.triangles.push_back({base, base + 1, base + 2});
        }
        m.triangle_material.push_back(0);
    }
    return m;
}

Scene random_scene(Rng& rng, Mesh mesh) {
    Scene s;
    s.name = "random";
    s.mesh = std::move(mesh);
    Aabb b = s.mesh.bounds();
    const Vec3d c = b.center();
    const double r = std::max(length(b.extent()) * 0.5, 1e-6);
    // camera: outside or (sometimes) inside the geometry, looking near the centre
    const double dist = irand(rng, 0, 4) == 0 ? uni(rng, 0.1, 0.8) * r : uni(rng, 1.5, 4.0) * r;
    s.camera.eye = c + normalize(rvec(rng, -1, 1)) * dist;
    s.camera.look_at = c + rvec(rng, -0.3 * r, 0.3 * r);
    s.camera.up = normalize(Vec3d{uni(rng, -0.2, 0.2), 1, uni(rng, -0.2, 0.2)});
    s.camera.fov_deg = uni(rng, 20, 90);
    // light: a random rectangle somewhere around the geometry
    s.light.corner = c + rvec(rng, -2 * r, 2 * r);
    s.light.edge_u = rvec(rng, -0.5 * r, 0.5 * r);
    s.light.edge_v = rvec(rng, -0.5 * r, 0.5 * r);
    s.width = irand(rng, 5, 23);
    s.height = irand(rng, 5, 19);
    s.group_size = irand(rng, 1, 9);
    s.shadow_group_size = irand(rng, 1, 6);
    s.tris_per_sphere = irand(rng, 1, 5);
    s.sphere_method = irand(rng, 0, 1) ? "median-split" : "file-order";
    return s;
}

struct Checked {
    std::uint64_t rays = 0, hits = 0;
};

// Every valid ray of the group: the culled nearest hit equals brute force.
void expect_group_matches_brute_force(const Tracer& tracer, const RayGroup& g, Checked& c, const std::string& what) {
    GroupResult res;
    tracer.trace(g, res, false, false);
    ASSERT_EQ(res.hits.size(), std::size_t(g.n) * g.n);
    for (std::uint32_t v = 0; v < g.n; ++v) {
        for (std::uint32_t h = 0; h < g.n; ++h) {
            const Hit& got = res.hits[std::size_t(v) * g.n + h];
            if (!g.ray_valid(h, v)) {
                EXPECT_EQ(got.tri, -1) << what << ": invalid ray (" << h << "," << v << ") has a hit";
                continue;
            }
            const Hit want = tracer.brute_force(group_ray(g, h, v));
            ++c.rays;
            c.hits += want.tri >= 0;
            ASSERT_EQ(got.tri, want.tri) << what << " ray (" << h << "," << v << ") of group at " << g.px << ","
                                         << g.py << " n=" << g.n << ": culling lost or changed the nearest hit";
            if (want.tri >= 0) { ASSERT_EQ(got.t, want.t) << what << " ray (" << h << "," << v << ")"; }
        }
    }
}

class CullingIsConservative : public ::testing::TestWithParam<const char*> {};

TEST_P(CullingIsConservative, RandomSoupsAndScenes) {
    const NumFormat fmt = NumFormat::parse(GetParam());
    const bool soft = fmt.kind == NumFormat::Kind::custom;
    Rng rng(20240601);
    Checked total;
    const int scenes = 12;
    for (int si = 0; si < scenes; ++si) {
        // size and position vary over orders of magnitude, including far from the origin
        const double size = std::pow(10.0, irand(rng, -2, 3));
        const Vec3d center = irand(rng, 0, 2) == 0 ? rvec(rng, -1, 1) * (size * 200) : rvec(rng, -size, size);
        Mesh mesh = random_soup(rng, irand(rng, 20, soft ? 60 : 120), center, size);
        Scene s = random_scene(rng, std::move(mesh));
        const std::string what = "scene " + std::to_string(si) + " (" + fmt.name() + ", N=" +
                                 std::to_string(s.group_size) + ", " + std::to_string(s.width) + "x" +
                                 std::to_string(s.height) + ", " + s.sphere_method + ")";
        const double margin = conservative_margin(fmt.unit_roundoff(), scene_extent(s));
        const SphereSet spheres = build_spheres(s.mesh, s.tris_per_sphere, s.sphere_method, margin);
        const Tracer tracer(spheres, fmt);
        for (const RayGroup& g : primary_groups(s)) {
            expect_group_matches_brute_force(tracer, g, total, what + " primary");
            if (HasFatalFailure()) return;
        }
        // shadow groups from points on (and just off) random triangles
        for (int k = 0; k < 6; ++k) {
            const std::size_t t = static_cast<std::size_t>(irand(rng, 0, int(s.mesh.triangle_count()) - 1));
            double a = uni(rng, 0, 1), b = uni(rng, 0, 1 - a);
            Vec3d p = to_d(s.mesh.corner(t, 0)) * (1 - a - b) + to_d(s.mesh.corner(t, 1)) * a +
                      to_d(s.mesh.corner(t, 2)) * b;
            if (k % 2) p = p + rvec(rng, -1e-3, 1e-3) * size;
            RayGroup g = shadow_group(s, to_f(p), 0, 0);
            expect_group_matches_brute_force(tracer, g, total, what + " shadow");
            if (HasFatalFailure()) return;
        }
    }
    EXPECT_GT(total.rays, 2000u);
    EXPECT_GT(total.hits, 200u);              // the soups are actually hit ...
    EXPECT_LT(total.hits, total.rays);        // ... and missed
}

TEST_P(CullingIsConservative, WholeFramesOfTheBuiltinSceneWithRandomCameraAndLight) {
    // Through render_frame: primary groups and the shadow groups it issues
    // from real hit points (origins offset just off the surfaces).
    const NumFormat fmt = NumFormat::parse(GetParam());
    Rng rng(77);
    for (int si = 0; si < 3; ++si) {
        Scene s = random_scene(rng, builtin_mesh(1));
        s.width = irand(rng, 9, 21);
        s.height = irand(rng, 7, 15);
        s.shadow_group_size = irand(rng, 2, 5);
        FrameOptions fo;
        fo.format = fmt;
        fo.threads = 2;
        fo.record = true;
        Frame f = render_frame(s, fo);
        Tracer tracer(f.spheres, fmt);
        std::size_t hits = 0;
        for (std::size_t px = 0; px < f.pixel_hit.size(); ++px) {
            const Hit want = tracer.brute_force(f.pixel_ray[px]);
            ASSERT_EQ(f.pixel_hit[px], want) << "scene " << si << " pixel " << px;
            hits += want.tri >= 0;
        }
        ASSERT_EQ(f.shadow.size(), hits);
        ASSERT_EQ(f.shadow_results.size(), hits);
        for (std::size_t i = 0; i < f.shadow.size(); ++i) {
            const RayGroup& g = f.shadow[i];
            for (std::uint32_t v = 0; v < g.n; ++v)
                for (std::uint32_t h = 0; h < g.n; ++h)
                    ASSERT_EQ(f.shadow_results[i].hits[v * g.n + h], tracer.brute_force(group_ray(g, h, v)))
                        << "scene " << si << " shadow group " << i << " ray " << h << "," << v;
        }
    }
}

TEST_P(CullingIsConservative, WideGroupsUpTo64Rays) {
    // N = 32 (widest 32-bit mask), 33 and 64 (the widest mask), with an
    // image that is a multiple of none of them.
    const NumFormat fmt = NumFormat::parse(GetParam());
    Rng rng(5);
    Scene s = random_scene(rng, random_soup(rng, fmt.kind == NumFormat::Kind::custom ? 30 : 60, {0, 0, 0}, 1.0));
    s.camera.eye = {0.3, 0.2, 4};
    s.camera.look_at = {0, 0, 0};
    s.camera.fov_deg = 30;
    s.width = 70;
    s.height = 66;
    const SphereSet spheres =
        build_spheres(s.mesh, 2, "median-split", conservative_margin(fmt.unit_roundoff(), scene_extent(s)));
    const Tracer tracer(spheres, fmt);
    for (int n : {32, 33, 64}) {
        s.group_size = n;
        const auto groups = primary_groups(s);
        const std::size_t tiles_x = std::size_t((70 + n - 1) / n), tiles_y = std::size_t((66 + n - 1) / n);
        ASSERT_EQ(groups.size(), tiles_x * tiles_y);
        const std::uint64_t full = n == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
        EXPECT_EQ(groups[0].row_valid, full);
        EXPECT_EQ(groups[0].col_valid, full);
        EXPECT_EQ(groups.back().row_valid, (std::uint64_t(1) << (66 - (tiles_y - 1) * std::size_t(n))) - 1);
        EXPECT_EQ(groups.back().col_valid, (std::uint64_t(1) << (70 - (tiles_x - 1) * std::size_t(n))) - 1);
        Checked c;
        for (const auto& g : groups) {
            expect_group_matches_brute_force(tracer, g, c, "N=" + std::to_string(n));
            if (HasFatalFailure()) return;
        }
        EXPECT_EQ(c.rays, 70u * 66u);
        EXPECT_GT(c.hits, 100u);
    }
}

TEST_P(CullingIsConservative, SpheresTangentToARayPlaneAtTheHitPoint) {
    // The knife-edge case: a ray's row (or column) plane is tangent to a
    // bounding sphere exactly where the ray meets a corner of the sphere's
    // triangle. Rounding decides both the plane test and the triangle test;
    // the sphere margin must make the plane test pass whenever the triangle
    // test can hit. One obtuse triangle per ray, its longest edge a diameter
    // of its (minimal) bounding sphere, perpendicular to the plane.
    const NumFormat fmt = NumFormat::parse(GetParam());
    Rng rng(31337);
    std::uint64_t hits = 0, rays = 0;
    for (int si = 0; si < 4; ++si) {
        Scene s;
        s.mesh.materials.push_back(Material{});
        const double scale = std::pow(10.0, irand(rng, -1, 2));
        const Vec3d offset = si % 2 ? rvec(rng, -50, 50) * scale : Vec3d{};
        s.camera = {offset + rvec(rng, -1, 1) * scale, offset + rvec(rng, -0.2, 0.2) * scale + Vec3d{0, 0, -4 * scale},
                    {0, 1, 0}, uni(rng, 30, 60)};
        s.light.corner = offset + Vec3d{-1, 5, -1} * scale;
        s.light.edge_u = Vec3d{2, 0, 0} * scale;
        s.light.edge_v = Vec3d{0, 0, 2} * scale;
        s.width = 21;
        s.height = 17;
        s.group_size = 8;
        s.tris_per_sphere = 1;
        const auto groups = primary_groups(s);
        const double pixel = 2 * std::tan(s.camera.fov_deg * M_PI / 360) / s.height;
        for (const RayGroup& g : groups) {
            for (std::uint32_t v = 0; v < g.n; ++v)
                for (std::uint32_t h = 0; h < g.n; ++h) {
                    if (!g.ray_valid(h, v)) continue;
                    const Ray r = group_ray(g, h, v);
                    const double t = uni(rng, 1.5, 6.0);
                    const Vec3d d = to_d(r.d);
                    const Vec3d x = to_d(r.o) + d * t;
                    const Plane& pl = irand(rng, 0, 1) ? g.planes[v] : g.planes[g.n + h];
                    const Vec3d m = to_d(pl.n) * (irand(rng, 0, 1) ? 1.0 : -1.0);
                    const double rho = 0.02 * pixel * t * length(d);
                    const Vec3d w = normalize(cross(m, d)) * (irand(rng, 0, 1) ? 1.0 : -1.0);
                    auto base = static_cast<std::uint32_t>(s.mesh.vertices.size());
                    s.mesh.vertices.push_back(to_f(x));
                    s.mesh.vertices.push_back(to_f(x + m * (2 * rho)));
                    s.mesh.vertices.push_back(to_f(x + m * rho + w * (0.9 * rho)));
                    s.mesh.triangles.push_back({base, base + 1, base + 2});
                    s.mesh.triangle_material.push_back(0);
                }
        }
        const SphereSet spheres =
            build_spheres(s.mesh, 1, "median-split", conservative_margin(fmt.unit_roundoff(), scene_extent(s)));
        const Tracer tracer(spheres, fmt);
        Checked c;
        for (const RayGroup& g : groups) {
            expect_group_matches_brute_force(tracer, g, c, "tangent scene " + std::to_string(si));
            if (HasFatalFailure()) return;
        }
        rays += c.rays;
        hits += c.hits;
    }
    EXPECT_EQ(rays, 4u * 21u * 17u);
    EXPECT_GT(hits, rays / 10);  // the corners are really hit (rounding decides about a sixth of them)
}

INSTANTIATE_TEST_SUITE_P(Formats, CullingIsConservative, ::testing::Values("float32", "float64", "fp1-8-15"),
                         [](const ::testing::TestParamInfo<const char*>& i) {
                             std::string n = i.param;
                             std::replace(n.begin(), n.end(), '-', '_');
                             return n;
                         });

// ---- bounding spheres -------------------------------------------------------

void expect_valid_sphere_set(const Mesh& m, const SphereSet& s, int k, double margin, const std::string& what) {
    const std::size_t nt = m.triangle_count();
    ASSERT_EQ(s.triangle_count(), nt) << what;
    ASSERT_EQ(s.tri_mesh_index.size(), nt) << what;
    ASSERT_EQ(s.tri_sphere.size(), nt) << what;
    ASSERT_EQ(s.first_tri.size(), s.sphere_count()) << what;
    ASSERT_EQ(s.tri_count.size(), s.sphere_count()) << what;
    // contiguous tiling of Triangle Memory, at most K per sphere
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < s.sphere_count(); ++i) {
        ASSERT_EQ(s.first_tri[i], next) << what << " sphere " << i;
        ASSERT_GE(s.tri_count[i], 1u) << what;
        ASSERT_LE(s.tri_count[i], std::uint32_t(k)) << what;
        for (std::uint32_t t = s.first_tri[i]; t < s.first_tri[i] + s.tri_count[i]; ++t)
            ASSERT_EQ(s.tri_sphere[t], i) << what << " triangle " << t;
        next += s.tri_count[i];
    }
    ASSERT_EQ(next, nt) << what;
    // every mesh triangle exactly once, with its own record
    std::vector<int> seen(nt, 0);
    for (std::size_t t = 0; t < nt; ++t) {
        const auto mi = s.tri_mesh_index[t];
        ASSERT_GE(mi, 0);
        ASSERT_LT(std::size_t(mi), nt);
        ++seen[std::size_t(mi)];
        const TriangleRec want = make_triangle_record(m, std::size_t(mi));
        ASSERT_TRUE(s.triangles[t].v0 == want.v0 && s.triangles[t].e1 == want.e1 && s.triangles[t].e2 == want.e2 &&
                    s.triangles[t].n == want.n)
            << what << " record " << t;
    }
    for (std::size_t i = 0; i < nt; ++i) ASSERT_EQ(seen[i], 1) << what << " mesh triangle " << i;
    // every vertex inside its sphere, by at least the margin
    for (std::size_t t = 0; t < nt; ++t) {
        const Sphere& sp = s.spheres[s.tri_sphere[t]];
        const std::size_t mi = std::size_t(s.tri_mesh_index[t]);
        for (int c = 0; c < 3; ++c) {
            const double d = length(to_d(m.corner(mi, c)) - to_d(sp.c));
            ASSERT_LE(d + margin, double(sp.r)) << what << " triangle " << mi << " corner " << c;
        }
    }
}

TEST(BoundingSpheres, EnclosePerSphereContiguousTriangles) {
    Rng rng(11);
    for (int it = 0; it < 24; ++it) {
        const double size = std::pow(10.0, irand(rng, -3, 3));
        Mesh m = random_soup(rng, irand(rng, 1, 150), rvec(rng, -size, size) * 10.0, size);
        const int k = irand(rng, 1, 7);
        const double u = NumFormat::parse("fp1-8-15").unit_roundoff();
        const double margin = it % 3 == 0 ? 0.0 : conservative_margin(u, size);
        for (const char* method : {"median-split", "file-order"}) {
            SphereSet s = build_spheres(m, k, method, margin);
            expect_valid_sphere_set(m, s, k, margin,
                                    std::string(method) + " it=" + std::to_string(it) + " K=" + std::to_string(k));
            if (HasFatalFailure()) return;
        }
    }
}

// Spheres built on several threads are the same bytes as on one.
TEST(BoundingSpheres, SameOnAnyNumberOfThreads) {
    Rng rng(17);
    for (int it = 0; it < 6; ++it) {
        Mesh m = random_soup(rng, irand(rng, 1, 400), {0, 0, 0}, 1.0);
        const int k = irand(rng, 1, 4);
        for (const char* method : {"median-split", "file-order"}) {
            const SphereSet a = build_spheres(m, k, method, 1e-6, 1), b = build_spheres(m, k, method, 1e-6, 3);
            const std::string what = std::string(method) + " it=" + std::to_string(it);
            ASSERT_EQ(a.sphere_count(), b.sphere_count()) << what;
            ASSERT_EQ(a.triangle_count(), b.triangle_count()) << what;
            EXPECT_EQ(std::memcmp(a.spheres.data(), b.spheres.data(), a.spheres.size() * sizeof(Sphere)), 0) << what;
            EXPECT_EQ(std::memcmp(a.triangles.data(), b.triangles.data(), a.triangles.size() * sizeof(TriangleRec)), 0)
                << what;
            EXPECT_EQ(a.first_tri, b.first_tri) << what;
            EXPECT_EQ(a.tri_count, b.tri_count) << what;
            EXPECT_EQ(a.tri_mesh_index, b.tri_mesh_index) << what;
            EXPECT_EQ(a.tri_sphere, b.tri_sphere) << what;
        }
    }
}

TEST(BoundingSpheres, FileOrderKeepsMeshOrderAndMedianSplitFillsLeaves) {
    Rng rng(3);
    Mesh m = random_soup(rng, 37, {0, 0, 0}, 1.0);
    SphereSet fo = build_spheres(m, 4, "file-order", 0.0);
    ASSERT_EQ(fo.sphere_count(), 10u);  // ceil(37 / 4)
    for (std::size_t t = 0; t < fo.triangle_count(); ++t) EXPECT_EQ(fo.tri_mesh_index[t], std::int32_t(t));
    SphereSet ms = build_spheres(m, 4, "median-split", 0.0);
    EXPECT_EQ(ms.sphere_count(), 10u);  // leaves stay full: only one can be short
    std::size_t short_leaves = 0;
    for (auto c : ms.tri_count) short_leaves += c < 4;
    EXPECT_LE(short_leaves, 1u);
    // within a sphere, mesh order is kept
    for (std::size_t i = 0; i < ms.sphere_count(); ++i)
        for (std::uint32_t t = ms.first_tri[i] + 1; t < ms.first_tri[i] + ms.tri_count[i]; ++t)
            EXPECT_LT(ms.tri_mesh_index[t - 1], ms.tri_mesh_index[t]);
}

TEST(BoundingSpheres, SingleTriangleSphereIsTight) {
    // Acute triangle: the smallest sphere is the circumsphere; obtuse: the
    // sphere on the longest edge.
    Mesh m;
    m.materials.push_back(Material{});
    m.vertices = {{0, 0, 0}, {2, 0, 0}, {1, 1.5f, 0}, {10, 0, 0}, {14, 0, 0}, {12, 0.5f, 0}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    m.triangle_material = {0, 0};
    SphereSet s = build_spheres(m, 1, "median-split", 0.0);
    ASSERT_EQ(s.sphere_count(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        const Sphere& sp = s.spheres[i];
        if (s.tri_mesh_index[s.first_tri[i]] == 0) {
            // circumradius of (0,0),(2,0),(1,1.5): centre (1, 5/12), r = 13/12
            EXPECT_NEAR(sp.r, 13.0 / 12.0, 1e-5);
        } else {
            EXPECT_NEAR(sp.r, 2.0, 1e-5);  // half of the longest edge
            EXPECT_NEAR(sp.c.x, 12.0, 1e-5);
        }
    }
}

TEST(BoundingSpheres, MedianSplitBeatsFileOrderOnTheBunny) {
    const std::string path = raplas_test::shared_scene("bunny/bun_zipper.obj");
    RAPLAS_NEED_SHARED(path);
    const Mesh m = load_obj(path);
    ASSERT_GT(m.triangle_count(), 60000u);
    const Aabb box = m.bounds();
    const double margin =
        conservative_margin(NumFormat::float32().unit_roundoff(), std::max(max_abs(box.lo), max_abs(box.hi)));
    for (int k : {2, 4}) {
        const SphereSet ms = build_spheres(m, k, "median-split", margin);
        const SphereSet fo = build_spheres(m, k, "file-order", margin);
        const SphereQuality qm = sphere_quality(ms), qf = sphere_quality(fo);
        EXPECT_LT(qm.sum_radius, qf.sum_radius) << "K=" << k;
        EXPECT_LT(qm.sum_volume, qf.sum_volume) << "K=" << k;
        EXPECT_EQ(ms.sphere_count(), fo.sphere_count()) << "K=" << k;  // same count, smaller spheres
        EXPECT_NEAR(qm.mean_tris_per_sphere, double(m.triangle_count()) / double(ms.sphere_count()), 1e-9);
        if (k == 2) {
            expect_valid_sphere_set(m, ms, k, margin, "bunny median-split");
            expect_valid_sphere_set(m, fo, k, margin, "bunny file-order");
        }
    }
}

// ---- ray-planes ----------------------------------------------------------------

// Signed distance of point p from plane pl, in double.
double plane_dist(const Plane& pl, const Vec3d& p) { return dot(to_d(pl.n), p) + pl.w; }

void expect_rays_in_their_planes(const RayGroup& g, const std::string& what) {
    ASSERT_EQ(g.planes.size(), std::size_t(2) * g.n) << what;
    for (const Plane& p : g.planes) ASSERT_NEAR(length(to_d(p.n)), 1.0, 1e-6) << what;
    for (std::uint32_t v = 0; v < g.n; ++v) {
        for (std::uint32_t h = 0; h < g.n; ++h) {
            const Ray r = group_ray(g, h, v);
            const Vec3d o = to_d(r.o), e = to_d(r.o) + to_d(r.d);
            const double scale = std::max({max_abs(o), max_abs(e), 1e-30});
            const double tol = 4e-6 * scale;
            const Plane& row = g.planes[v];
            const Plane& col = g.planes[g.n + h];
            ASSERT_LE(std::fabs(plane_dist(row, o)), tol) << what << " origin vs row plane " << v;
            ASSERT_LE(std::fabs(plane_dist(row, e)), tol) << what << " ray (" << h << "," << v << ") vs row plane";
            ASSERT_LE(std::fabs(plane_dist(col, o)), tol) << what << " origin vs column plane " << h;
            ASSERT_LE(std::fabs(plane_dist(col, e)), tol) << what << " ray (" << h << "," << v << ") vs column plane";
            // and not in the neighbouring planes (the test can tell planes apart)
            if (v + 1 < g.n) { ASSERT_GT(std::fabs(plane_dist(g.planes[v + 1], e)), tol) << what; }
            if (h + 1 < g.n) { ASSERT_GT(std::fabs(plane_dist(g.planes[g.n + h + 1], e)), tol) << what; }
        }
    }
}

TEST(RayPlanes, EveryRayLiesInItsRowAndColumnPlane) {
    Rng rng(42);
    for (int it = 0; it < 20; ++it) {
        const double size = std::pow(10.0, irand(rng, -2, 2));
        Scene s = random_scene(rng, random_soup(rng, 10, rvec(rng, -size, size), size));
        s.group_size = irand(rng, 1, 17);
        s.shadow_group_size = irand(rng, 1, 9);
        const std::string what = "scene " + std::to_string(it);
        const auto groups = primary_groups(s);
        // tiles cover the image exactly once
        std::vector<int> cover(std::size_t(s.width) * std::size_t(s.height), 0);
        for (const auto& g : groups) {
            EXPECT_EQ(g.kind, GroupKind::primary);
            EXPECT_EQ(g.n, std::uint32_t(s.group_size));
            for (std::uint32_t v = 0; v < g.n; ++v)
                for (std::uint32_t h = 0; h < g.n; ++h) {
                    const int x = g.px + int(h), y = g.py + int(v);
                    const bool inside = x < s.width && y < s.height;
                    EXPECT_EQ(g.ray_valid(h, v), inside) << what;
                    if (inside) ++cover[std::size_t(y) * std::size_t(s.width) + std::size_t(x)];
                }
            expect_rays_in_their_planes(g, what + " primary");
            if (HasFatalFailure()) return;
        }
        for (int c : cover) ASSERT_EQ(c, 1) << what;
        // shadow group: rays end on the light's grid cell centres
        const Vec3f origin = to_f(s.light.center() + s.light.normal() * uni(rng, 0.5, 3.0) * size);
        RayGroup g = shadow_group(s, origin, 3, 4);
        expect_rays_in_their_planes(g, what + " shadow");
        const std::uint32_t n = g.n;
        for (std::uint32_t v = 0; v < n; ++v)
            for (std::uint32_t h = 0; h < n; ++h) {
                ASSERT_TRUE(g.ray_valid(h, v));
                const Ray r = group_ray(g, h, v);
                const Vec3d end = to_d(r.o) + to_d(r.d);
                const Vec3d want = s.light.corner + s.light.edge_u * ((h + 0.5) / n) + s.light.edge_v * ((v + 0.5) / n);
                EXPECT_LE(length(end - want), 1e-5 * std::max(1.0, max_abs(want))) << what;
                EXPECT_LT(r.tmax, 1.0f);
            }
    }
}

TEST(RayPlanes, PrimaryRaysGoThroughPixelCentres) {
    Scene s;
    s.mesh = builtin_mesh(0);
    s.camera = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 90};
    s.width = 4;
    s.height = 2;
    s.group_size = 3;
    auto groups = primary_groups(s);
    ASSERT_EQ(groups.size(), 2u);  // a 3x3 tile and a 3x3 tile with one valid column
    EXPECT_EQ(groups[1].px, 3);
    EXPECT_EQ(groups[1].col_valid, 0x1u);
    EXPECT_EQ(groups[1].row_valid, 0x3u);
    // fov 90, aspect 2: screen at distance 1 spans x in [-2, 2], y in [-1, 1]
    const Ray r = group_ray(groups[0], 0, 0);  // pixel (0, 0): top left
    const Vec3d d = normalize(to_d(r.d));
    const Vec3d want = normalize(Vec3d{-1.5, 0.5, -1});
    EXPECT_NEAR(d.x, want.x, 1e-6);
    EXPECT_NEAR(d.y, want.y, 1e-6);
    EXPECT_NEAR(d.z, want.z, 1e-6);
    const Ray r2 = group_ray(groups[1], 0, 1);  // pixel (3, 1): bottom right
    const Vec3d d2 = normalize(to_d(r2.d));
    const Vec3d want2 = normalize(Vec3d{1.5, -0.5, -1});
    EXPECT_NEAR(d2.x, want2.x, 1e-6);
    EXPECT_NEAR(d2.y, want2.y, 1e-6);
    EXPECT_NEAR(d2.z, want2.z, 1e-6);
}

}  // namespace
