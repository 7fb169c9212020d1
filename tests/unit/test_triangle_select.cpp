// The Triangle Selector readings (icc.triangle_select, docs/MODEL.md §3) as
// the memory systems see them: under `any` a group needs the triangles of
// every sphere that any valid ray-plane cuts. Checked against an independent
// sphere-by-sphere, plane-by-plane scalar Eq. 1 evaluation (not the batched
// or culled kernels the front end uses), and the shared-memory baseline
// (paper Figure 10) must read exactly their sum.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "baseline_memory.hpp"
#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/error.hpp"
#include "shared_scenes.hpp"

namespace {

using namespace raplas;
using namespace raplas::model;

struct Independent {
    std::uint64_t both = 0, any = 0;  // triangles kept under each reading
};

// One group, every sphere, every valid plane, one scalar float32 test each.
Independent scalar_need(const Trace& t, const TraceGroup& g) {
    const ArithF32 a{};
    std::vector<PlaneA<ArithF32>> planes;
    for (const Plane& p : g.planes) planes.push_back(load(a, p));
    Independent need;
    for (std::size_t s = 0; s < t.spheres.size(); ++s) {
        const SphereA<ArithF32> sp = load(a, t.spheres[s]);
        bool row = false, col = false;
        for (std::uint32_t v = 0; v < g.n && !row; ++v) row = (g.row_valid >> v & 1) && plane_hits_sphere(a, planes[v], sp);
        for (std::uint32_t h = 0; h < g.n && !col; ++h)
            col = (g.col_valid >> h & 1) && plane_hits_sphere(a, planes[g.n + h], sp);
        if (row && col) need.both += t.tri_count[s];
        if (row || col) need.any += t.tri_count[s];
    }
    return need;
}

Trace any_trace(const Scene& scene) {
    FrameOptions fo;
    fo.record = true;
    fo.pairless = true;
    fo.threads = 2;
    Frame f = render_frame(scene, fo);
    return make_trace(scene, std::move(f), fo.format, true);
}

SimConfig shared(TriangleSelect sel) {
    SimConfig c;
    c.iccs = 16;
    c.functional = FunctionalMode::trace;
    c.memory.system = MemorySystem::shared;
    c.icc.decoder.select = sel;
    return c;
}

// Every group checked when `sample` is 0, else the primary groups and about
// `sample` shadow groups evenly spread.
void check_scene(const Scene& scene, std::size_t sample) {
    const Trace t = any_trace(scene);
    const std::vector<GroupWork> w_any = group_work(t, TriangleSelect::any), w_both = group_work(t);
    std::size_t checked = 0;
    const std::size_t shadow = t.groups.size() - t.primary_groups;
    const std::size_t step = sample ? shadow / sample + 1 : 1;
    for (std::size_t gi = 0; gi < t.groups.size(); ++gi) {
        if (gi >= t.primary_groups && (gi - t.primary_groups) % step != step / 2 % step) continue;
        const Independent need = scalar_need(t, t.groups[gi]);
        ASSERT_EQ(w_both[gi].triangles_needed, need.both) << scene.name << " group " << gi;
        ASSERT_EQ(w_any[gi].triangles_needed, need.any) << scene.name << " group " << gi;
        ASSERT_EQ(w_any[gi].rt_tests, w_both[gi].rt_tests);
        ++checked;
    }
    EXPECT_GE(checked, t.primary_groups + std::min<std::size_t>(shadow, sample ? sample / 2 : shadow));
    // The shared memory reads exactly the groups' needs, under each reading.
    std::uint64_t sum_any = 0, sum_both = 0;
    for (std::size_t gi = 0; gi < t.groups.size(); ++gi) {
        sum_any += w_any[gi].triangles_needed;
        sum_both += w_both[gi].triangles_needed;
    }
    MemoryStats st_any, st_both;
    const SimResult r_any = simulate_system(t, shared(TriangleSelect::any), st_any);
    const SimResult r_both = simulate_system(t, shared(TriangleSelect::both), st_both);
    EXPECT_EQ(st_any.triangle_records_read, sum_any);
    EXPECT_EQ(st_both.triangle_records_read, sum_both);
    EXPECT_EQ(r_any.total_cycles, sum_any);  // one port, one record per cycle, ideal PEs
    EXPECT_GT(sum_any, 2 * sum_both) << scene.name << ": the readings differ";
    std::printf("  %s: %zu groups checked; shared memory reads %llu triangles under any, %llu under both\n",
                scene.name.c_str(), checked, (unsigned long long)sum_any, (unsigned long long)sum_both);
}

}  // namespace

TEST(TriangleSelectReading, BuiltInSceneEveryGroup) {
    SceneRequest req;
    req.overrides = {"image.width=24", "image.height=24", "groups.size=8", "groups.shadow_size=8", "builtin_detail=1"};
    check_scene(load_scene(req), 0);
}

TEST(TriangleSelectReading, BunnyAt64x64) {
    RAPLAS_NEED_SHARED(raplas_test::shared_scene("bunny/bun_zipper.obj"));
    SceneRequest req;
    req.scene_file = std::string(RAPLAS_SOURCE_DIR) + "/scenes/bunny.toml";
    check_scene(load_scene(req), 24);
}

TEST(TriangleSelectReading, TheRowAndColumnTraceCannotServeTheAnyReading) {
    SceneRequest req;
    req.overrides = {"image.width=8", "image.height=8", "groups.size=8", "groups.shadow_size=4", "builtin_detail=0"};
    const Scene scene = load_scene(req);
    FrameOptions fo;
    fo.record = true;
    const Trace t = make_trace(scene, render_frame(scene, fo), fo.format);
    MemoryStats st;
    EXPECT_THROW(simulate_system(t, shared(TriangleSelect::any), st), InputError);
    EXPECT_NO_THROW(simulate_system(t, shared(TriangleSelect::both), st));
}
