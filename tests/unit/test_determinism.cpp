// The same run twice, with different thread counts, gives the same bytes:
// PNG, trace file, and JSON apart from the wall-clock figures kept under
// "wall". (The PNG and hits CSV for --threads 1 and 2 are also checked in
// test_cli.cpp; sweep CSVs for --jobs 1 and 2 in test_sweep.cpp.)
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) {
        if (c == '\'') q += "'\\''";
        else q += c;
    }
    return q + "'";
}

class Determinism : public ::testing::Test {
protected:
    fs::path dir;
    void SetUp() override {
        std::string tmpl = (fs::path(::testing::TempDir()) / "raplas_det_XXXXXX").string();
        ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
        dir = tmpl;
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    int run(const std::vector<std::string>& args) const {
        std::string cmd = "cd " + quoted(dir.string()) + " && " + quoted(RAPLAS_BINARY);
        for (const auto& a : args) cmd += " " + quoted(a);
        cmd += " >/dev/null 2>" + quoted((dir / "stderr").string());
        const int status = std::system(cmd.c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    std::string err() const { return slurp(dir / "stderr"); }
    // The JSON file without its "wall" object, which must be there.
    nlohmann::json without_wall(const std::string& name) const {
        nlohmann::json j = nlohmann::json::parse(slurp(dir / name));
        EXPECT_TRUE(j.contains("wall")) << name;
        j.erase("wall");
        return j;
    }
};

// A scene whose shadow groups hit many spheres, so that threads interleave.
std::vector<std::string> scene_args() {
    std::vector<std::string> a = {"--set", "image.width=48", "--set", "image.height=40", "--set", "groups.size=8",
                                  "--set", "groups.shadow_size=4"};
    const std::string bunny = std::string(RAPLAS_SHARED_SCENES) + "/bunny/bun_zipper_res4.obj";
    if (fs::exists(bunny)) a.insert(a.end(), {"--mesh", bunny, "--set", "floor=true"});
    return a;
}

std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

}  // namespace

TEST_F(Determinism, RenderJsonAndPngDoNotDependOnThreads) {
    ASSERT_EQ(run(plus(plus({"render", "-q"}, scene_args()), {"--threads", "1", "-o", "a.png", "--json", "a.json"})), 0)
        << err();
    ASSERT_EQ(run(plus(plus({"render", "-q"}, scene_args()), {"--threads", "2", "-o", "b.png", "--json", "b.json"})), 0)
        << err();
    EXPECT_EQ(slurp(dir / "a.png"), slurp(dir / "b.png"));
    const nlohmann::json a = without_wall("a.json"), b = without_wall("b.json");
    EXPECT_GT(a["counts"]["shadow_ray_groups"].get<std::uint64_t>(), 100u);
    EXPECT_EQ(a.dump(), b.dump());
}

TEST_F(Determinism, TraceFileAndSimulateJsonDoNotDependOnThreads) {
    ASSERT_EQ(run(plus(plus({"trace", "-q"}, scene_args()), {"--threads", "1", "-o", "a.trace"})), 0) << err();
    ASSERT_EQ(run(plus(plus({"trace", "-q"}, scene_args()), {"--threads", "2", "-o", "b.trace"})), 0) << err();
    const std::string ta = slurp(dir / "a.trace");
    EXPECT_GT(ta.size(), 1000u);
    EXPECT_TRUE(ta == slurp(dir / "b.trace")) << "trace files differ";
    // simulate: the front end with 1 and 2 threads, the model from the scene and from the trace
    const std::vector<std::string> sim = {"simulate", "-q", "--iccs", "3", "--fifo", "10"};
    ASSERT_EQ(run(plus(plus(sim, scene_args()), {"--threads", "1", "--json", "a.json"})), 0) << err();
    ASSERT_EQ(run(plus(plus(sim, scene_args()), {"--threads", "2", "--json", "b.json"})), 0) << err();
    ASSERT_EQ(run(plus(sim, {"--trace", "a.trace", "--json", "c.json"})), 0) << err();
    const nlohmann::json a = without_wall("a.json"), b = without_wall("b.json"), c = without_wall("c.json");
    EXPECT_GT(a["total_cycles"].get<std::uint64_t>(), 0u);
    EXPECT_TRUE(a["functional_match"].get<bool>());
    EXPECT_EQ(a.dump(), b.dump());
    EXPECT_EQ(a.dump(), c.dump());
}
