// The functional check can fail. The model's answers come from the same
// kernels as the front end's, so two things guard them: a fault that makes
// one answer wrong must turn `functional_match` false, name the ray and exit
// 1 (every timing engine); and the plane masks the model's Plane-Sphere
// Intersectors compute (batched, culled kernels) must equal a sphere-by-sphere,
// plane-by-plane scalar Eq. 1 evaluation in every number format.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "functional.hpp"
#include "raplas/core/intersect.hpp"
#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/scene/scene.hpp"
#include "run_raplas.hpp"
#include "shared_scenes.hpp"

namespace {

using namespace raplas;
using namespace raplas_test;
using ::testing::HasSubstr;

class FunctionalFault : public TempDirTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(FunctionalFault, OneWrongRtiAnswerIsCaughtNamedAndExitsOne) {
    // (the built-in scene at 32x32: four primary groups, one pass on 4 ICCs)
    const std::vector<std::string> sim = {"simulate", "-q", "--config", "paper", "--iccs", "4",
                                          "--set", "image.width=32", "--set", "image.height=32",
                                          "--set", "sim.mode=" + GetParam()};
    const RunResult good = run(plus(sim, {"--json", "good.json"}));
    ASSERT_EQ(good.code, 0) << good.err;
    const nlohmann::json g = nlohmann::json::parse(slurp(dir / "good.json"));
    EXPECT_TRUE(g["functional_match"].get<bool>());
    EXPECT_EQ(g["rays_mismatched"].get<std::uint64_t>(), 0u);
    EXPECT_TRUE(g["first_mismatch"].is_null());

    const RunResult bad = run(plus(sim, {"--set", "sim.fault=wrong_rti", "--set", "sim.fault_icc=2", "--json", "bad.json"}));
    EXPECT_EQ(bad.code, 1) << bad.err;
    EXPECT_THAT(bad.err, HasSubstr("raplas: error: functional mismatch: 1 of "));
    EXPECT_THAT(bad.err, HasSubstr("first: primary ray (h "));
    EXPECT_THAT(bad.err, HasSubstr("model triangle "));
    // The JSON is still written, and says which ray.
    const nlohmann::json b = nlohmann::json::parse(slurp(dir / "bad.json"));
    EXPECT_FALSE(b["functional_match"].get<bool>());
    EXPECT_EQ(b["rays_mismatched"].get<std::uint64_t>(), 1u);
    EXPECT_EQ(b["rays_checked"], g["rays_checked"]);
    const nlohmann::json& m = b["first_mismatch"];
    ASSERT_TRUE(m.is_object()) << b.dump();
    // ICC 2 of 4 serves group 2 in the first pass (a primary group).
    EXPECT_EQ(m["group"].get<std::size_t>(), 2u);
    EXPECT_EQ(m["kind"], "primary");
    EXPECT_EQ(m["model"]["t"].get<double>(), 0.0);
    EXPECT_NE(m["model"], m["frontend"]);
    // The wrong answer is an answer, not a timing change: the cycles are the same.
    EXPECT_EQ(b["total_cycles"], g["total_cycles"]);
}

INSTANTIATE_TEST_SUITE_P(Engines, FunctionalFault, ::testing::Values("event", "netlist"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

// (sim.fault = wrong_rti without the compute mode: the bad-input table.)

// ---- plane masks against a scalar Eq. 1 -----------------------------------

struct Masks {
    std::vector<SphereHitRec> pairs;
    std::vector<SphereRun> pairless;
};

// Every sphere, every valid plane, one scalar Eq. 1 test each, operation by
// operation in the format.
template <class A>
Masks scalar_masks(const A& a, const Trace& t, const TraceGroup& g) {
    std::vector<PlaneA<A>> planes;
    for (const Plane& p : g.planes) planes.push_back(load(a, p));
    Masks m;
    for (std::uint32_t s = 0; s < t.spheres.size(); ++s) {
        const SphereA<A> sp = load(a, t.spheres[s]);
        std::uint64_t rows = 0, cols = 0;
        for (std::uint32_t v = 0; v < g.n; ++v)
            if ((g.row_valid >> v & 1) && plane_hits_sphere_ops(a, planes[v], sp)) rows |= std::uint64_t(1) << v;
        for (std::uint32_t h = 0; h < g.n; ++h)
            if ((g.col_valid >> h & 1) && plane_hits_sphere_ops(a, planes[g.n + h], sp)) cols |= std::uint64_t(1) << h;
        if (rows && cols) m.pairs.push_back({s, rows, cols});
        else if (rows || cols) add_to_runs(m.pairless, s);
    }
    return m;
}

Masks scalar_masks(const NumFormat& f, const Trace& t, const TraceGroup& g) {
    switch (f.kind) {
        case NumFormat::Kind::f32: return scalar_masks(ArithF32{f.rti}, t, g);
        case NumFormat::Kind::f64: return scalar_masks(ArithF64{f.rti}, t, g);
        case NumFormat::Kind::custom: return scalar_masks(ArithSoft{f, true}, t, g);
    }
    return {};
}

void check_masks(const Scene& scene) {
    for (const char* fmt : {"float32", "float64", "fp1-8-15"}) {
        const NumFormat format = NumFormat::parse(fmt);
        FrameOptions fo;
        fo.format = format;
        fo.record = true;
        fo.pairless = true;
        fo.threads = 2;
        const Trace t = make_trace(scene, render_frame(scene, fo), format, true);
        for (const bool cull : {false, true}) {
            const auto f = model::Functional::create(t, format, model::FunctionalMode::compute, cull, true);
            auto unit = f->make_unit();
            std::size_t records = 0;
            for (std::size_t gi = 0; gi < t.groups.size(); ++gi) {
                const TraceGroup& g = t.groups[gi];
                unit->load(g);
                const Masks want = scalar_masks(format, t, g);
                const auto& got = unit->sphere_hits();
                ASSERT_EQ(got.size(), want.pairs.size()) << scene.name << " " << fmt << " cull " << cull << " group " << gi;
                for (std::size_t i = 0; i < got.size(); ++i) {
                    // By value: SphereHitRec is packed, a reference to its members is misaligned.
                    const std::uint32_t sphere = got[i].sphere, want_sphere = want.pairs[i].sphere;
                    const std::uint64_t rows = got[i].rows, want_rows = want.pairs[i].rows;
                    const std::uint64_t cols = got[i].cols, want_cols = want.pairs[i].cols;
                    ASSERT_EQ(sphere, want_sphere) << fmt << " group " << gi;
                    ASSERT_EQ(rows, want_rows) << fmt << " group " << gi << " sphere " << sphere;
                    ASSERT_EQ(cols, want_cols) << fmt << " group " << gi << " sphere " << sphere;
                }
                ASSERT_EQ(unit->pairless(), want.pairless) << fmt << " cull " << cull << " group " << gi;
                records += got.size();
            }
            EXPECT_GT(records, t.groups.size()) << scene.name << " " << fmt << ": too few plane hits to mean much";
        }
    }
}

TEST(ModelPlaneMasks, EqualAScalarEq1EvaluationOnTheBuiltInScene) {
    SceneRequest req;
    req.overrides = {"image.width=24", "image.height=24", "groups.size=8", "groups.shadow_size=8", "builtin_detail=2"};
    check_masks(load_scene(req));
}

TEST(ModelPlaneMasks, EqualAScalarEq1EvaluationOnTheSmallBunny) {
    RAPLAS_NEED_SHARED(shared_scene("bunny/bun_zipper_res4.obj"));
    SceneRequest req;
    req.scene_file = std::string(RAPLAS_SOURCE_DIR) + "/scenes/bunny_small.toml";
    req.overrides = {"image.width=16", "image.height=16"};
    check_masks(load_scene(req));
}

}  // namespace
