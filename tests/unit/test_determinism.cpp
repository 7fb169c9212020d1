// The same run with 1, 2 and 3 threads (an odd count splits the work
// differently) gives the same bytes: PNG, hits CSV, trace file, and JSON
// apart from the wall-clock figures kept under "wall"; for the built-in scene
// and, from the shared scenes, the small bunny on a floor. (Sweep CSVs for
// --jobs 1, 2 and 3: test_sweep.cpp.)
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "run_raplas.hpp"
#include "shared_scenes.hpp"

namespace {

using namespace raplas_test;

const char* const kThreads[] = {"1", "2", "3"};

// A scene whose shadow groups hit many spheres, so that threads interleave.
std::vector<std::string> scene_args(const std::string& scene) {
    std::vector<std::string> a = {"--set", "image.width=48", "--set", "image.height=40", "--set", "groups.size=8",
                                  "--set", "groups.shadow_size=4"};
    if (scene == "bunny_floor") return plus(a, {"--mesh", shared_scene("bunny/bun_zipper_res4.obj"), "--set", "floor=true"});
    return plus(a, {"--set", "builtin_detail=3"});
}

class Determinism : public TempDirTest, public ::testing::WithParamInterface<std::string> {
protected:
    void SetUp() override {
        TempDirTest::SetUp();
        if (GetParam() == "bunny_floor") RAPLAS_NEED_SHARED(shared_scene("bunny/bun_zipper_res4.obj"));
    }
    void ok(const std::vector<std::string>& args) const {
        const RunResult r = run(args);
        ASSERT_EQ(r.code, 0) << r.err;
    }
    // The JSON file without its "wall" object, which must be there.
    nlohmann::json without_wall(const std::string& name) const {
        nlohmann::json j = nlohmann::json::parse(slurp(dir / name));
        EXPECT_TRUE(j.contains("wall")) << name;
        j.erase("wall");
        return j;
    }
};

TEST_P(Determinism, RenderPngHitsAndJsonDoNotDependOnThreads) {
    for (const char* n : kThreads)
        ASSERT_NO_FATAL_FAILURE(ok(plus(plus({"render", "-q"}, scene_args(GetParam())),
                                        {"--threads", n, "-o", std::string(n) + ".png", "--json",
                                         std::string(n) + ".json", "--hits", std::string(n) + ".csv"})));
    const nlohmann::json one = without_wall("1.json");
    EXPECT_GT(one["counts"]["shadow_ray_groups"].get<std::uint64_t>(), 100u);
    EXPECT_GT(slurp(dir / "1.png").size(), 100u);
    for (const char* n : {"2", "3"}) {
        SCOPED_TRACE(std::string("--threads ") + n);
        EXPECT_TRUE(slurp(dir / "1.png") == slurp(dir / (std::string(n) + ".png"))) << "PNG differs";
        EXPECT_TRUE(slurp(dir / "1.csv") == slurp(dir / (std::string(n) + ".csv"))) << "hits CSV differs";
        EXPECT_EQ(one.dump(), without_wall(std::string(n) + ".json").dump());
    }
}

TEST_P(Determinism, TraceFileAndSimulateJsonDoNotDependOnThreads) {
    const std::vector<std::string> sim = {"simulate", "-q", "--iccs", "3", "--fifo", "10"};
    for (const char* n : kThreads) {
        const std::string t = n;
        ASSERT_NO_FATAL_FAILURE(ok(plus(plus({"trace", "-q"}, scene_args(GetParam())), {"--threads", t, "-o", t + ".trace"})));
        // the front end with n threads, then the model
        ASSERT_NO_FATAL_FAILURE(ok(plus(plus(sim, scene_args(GetParam())), {"--threads", t, "--json", t + ".json"})));
    }
    const std::string trace = slurp(dir / "1.trace");
    EXPECT_GT(trace.size(), 1000u);
    // the model from the trace file
    ASSERT_NO_FATAL_FAILURE(ok(plus(sim, {"--trace", "1.trace", "--json", "from_trace.json"})));
    const nlohmann::json one = without_wall("1.json");
    EXPECT_GT(one["total_cycles"].get<std::uint64_t>(), 0u);
    EXPECT_TRUE(one["functional_match"].get<bool>());
    for (const char* n : {"2", "3"}) {
        SCOPED_TRACE(std::string("--threads ") + n);
        EXPECT_TRUE(trace == slurp(dir / (std::string(n) + ".trace"))) << "trace files differ";
        EXPECT_EQ(one.dump(), without_wall(std::string(n) + ".json").dump());
    }
    EXPECT_EQ(one.dump(), without_wall("from_trace.json").dump());
}

INSTANTIATE_TEST_SUITE_P(Scenes, Determinism, ::testing::Values("builtin", "bunny_floor"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
