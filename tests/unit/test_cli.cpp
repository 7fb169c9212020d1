// The `raplas` executable end to end: outputs, exit codes, error messages,
// determinism across thread counts.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "raplas/app/image_io.hpp"
#include "raplas/app/reports.hpp"
#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/scene/scene.hpp"
#include "run_raplas.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::StartsWith;

using namespace raplas_test;

class Cli : public TempDirTest {
protected:
    // A bad-input run: exit 2, nothing on stdout, one line on stderr naming `needle`.
    void expect_input_error(const std::vector<std::string>& args, const std::string& needle) const {
        const RunResult r = run(args);
        std::string shown;
        for (const auto& a : args) shown += a + " ";
        EXPECT_EQ(r.code, 2) << shown << "\nstderr: " << r.err;
        EXPECT_THAT(r.err, StartsWith("raplas: error:")) << shown;
        EXPECT_THAT(r.err, HasSubstr(needle)) << shown;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << shown << "\nstderr: " << r.err;
        EXPECT_EQ(r.out, "") << shown;
    }
};

TEST_F(Cli, RenderWithNoArgumentsWritesAPng) {
    const RunResult r = run({"render"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_THAT(r.out, HasSubstr("render.png"));
    const std::string png = (dir / "render.png").string();
    ASSERT_TRUE(fs::exists(png));
    EXPECT_EQ(slurp(png).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    int w = 0, h = 0;
    const std::vector<std::uint8_t> px = raplas::read_rgb8(png, w, h);
    EXPECT_EQ(w, 64);
    EXPECT_EQ(h, 64);
    ASSERT_EQ(px.size(), 64u * 64u * 3u);
    // a real picture: many distinct values, not a constant image
    std::vector<bool> seen(256, false);
    for (auto v : px) seen[v] = true;
    EXPECT_GT(std::count(seen.begin(), seen.end(), true), 30);
    // nothing else left in the directory (atomic writes leave no temporaries)
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
    EXPECT_EQ(files, 1u);
}

TEST_F(Cli, VersionAndHelp) {
    RunResult r = run({"--version"});
    EXPECT_EQ(r.code, 0);
    EXPECT_THAT(r.out, StartsWith("raplas "));
    EXPECT_THAT(r.out, ::testing::ContainsRegex("raplas [0-9]+\\.[0-9]+"));
    r = run({"--help"});
    EXPECT_EQ(r.code, 0);
    EXPECT_THAT(r.out, AllOf(HasSubstr("render"), HasSubstr("trace")));
    r = run({"render", "--help"});
    EXPECT_EQ(r.code, 0);
    EXPECT_THAT(r.out, AllOf(HasSubstr("--scene"), HasSubstr("--mesh"), HasSubstr("--set"), HasSubstr("--hits")));
    EXPECT_FALSE(fs::exists(dir / "render.png"));
}

TEST_F(Cli, UsageErrorsExitTwo) {
    RunResult r = run({});
    EXPECT_EQ(r.code, 2);
    EXPECT_THAT(r.err, HasSubstr("subcommand"));
    r = run({"render", "--no-such-option"});
    EXPECT_EQ(r.code, 2);
    EXPECT_THAT(r.err, HasSubstr("--no-such-option"));
    r = run({"frobnicate"});
    EXPECT_EQ(r.code, 2);
}

TEST_F(Cli, BadInputsExitTwoWithOneLineNamingTheFileOrKey) {
    const std::string missing = (dir / "missing_scene.toml").string();
    expect_input_error({"render", "--scene", missing}, missing);
    expect_input_error({"render", "--set", "nosuch.key=1"}, "nosuch.key");
    expect_input_error({"render", "--set", "image.width=0"}, "image.width");
    expect_input_error({"render", "--format", "fp9-9"}, "--format");
    const std::string scene = write("ok.toml", "[image]\nwidth = 8\nheight = 8\n");
    const std::string mesh = write("ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_input_error({"render", "--scene", scene, "--mesh", mesh}, "--scene or --mesh");
    const std::string bad_obj = write("broken.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    expect_input_error({"render", "--mesh", bad_obj}, bad_obj + ":3:");
    const std::string bad_scene = write("bad.toml", "[image]\ncolour = 3\n");
    expect_input_error({"render", "--scene", bad_scene}, bad_scene + ":2: unknown scene key 'image.colour'");
    expect_input_error({"trace", "-o", "t.trace", "--set", "bogus=1"}, "bogus");
    // no output was produced by any of the failed runs
    EXPECT_FALSE(fs::exists(dir / "render.png"));
    EXPECT_FALSE(fs::exists(dir / "t.trace"));
}

// Splits CSV text into rows of fields.
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::size_t start = 0;
        for (;;) {
            auto comma = line.find(',', start);
            f.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        rows.push_back(f);
    }
    return rows;
}

TEST_F(Cli, HitsCsvHasOneRowPerPixel) {
    const RunResult r = run({"render", "-q", "--set", "image.width=20", "--set", "image.height=12", "--set",
                       "builtin_detail=1", "--hits", "hits.csv", "-o", "img.png"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out, "");  // -q
    const std::string text = slurp(dir / "hits.csv");
    ASSERT_FALSE(text.empty());
    EXPECT_EQ(text.back(), '\n');
    const auto rows = parse_csv(text);
    ASSERT_EQ(rows.size(), 1u + 20u * 12u);
    EXPECT_EQ(text.substr(0, text.find('\n')), "x,y,ox,oy,oz,dx,dy,dz,tri,t");
    // the same scene rendered in-process
    raplas::SceneRequest req;
    req.overrides = {"image.width=20", "image.height=12", "builtin_detail=1"};
    const raplas::Scene scene = raplas::load_scene(req);
    raplas::FrameOptions fo;
    fo.threads = 1;
    const raplas::Frame f = raplas::render_frame(scene, fo);
    std::size_t hits = 0, misses = 0;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        const auto& row = rows[i];
        ASSERT_EQ(row.size(), 10u) << "row " << i;
        const int x = std::stoi(row[0]), y = std::stoi(row[1]);
        EXPECT_EQ(x, int((i - 1) % 20));
        EXPECT_EQ(y, int((i - 1) / 20));
        const raplas::Hit& h = f.pixel_hit[i - 1];
        const int tri = std::stoi(row[8]);
        if (h.tri < 0) {
            EXPECT_EQ(tri, -1) << "row " << i;
            EXPECT_EQ(row[9], "") << "row " << i;
            ++misses;
        } else {
            EXPECT_EQ(tri, f.spheres.tri_mesh_index[std::size_t(h.tri)]) << "row " << i;
            EXPECT_EQ(std::stod(row[9]), h.t) << "row " << i;  // printed with 17 digits
            ++hits;
        }
        const raplas::Ray& ray = f.pixel_ray[i - 1];
        EXPECT_EQ(std::stof(row[2]), ray.o.x);
        EXPECT_EQ(std::stof(row[5]), ray.d.x);
        EXPECT_EQ(std::stof(row[7]), ray.d.z);
    }
    EXPECT_GT(hits, 0u);
    EXPECT_GT(misses, 0u);
    EXPECT_EQ(text, raplas::hits_csv(f));
}

// (Thread counts: test_determinism.cpp.) The number format reaches the answers.
TEST_F(Cli, HitsCsvFollowsTheNumberFormat) {
    const std::vector<std::string> common = {"render", "-q", "--set", "image.width=40", "--set", "image.height=28",
                                             "--set", "groups.shadow_size=6", "--set", "groups.size=16"};
    const RunResult ra = run(plus(common, {"-o", "a.png", "--hits", "a.csv"}));
    ASSERT_EQ(ra.code, 0) << ra.err;
    const std::string ca = slurp(dir / "a.csv");
    EXPECT_EQ(std::count(ca.begin(), ca.end(), '\n'), 1 + 40 * 28);
    const RunResult rc = run(plus(common, {"--format", "float64", "-o", "c.png", "--hits", "c.csv"}));
    ASSERT_EQ(rc.code, 0) << rc.err;
    const std::string cc = slurp(dir / "c.csv");
    EXPECT_EQ(std::count(cc.begin(), cc.end(), '\n'), 1 + 40 * 28);
    EXPECT_NE(cc, ca);
}

TEST_F(Cli, TraceCommandWritesAReadableTrace) {
    const RunResult r = run({"trace", "-q", "-o", "small.trace", "--set", "image.width=16", "--set", "image.height=8",
                       "--set", "builtin_detail=0", "--set", "groups.shadow_size=2", "--format", "fp1-8-15"});
    ASSERT_EQ(r.code, 0) << r.err;
    const raplas::Trace t = raplas::read_trace((dir / "small.trace").string());
    EXPECT_EQ(t.width, 16u);
    EXPECT_EQ(t.height, 8u);
    EXPECT_EQ(t.format.name(), "fp1-8-15");
    EXPECT_EQ(t.primary_groups, 1u);
    EXPECT_GT(t.groups.size(), 1u);
}

TEST_F(Cli, DumpSceneIsValidSceneInput) {
    const RunResult a = run({"render", "--set", "image.width=17", "--set", "camera.fov_deg=55.5", "--dump-scene"});
    ASSERT_EQ(a.code, 0) << a.err;
    EXPECT_THAT(a.out, AllOf(HasSubstr("width = 17"), HasSubstr("fov_deg = 55.5")));
    EXPECT_FALSE(fs::exists(dir / "render.png"));
    const std::string scene = write("dumped.toml", a.out);
    const RunResult b = run({"render", "--scene", scene, "--dump-scene"});
    ASSERT_EQ(b.code, 0) << b.err;
    EXPECT_EQ(b.out, a.out);
}

// The value a dump (TOML, [section] headers) gives `key` in `section`.
std::string dumped(const std::string& dump, const std::string& section, const std::string& key) {
    std::string current;
    for (const auto& line : lines_of(dump)) {
        if (!line.empty() && line[0] == '[') current = line.substr(1, line.find(']') - 1);
        else if (current == section && line.rfind(key + " = ", 0) == 0) return line.substr(key.size() + 3);
    }
    return "";
}

TEST_F(Cli, SetTakesTheLastPartOfAKeyWhenOneKeyEndsInIt) {
    RunResult r = run({"simulate", "--set", "rti_pipes=2", "--set", "triangle_depth=7", "--dump-config"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(dumped(r.out, "icc", "rti_pipes"), "2");
    EXPECT_EQ(dumped(r.out, "fifo", "triangle_depth"), "7");
    // simulate gives scene keys to the scene
    r = run({"simulate", "--set", "width=9", "--set", "fov_deg=31.5", "--dump-scene"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(dumped(r.out, "image", "width"), "9");
    EXPECT_EQ(dumped(r.out, "camera", "fov_deg"), "31.5");
    r = run({"render", "--set", "height=5", "--dump-scene"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(dumped(r.out, "image", "height"), "5");
    // a sweep hands its children whole keys (a last part alone could name another key)
    r = run({"sweep", "--set", "rti_pipes=2", "--set", "width=8", "--emit-jobs", "jobs.txt", "--out", "s.csv", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(slurp(dir / "jobs.txt"), HasSubstr("--set icc.rti_pipes=2"));
    EXPECT_THAT(slurp(dir / "jobs.txt.traces"), HasSubstr("--set image.width=8"));
}

TEST_F(Cli, ShippedConfigsAndScenesByNameFromAnyDirectory) {
    RunResult r = run({"simulate", "--config", "fpga", "--dump-config"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(dumped(r.out, "", "name"), "\"fpga\"");
    r = run({"render", "--scene", "cornell", "--dump-scene"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(dumped(r.out, "", "mesh"), "\"cornell/CornellBox-Original.obj\"");
    r = run({"render", "--scene", "cornell.toml", "--dump-scene"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(dumped(r.out, "", "name"), "\"cornell\"");
    // a file in the working directory comes first, then its configs/ folder
    fs::create_directory(dir / "configs");
    write("configs/paper.toml", "name = \"mine\"\n");
    r = run({"simulate", "--config", "paper", "--dump-config"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(dumped(r.out, "", "name"), "\"mine\"");
    write("paper", "name = \"here\"\n");
    r = run({"simulate", "--config", "paper", "--dump-config"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(dumped(r.out, "", "name"), "\"here\"");
    // the names listed are those of every configs/ folder searched
    expect_input_error({"simulate", "--config", "nosuch"}, "nor a name in configs/ (fpga, paper)");
    // a sweep reads a shipped scene by name too, and hands its children the file
    r = run({"sweep", "--scene", "cornell", "--emit-jobs", "jobs.txt", "--out", "s.csv", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(slurp(dir / "jobs.txt.traces"), HasSubstr("/scenes/cornell.toml"));
}

}  // namespace
