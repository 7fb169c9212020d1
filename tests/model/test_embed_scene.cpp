// The scene of examples/embed_icc on the whole machine (model::simulate, one
// ICC): the nearest hits and the cycles the example expects of the ICC it
// embeds in a testbench of its own are the machine's, in both modes. (The
// example itself is built and run against an installed raplas by
// tests/embed_example.py.) One simulation per process.
#include <gtest/gtest.h>

#include "raplas/frontend/raygroups.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "top.hpp"

using namespace raplas;
using namespace raplas::model;

namespace {

TriangleRec triangle(Vec3f a, Vec3f b, Vec3f c) {
    const Vec3f e1 = b - a, e2 = c - a;
    return {a, e1, e2, cross(e1, e2), b, c};
}

// examples/embed_icc/main.cpp's scene and group, with the hits it expects.
Trace example_trace() {
    Trace t;
    t.format = NumFormat::float32();
    t.triangles = {triangle({-5, -5, 0}, {2.5f, -5, 0}, {-5, 5, 0}), triangle({2.5f, -5, 0}, {2.5f, 5, 0}, {-5, 5, 0}),
                   triangle({-1, -1, 4}, {3, -1, 4}, {-1, 3, 4}), triangle({50, 50, 0}, {51, 50, 0}, {50, 51, 0})};
    t.spheres = {{{-1.25f, 0, 0}, 6.25f}, {{1, 1, 4}, 3}, {{50.5f, 50.5f, 0}, 1}};
    t.first_tri = {0, 2, 3};
    t.tri_count = {2, 1, 1};
    t.width = t.height = t.group_size = t.shadow_group_size = 4;
    t.tris_per_sphere = 2;
    RayGroup rays;
    rays.n = 4;
    rays.origin = {0, 0, 10};
    rays.grid_corner = {-0.5, -0.5, 9};
    rays.du = {0.25, 0, 0};
    rays.dv = {0, 0.25, 0};
    rays.tmax = 1e30f;
    rays.row_valid = rays.col_valid = 0xf;
    build_planes(rays);
    TraceGroup g = trace_group(std::move(rays), GroupResult{}, false);
    const Hit T0{10, 0}, T1{10, 1}, T2{6, 2}, none{0, -1};
    g.hits = {T0, T0, T0, none, T0, T2, T2, T2, T0, T2, T2, none, T1, T2, T1, none};
    t.groups = {g};
    t.primary_groups = 1;
    return t;
}

class EmbedScene : public ::testing::TestWithParam<SimMode> {};

}  // namespace

TEST_P(EmbedScene, TheMachineGivesTheExamplesHitsAndCycles) {
    SimConfig c;
    c.mode = GetParam();
    c.functional = FunctionalMode::compute;
    const SimResult r = simulate(example_trace(), c);
    EXPECT_TRUE(r.functional_match);
    EXPECT_EQ(r.rays_checked, 16u);
    EXPECT_EQ(r.iccs[0].rti.tests, 41u);
    EXPECT_EQ(r.total_cycles, c.icc.psi.stages + 3 + 41 + c.icc.rti.stages);
}

INSTANTIATE_TEST_SUITE_P(Modes, EmbedScene, ::testing::Values(SimMode::event, SimMode::netlist),
                         [](const ::testing::TestParamInfo<SimMode>& i) {
                             return std::string(i.param == SimMode::event ? "event" : "netlist");
                         });
