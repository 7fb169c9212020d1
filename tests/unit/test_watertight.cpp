// The watertight ray-triangle test (watertight.hpp) as the RTI's alternative:
// selection (format suffix -wt, numerics.rti_test), hand cases in every kind
// of format, and the records and traces that carry the vertices it reads.
#include <gtest/gtest.h>

#include <cfloat>
#include <string>

#include "config.hpp"
#include "raplas/core/intersect.hpp"
#include "raplas/frontend/spheres.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/util/error.hpp"

namespace {

using namespace raplas;

TriangleRec tri(Vec3d a, Vec3d b, Vec3d c) {
    const Vec3d e1 = b - a, e2 = c - a;
    return {to_f(a), to_f(e1), to_f(e2), to_f(cross(e1, e2)), to_f(b), to_f(c)};
}

Ray ray(Vec3d o, Vec3d d, float tmin = 0.0f, float tmax = FLT_MAX) { return Ray{to_f(o), to_f(d), tmin, tmax}; }

bool hits(const NumFormat& f, const Ray& r, const TriangleRec& t, double& tt) {
    return with_arith(f, [&](const auto& a) { return ray_hits_triangle(a, load(a, r), load(a, t), tt); });
}
bool hits(const NumFormat& f, const Ray& r, const TriangleRec& t) {
    double tt;
    return hits(f, r, t, tt);
}

TEST(Watertight, SelectedByTheFormatSuffixAndTheConfigKey) {
    EXPECT_EQ(NumFormat::parse("float32-wt").rti, RtiTest::watertight);
    EXPECT_EQ(NumFormat::parse("float32-wt").kind, NumFormat::Kind::f32);
    EXPECT_EQ(NumFormat::parse("float64").rti, RtiTest::division_free);
    const NumFormat f = NumFormat::parse("fp1-7-16-rtz-psiunnorm-wt");
    EXPECT_EQ(f.rti, RtiTest::watertight);
    EXPECT_FALSE(f.psi_normalize);
    EXPECT_EQ(f.name(), "fp1-7-16-rtz-psiunnorm-wt");
    EXPECT_EQ(NumFormat::parse(f.name()), f);
    EXPECT_FALSE(NumFormat::parse("fp1-7-16") == NumFormat::parse("fp1-7-16-wt"));
    EXPECT_THROW(NumFormat::parse("fp1-7-16-wt-rtz"), std::invalid_argument);
    EXPECT_THROW(NumFormat::parse("-wt"), std::invalid_argument);

    auto config = [](std::initializer_list<std::string> sets) {
        ParamSet p = model::machine_params();
        for (const auto& s : sets) p.set(s);
        return model::config_from_params(p);
    };
    EXPECT_EQ(config({"numerics.rti_test=watertight"}).format.name(), "float32-wt");
    EXPECT_EQ(config({"numerics.format=fp1-7-16", "numerics.rti_test=watertight"}).format.name(), "fp1-7-16-wt");
    EXPECT_EQ(config({"numerics.format=fp1-7-16-wt"}).format.name(), "fp1-7-16-wt");
    EXPECT_EQ(config({"numerics.rti_test=division_free"}).format.name(), "float32");
    EXPECT_THROW(config({"numerics.format=fp1-7-16-wt", "numerics.rti_test=division_free"}), InputError);
    EXPECT_THROW(config({"numerics.rti_test=exact"}), InputError);
}

class WatertightKernel : public ::testing::TestWithParam<const char*> {
protected:
    NumFormat f = NumFormat::parse(GetParam());
};

const TriangleRec kTri = tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0});

TEST_P(WatertightKernel, HitsAtTheExactDistanceFromBothSides) {
    double t = -1;
    ASSERT_TRUE(hits(f, ray({0.25, 0.25, 1}, {0, 0, -1}), kTri, t));
    EXPECT_EQ(t, 1.0);
    ASSERT_TRUE(hits(f, ray({0.25, 0.25, 3}, {0, 0, -2}), kTri, t));  // t in units of D
    EXPECT_EQ(t, 1.5);
    ASSERT_TRUE(hits(f, ray({-0.75, -0.75, 2}, {0.5, 0.5, -1}), kTri, t));
    EXPECT_EQ(t, 2.0);
    ASSERT_TRUE(hits(f, ray({0.25, 0.25, -1}, {0, 0, 1}), kTri, t));  // back face
    EXPECT_EQ(t, 1.0);
    ASSERT_TRUE(hits(f, ray({0.25, 0.5, 0.5}, {0, -1, -1}), kTri, t));  // largest |D| component negative
    EXPECT_EQ(t, 0.5);
}

TEST_P(WatertightKernel, MissesOutsideBehindParallelAndOutOfRange) {
    EXPECT_FALSE(hits(f, ray({0.75, 0.75, 1}, {0, 0, -1}), kTri));   // beyond the hypotenuse
    EXPECT_FALSE(hits(f, ray({-0.25, 0.25, 1}, {0, 0, -1}), kTri));  // left of the y edge
    EXPECT_FALSE(hits(f, ray({0.25, 0.25, 1}, {0, 0, 1}), kTri));    // behind the origin
    EXPECT_FALSE(hits(f, ray({0.25, 0.25, 0}, {1, 0, 0}), kTri));    // in the plane
    EXPECT_FALSE(hits(f, ray({0.25, 0.25, 1}, {0, 0, -1}, 0.0f, 1.0f), kTri));  // t = tmax (open interval)
    EXPECT_FALSE(hits(f, ray({0.25, 0.25, 1}, {0, 0, -1}, 1.0f, 5.0f), kTri));  // t = tmin
    EXPECT_TRUE(hits(f, ray({0.25, 0.25, 1}, {0, 0, -1}, 0.5f, 1.5f), kTri));
}

TEST_P(WatertightKernel, EdgesAndVerticesAreInclusive) {
    for (Vec3d p : {Vec3d{0, 0.5, 0}, Vec3d{0.5, 0, 0}, Vec3d{0.5, 0.5, 0}, Vec3d{0, 0, 0}, Vec3d{1, 0, 0}, Vec3d{0, 1, 0}})
        EXPECT_TRUE(hits(f, ray(p + Vec3d{0, 0, 1}, {0, 0, -1}), kTri)) << p.x << "," << p.y;
}

TEST_P(WatertightKernel, DegenerateTrianglesAreNeverHit) {
    for (const TriangleRec& t : {tri({0, 0, 0}, {1, 1, 1}, {2, 2, 2}), tri({0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, 0.5, 0}),
                                 tri({0, 0, 0}, {0, 0, 0}, {1, 0, 0})})
        for (Vec3d d : {Vec3d{0, 0, -1}, Vec3d{0.3, -0.2, -1}, Vec3d{-1, 1, 0.5}})
            EXPECT_FALSE(hits(f, ray(Vec3d{0.5, 0.5, 0} - d, d), t));
}

TEST_P(WatertightKernel, ASharedEdgeNeverLetsARayThrough) {
    // Two triangles with an edge at awkward float32 coordinates, opposite
    // windings along the edge as in a closed mesh; rays aimed at points of
    // the edge from many directions: one or both always hit.
    const Vec3d a{0.1, 0.3, 0.7}, b{0.9, 0.35, 0.2}, c{0.4, 0.9, 0.3}, d{0.5, -0.2, 0.5};
    const TriangleRec t1 = tri(a, b, c), t2 = tri(b, a, d);
    const Vec3d n1 = cross(b - a, c - a), n2 = cross(a - b, d - b);
    int rays = 0;
    for (int i = 1; i < 40; ++i) {
        const double s = i / 40.0 + 1e-3 / 7;
        const Vec3d p = a + (b - a) * s;
        for (Vec3d dir : {Vec3d{0.1, 0.2, -1}, Vec3d{-0.3, 0.1, -0.8}, Vec3d{0.05, -0.9, -0.4}, Vec3d{0.7, 0.1, -0.6},
                          Vec3d{-0.1, -0.2, 1}, Vec3d{0.2, 0.3, 0.9}}) {
            // both triangles seen from the same side: the ray crosses the surface at the edge
            if ((dot(dir, n1) < 0) != (dot(dir, n2) < 0)) continue;
            const Vec3f o = to_f(p - dir * 2.0);
            const Ray r{o, to_f(p - to_d(o)), 0.0f, FLT_MAX};
            EXPECT_TRUE(hits(f, r, t1) || hits(f, r, t2)) << GetParam() << " s=" << s;
            ++rays;
        }
    }
    EXPECT_GT(rays, 100);
}

INSTANTIATE_TEST_SUITE_P(Formats, WatertightKernel,
                         ::testing::Values("float32-wt", "float64-wt", "fp1-7-16-wt", "fp1-7-16-rtz-wt", "fp1-8-15-wt"),
                         [](const ::testing::TestParamInfo<const char*>& i) {
                             std::string s = i.param;
                             for (char& c : s)
                                 if (c == '-') c = '_';
                             return s;
                         });

TEST(Watertight, RecordsAndTracesCarryTheVertices) {
    Mesh m;
    m.materials.push_back(Material{});
    m.vertices = {{0.1f, 0.2f, 0.3f}, {1.7f, 0.25f, -0.3f}, {0.3f, 2.1f, 0.05f}};
    m.triangles = {{0, 1, 2}};
    m.triangle_material = {0};
    const TriangleRec r = make_triangle_record(m, 0);
    EXPECT_EQ(r.v0, m.vertices[0]);
    EXPECT_EQ(r.v1, m.vertices[1]);
    EXPECT_EQ(r.v2, m.vertices[2]);
    Trace t;
    t.scene_name = "one";
    t.format = NumFormat::parse("fp1-7-16-wt");
    t.spheres = {Sphere{{0.5f, 0.5f, 0.f}, 3.f}};
    t.first_tri = {0};
    t.tri_count = {1};
    t.triangles = {r};
    t.tri_mesh_index = {0};
    const Trace back = parse_trace(serialize_trace(t), "mem");
    ASSERT_EQ(back.triangles.size(), 1u);
    EXPECT_EQ(back.triangles[0].v1, r.v1);
    EXPECT_EQ(back.triangles[0].v2, r.v2);
    EXPECT_EQ(back.triangles[0].n, r.n);
    EXPECT_EQ(back.format, t.format);
}

}  // namespace
