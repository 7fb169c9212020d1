// The shipped animated scenes (scenes/conference_orbit.toml, bunny_turn.toml,
// wave.toml: the workloads of bench/bench_animation.cpp) load, have their
// frame counts, and move what they should between frame 0 and a middle
// frame; and refit_spheres(), which carries a sphere set to moved triangles,
// keeps every moved triangle inside its sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/spheres.hpp"
#include "raplas/scene/animation.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/bytes.hpp"
#include "shared_scenes.hpp"

namespace animated_scenes_test {

using raplas::Mesh;
using raplas::RigidMotion;
using raplas::Scene;
using raplas::SphereRefit;
using raplas::SphereSet;
using raplas::Vec3d;
using raplas::Vec3f;

Scene load_shipped(const std::string& name) {
    raplas::SceneRequest req;
    req.scene_file = std::string(RAPLAS_SOURCE_DIR) + "/scenes/" + name + ".toml";
    return raplas::load_scene(req);
}

// Spheres some corner of their triangles (in `mesh`) is outside of, with `margin` to spare.
std::size_t spheres_not_enclosing(const SphereSet& s, const Mesh& mesh, double margin) {
    std::size_t bad = 0;
    for (std::size_t j = 0; j < s.spheres.size(); ++j) {
        const Vec3d c = raplas::to_d(s.spheres[j].c);
        bool ok = true;
        for (std::size_t i = s.first_tri[j]; i < s.first_tri[j] + s.tri_count[j]; ++i)
            for (int k = 0; k < 3; ++k)
                ok = ok && raplas::length(raplas::to_d(mesh.corner(static_cast<std::size_t>(s.tri_mesh_index[i]), k)) - c) +
                                   margin <=
                               double(s.spheres[j].r);
        if (!ok) ++bad;
    }
    return bad;
}

// The mesh moved by one motion per triangle (-1: not moved), each corner
// rounded to float once, as the animation moves objects. Corners shared by
// triangles of different motions are copied.
Mesh moved_mesh(const Mesh& m, const std::vector<std::int32_t>& tri_motion, const std::vector<RigidMotion>& motions) {
    Mesh out = m;
    out.vertices.clear();
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (std::size_t k = 0; k < 3; ++k) {
            const std::int32_t mo = tri_motion.empty() ? -1 : tri_motion[t];
            const Vec3f p = m.vertices[m.triangles[t][k]];
            out.vertices.push_back(mo < 0 ? p : raplas::to_f(motions[static_cast<std::size_t>(mo)].apply(raplas::to_d(p))));
            out.triangles[t][k] = static_cast<std::uint32_t>(out.vertices.size() - 1);
        }
    return out;
}

RigidMotion rotation(const Vec3d& axis, double deg, const Vec3d& pivot, const Vec3d& translate, double scale) {
    RigidMotion m;
    m.pivot = pivot;
    m.translate = translate;
    m.scale = scale;
    const Vec3d u = raplas::normalize(axis);
    const double h = deg * M_PI / 360.0, s = std::sin(h);
    const double w = std::cos(h), x = u.x * s, y = u.y * s, z = u.z * s;
    m.rotates = true;
    m.r[0][0] = 1 - 2 * (y * y + z * z), m.r[0][1] = 2 * (x * y - w * z), m.r[0][2] = 2 * (x * z + w * y);
    m.r[1][0] = 2 * (x * y + w * z), m.r[1][1] = 1 - 2 * (x * x + z * z), m.r[1][2] = 2 * (y * z - w * x);
    m.r[2][0] = 2 * (x * z - w * y), m.r[2][1] = 2 * (y * z + w * x), m.r[2][2] = 1 - 2 * (x * x + y * y);
    return m;
}

double margin_of(const Mesh& m) {
    double e = 0;
    for (const auto& v : m.vertices) e = std::max(e, raplas::max_abs(raplas::to_d(v)));
    return raplas::conservative_margin(raplas::NumFormat::float32().unit_roundoff(), e);
}

// ---- the shipped animated scenes ------------------------------------------------

TEST(AnimatedScenes, ConferenceOrbitMovesOnlyTheCamera) {
    RAPLAS_NEED_SHARED(raplas_test::shared_scene("conference/conference.obj"));
    const Scene s = load_shipped("conference_orbit");
    ASSERT_TRUE(s.animation);
    EXPECT_EQ(raplas::frame_count(s), 48);
    EXPECT_EQ(s.mesh.triangle_count(), 331179u);
    const Scene a = raplas::scene_at_frame(s, 0), b = raplas::scene_at_frame(s, 24);
    // The still scene (what render, trace and simulate draw) is frame 0 to the rounding of the eye.
    EXPECT_LT(raplas::length(s.camera.eye - a.camera.eye), 0.01);
    EXPECT_TRUE(raplas::same_bits(s.camera.look_at, a.camera.look_at));
    // Half a turn: the eye is on the other side of the table, at the same height, looking at the same point.
    EXPECT_GT(raplas::length(a.camera.eye - b.camera.eye), 1000.0);
    EXPECT_DOUBLE_EQ(a.camera.eye.y, b.camera.eye.y);
    EXPECT_TRUE(raplas::same_bits(a.camera.look_at, b.camera.look_at));
    EXPECT_TRUE(raplas::same_bytes(a.mesh.vertices, b.mesh.vertices));
    EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
    EXPECT_TRUE(raplas::same_bits(a.light.corner, b.light.corner));
    // Every frame's eye stays inside the room and below its largest coordinate: the
    // scene's extent (and so the spheres' margin) is frame 0's in every frame.
    const raplas::Aabb room = s.mesh.bounds();
    for (int f = 0; f < raplas::frame_count(s); f += 6) {
        const Scene x = raplas::scene_at_frame(s, f);
        for (int k = 0; k < 3; ++k) {
            EXPECT_GT(x.camera.eye[static_cast<std::size_t>(k)], double(room.lo[static_cast<std::size_t>(k)])) << "frame " << f;
            EXPECT_LT(x.camera.eye[static_cast<std::size_t>(k)], double(room.hi[static_cast<std::size_t>(k)])) << "frame " << f;
        }
        EXPECT_EQ(raplas::scene_extent(x), raplas::scene_extent(a)) << "frame " << f;
    }
}

TEST(AnimatedScenes, BunnyTurnsOnItsFloorAndTheFloorStays) {
    RAPLAS_NEED_SHARED(raplas_test::shared_scene("bunny/bun_zipper.obj"));
    const Scene s = load_shipped("bunny_turn");
    ASSERT_TRUE(s.animation);
    EXPECT_EQ(raplas::frame_count(s), 48);
    const Scene a = raplas::scene_at_frame(s, 0), b = raplas::scene_at_frame(s, 24);
    ASSERT_EQ(a.mesh.triangles, b.mesh.triangles);  // same topology: only positions change
    ASSERT_EQ(a.mesh.triangle_object.size(), a.mesh.triangle_count());
    EXPECT_TRUE(raplas::same_bits(a.camera.eye, b.camera.eye));
    EXPECT_TRUE(raplas::same_bits(a.light.corner, b.light.corner));
    const Vec3d pivot = s.animation->objects.at(0).pivot;
    std::size_t floor = 0, bunny = 0, moved = 0;
    float bunny_low_a = INFINITY, bunny_low_b = INFINITY, floor_top = -INFINITY;
    for (std::size_t t = 0; t < a.mesh.triangle_count(); ++t) {
        const bool is_floor = a.mesh.triangle_object[t] == Mesh::kAddedObject;
        (is_floor ? floor : bunny) += 1;
        for (int k = 0; k < 3; ++k) {
            const Vec3f p = a.mesh.corner(t, k), q = b.mesh.corner(t, k);
            if (is_floor) {
                EXPECT_TRUE(raplas::same_bits(p, q)) << "floor triangle " << t << " moved";
                floor_top = std::max(floor_top, p.y);
                continue;
            }
            // Half a turn about the vertical axis through the pivot: same height, mirrored through the pivot in x and z.
            EXPECT_NEAR(q.y, p.y, 1e-7);
            EXPECT_NEAR(q.x, 2 * pivot.x - p.x, 1e-6);
            EXPECT_NEAR(q.z, 2 * pivot.z - p.z, 1e-6);
            if (!raplas::same_bits(p, q)) ++moved;
            bunny_low_a = std::min(bunny_low_a, p.y);
            bunny_low_b = std::min(bunny_low_b, q.y);
        }
    }
    EXPECT_EQ(floor, 2u);
    EXPECT_EQ(bunny, 69451u);
    EXPECT_GT(moved, 3 * bunny - 10);  // (a corner on the axis could stay)
    EXPECT_EQ(bunny_low_a, bunny_low_b);  // still standing on the floor
    EXPECT_LT(floor_top, bunny_low_b);
    EXPECT_GT(floor_top, bunny_low_b - 0.001f);
}

TEST(AnimatedScenes, WaveGridDeforms) {
    const Scene s = load_shipped("wave");
    ASSERT_TRUE(s.animation);
    EXPECT_EQ(raplas::frame_count(s), 48);
    EXPECT_EQ(s.animation->deform, raplas::Deform::wave);
    EXPECT_EQ(s.mesh.triangle_count(), 131072u);  // 256 x 256 cells, 2 triangles each
    const Scene a = raplas::scene_at_frame(s, 0), b = raplas::scene_at_frame(s, 24);
    ASSERT_EQ(a.mesh.triangles, b.mesh.triangles);
    ASSERT_EQ(a.mesh.vertices.size(), b.mesh.vertices.size());
    EXPECT_TRUE(raplas::same_bits(a.camera.eye, b.camera.eye));
    EXPECT_TRUE(raplas::same_bits(a.light.corner, b.light.corner));
    std::size_t changed = 0;
    for (std::size_t i = 0; i < a.mesh.vertices.size(); ++i) {
        const Vec3f p = a.mesh.vertices[i], q = b.mesh.vertices[i];
        EXPECT_TRUE(raplas::same_bits(p.x, q.x) && raplas::same_bits(p.z, q.z)) << "vertex " << i << " moved sideways";
        EXPECT_LE(std::fabs(q.y), 0.25f + 1e-6f);
        // Half a period later the wave is upside down: y(24) = -y(0).
        EXPECT_NEAR(q.y, -p.y, 1e-6);
        if (!raplas::same_bits(p.y, q.y)) ++changed;
    }
    EXPECT_GT(changed, a.mesh.vertices.size() * 9 / 10);
}

// ---- refit_spheres ----------------------------------------------------------------

TEST(AnimatedSphereRefit, FittingAgainAnUnmovedMeshIsTheBuild) {
    const Mesh m = raplas::builtin_mesh(2);
    const double margin = margin_of(m);
    for (const char* method : {"median-split", "file-order"}) {
        for (int k : {1, 2, 3}) {
            const SphereSet built = raplas::build_spheres(m, k, method, margin);
            const SphereSet again =
                raplas::refit_spheres(built, margin, m, {}, {}, SphereRefit::enclose, method, margin, 2);
            EXPECT_TRUE(raplas::same_spheres(built, again)) << method << " K=" << k;
        }
    }
}

TEST(AnimatedSphereRefit, IdentityMotionKeepsTheSpheresBitForBit) {
    const Mesh m = raplas::builtin_mesh(2);
    const double margin = margin_of(m);
    const SphereSet built = raplas::build_spheres(m, 2, "median-split", margin);
    const std::vector<std::int32_t> motion(m.triangle_count(), 0);
    for (SphereRefit mode : {SphereRefit::transform, SphereRefit::transform_radius})
        EXPECT_TRUE(raplas::same_spheres(built, raplas::refit_spheres(built, margin, m, motion, {RigidMotion{}}, mode, "median-split", margin)));
}

TEST(AnimatedSphereRefit, RigidMotionsKeepEveryTriangleInsideItsSphere) {
    const Mesh m = raplas::builtin_mesh(2);
    const double margin = margin_of(m);
    std::mt19937_64 rng(15);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int k : {1, 2, 5}) {
        const SphereSet built = raplas::build_spheres(m, k, "median-split", margin);
        for (int trial = 0; trial < 12; ++trial) {
            // Large and small scales, far pivots and translations: the rounding allowance must cover them all.
            const double scale = std::pow(10.0, 3 * unit(rng));
            const double far = std::pow(10.0, 4 * unit(rng));
            const RigidMotion motion = rotation({unit(rng), unit(rng), unit(rng) + 1.5}, 360 * unit(rng),
                                                {far * unit(rng), far * unit(rng), far * unit(rng)},
                                                {far * unit(rng), far * unit(rng), far * unit(rng)}, scale);
            // Every triangle moves, or (odd trials) only the object "box" and the rest stays.
            std::vector<std::int32_t> tri_motion(m.triangle_count(), 1);
            if (trial % 2) {
                const auto box = std::find(m.object_names.begin(), m.object_names.end(), "box") - m.object_names.begin();
                for (std::size_t t = 0; t < m.triangle_count(); ++t)
                    tri_motion[t] = m.triangle_object[t] == box ? 1 : 0;
            }
            const std::vector<RigidMotion> motions = {RigidMotion{}, motion};
            const Mesh moved = moved_mesh(m, tri_motion, motions);
            const double new_margin = margin_of(moved);
            for (SphereRefit mode : {SphereRefit::transform, SphereRefit::transform_radius, SphereRefit::enclose}) {
                const SphereSet s = raplas::refit_spheres(built, margin, moved, tri_motion, motions, mode, "median-split",
                                                          new_margin, 2);
                EXPECT_EQ(spheres_not_enclosing(s, moved, new_margin), 0u)
                    << "K=" << k << " trial " << trial << " mode " << int(mode) << " scale " << scale << " far " << far;
                // The grouping and order are the earlier set's; the records are the moved mesh's.
                EXPECT_EQ(s.first_tri, built.first_tri);
                EXPECT_EQ(s.tri_mesh_index, built.tri_mesh_index);
                for (std::size_t i = 0; i < s.triangles.size(); ++i)
                    ASSERT_TRUE(raplas::same_bits(s.triangles[i],
                                            raplas::make_triangle_record(moved, static_cast<std::size_t>(s.tri_mesh_index[i]))));
                if (mode == SphereRefit::enclose) continue;
                // A sphere whose triangles share the motion has the moved centre.
                for (std::size_t j = 0; j < s.spheres.size(); ++j) {
                    const std::size_t lo = s.first_tri[j];
                    bool shared = true;
                    for (std::size_t i = lo; i < lo + s.tri_count[j]; ++i)
                        shared = shared && tri_motion[static_cast<std::size_t>(s.tri_mesh_index[i])] ==
                                               tri_motion[static_cast<std::size_t>(s.tri_mesh_index[lo])];
                    if (!shared) continue;
                    const std::int32_t mo = tri_motion[static_cast<std::size_t>(s.tri_mesh_index[lo])];
                    const Vec3f want = mo == 0 && new_margin == margin
                                           ? built.spheres[j].c
                                           : raplas::to_f(motions[static_cast<std::size_t>(mo)].apply(raplas::to_d(built.spheres[j].c)));
                    ASSERT_TRUE(raplas::same_bits(s.spheres[j].c, want)) << "sphere " << j;
                }
            }
        }
    }
}

TEST(AnimatedSphereRefit, TransformedSpheresAreCloseToTheRebuiltOnes) {
    // K = 1: every sphere is one triangle's smallest sphere, so the rebuild's
    // sphere of a triangle is the moved sphere up to rounding, in another order.
    const Mesh m = raplas::builtin_mesh(2);
    const double margin = margin_of(m);
    const SphereSet built = raplas::build_spheres(m, 1, "median-split", margin);
    const std::vector<RigidMotion> motions = {rotation({0, 1, 0}, 37, {0.3, 0, -0.2}, {0.1, 0, 0}, 1)};
    const std::vector<std::int32_t> tri_motion(m.triangle_count(), 0);
    const Mesh moved = moved_mesh(m, tri_motion, motions);
    const double new_margin = margin_of(moved);
    const SphereSet rebuilt = raplas::build_spheres(moved, 1, "median-split", new_margin);
    const SphereSet carried =
        raplas::refit_spheres(built, margin, moved, tri_motion, motions, SphereRefit::transform, "median-split", new_margin);
    std::vector<std::size_t> sphere_of(m.triangle_count());
    for (std::size_t i = 0; i < rebuilt.tri_mesh_index.size(); ++i)
        sphere_of[static_cast<std::size_t>(rebuilt.tri_mesh_index[i])] = rebuilt.tri_sphere[i];
    for (std::size_t j = 0; j < carried.spheres.size(); ++j) {
        const raplas::Sphere& a = carried.spheres[j];
        const raplas::Sphere& b = rebuilt.spheres[sphere_of[static_cast<std::size_t>(carried.tri_mesh_index[carried.first_tri[j]])]];
        EXPECT_LE(raplas::length(raplas::to_d(a.c) - raplas::to_d(b.c)), 1e-5 * b.r) << "sphere " << j;
        EXPECT_GE(a.r, b.r * (1 - 1e-5)) << "sphere " << j;
        EXPECT_LE(a.r, b.r * (1 + 1e-3) + 1e-6) << "sphere " << j;
    }
}

TEST(AnimatedSphereRefit, RefusesAMeshOfAnotherSize) {
    const Mesh m = raplas::builtin_mesh(1);
    const SphereSet built = raplas::build_spheres(m, 2, "median-split", 0.0);
    Mesh smaller = m;
    smaller.triangles.pop_back();
    EXPECT_THROW(raplas::refit_spheres(built, 0.0, smaller, {}, {}, SphereRefit::enclose, "median-split", 0.0),
                 std::invalid_argument);
    EXPECT_THROW(raplas::refit_spheres(built, 0.0, m, {0, 0}, {RigidMotion{}}, SphereRefit::transform, "median-split", 0.0),
                 std::invalid_argument);
}

}  // namespace animated_scenes_test
