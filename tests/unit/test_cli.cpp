// The `raplas` executable end to end: outputs, exit codes, error messages,
// determinism across thread counts.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
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
using ::testing::Not;
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

// --progress: one line per update on stderr for each long phase (the front
// end's primary and shadow ray groups, the model's passes), each ending at its
// total, a percent at a time at most; results as without it; -q alone is silent.
TEST_F(Cli, ProgressLinesForTheFrontEndAndTheModelChangeNoResult) {
    const std::vector<std::string> small = {"--set", "image.width=24", "--set", "image.height=16"};
    const RunResult quiet = run(plus({"simulate", "-q", "--json", "quiet.json"}, small));
    ASSERT_EQ(quiet.code, 0) << quiet.err;
    EXPECT_EQ(quiet.err, "");
    // unit -> its lines' "done/total", and the lines themselves
    auto phases_of = [](const std::string& err, std::vector<std::string>& all) {
        std::map<std::string, std::vector<std::string>> phases;
        std::istringstream lines(err);
        for (std::string line; std::getline(lines, line);) {
            EXPECT_THAT(line, StartsWith("[")) << line;
            EXPECT_THAT(line, HasSubstr("elapsed, ETA")) << line;
            const auto counts = line.find("] ") + 2;
            const auto space = line.find(' ', counts);
            const auto unit_end = line.find_first_of(",", space);
            phases[line.substr(space + 1, unit_end - space - 1)].push_back(line.substr(counts, space - counts));
            all.push_back(line);
        }
        return phases;
    };
    auto ends_at_total = [](const std::vector<std::string>& v, const char* unit) {
        const std::string last = v.back();
        const std::string total = last.substr(last.find('/') + 1);
        EXPECT_EQ(last, total + "/" + total) << unit;
        EXPECT_LE(v.size(), 102u) << unit;
    };
    auto drop_wall = [](nlohmann::json j) {
        j.erase("wall");
        return j;
    };
    // The whole frame first: a line per front-end phase, then the model's.
    const RunResult whole = run(plus({"simulate", "-q", "--whole-frame", "--progress", "--json", "whole.json"}, small));
    ASSERT_EQ(whole.code, 0) << whole.err;
    EXPECT_EQ(whole.out, "");
    std::vector<std::string> lines;
    auto phases = phases_of(whole.err, lines);
    for (const char* unit : {"front end primary ray groups", "front end shadow ray groups", "model passes"}) {
        ASSERT_EQ(phases.count(unit), 1u) << unit << " missing in:\n" << whole.err;
        ends_at_total(phases[unit], unit);
    }
    // Streamed: one line, the model's passes with the front end's phase beside them.
    const RunResult streamed = run(plus({"simulate", "-q", "--progress", "--json", "streamed.json"}, small));
    ASSERT_EQ(streamed.code, 0) << streamed.err;
    EXPECT_EQ(streamed.out, "");
    lines.clear();
    phases = phases_of(streamed.err, lines);
    ASSERT_EQ(phases.size(), 1u) << streamed.err;
    ASSERT_EQ(phases.count("model passes"), 1u) << streamed.err;
    ends_at_total(phases["model passes"], "model passes");
    EXPECT_THAT(lines.back(), HasSubstr("; front end shadow ray groups ")) << lines.back();
    const nlohmann::json q = drop_wall(nlohmann::json::parse(slurp(dir / "quiet.json")));
    EXPECT_EQ(drop_wall(nlohmann::json::parse(slurp(dir / "whole.json"))), q);
    EXPECT_EQ(drop_wall(nlohmann::json::parse(slurp(dir / "streamed.json"))), q);
    const RunResult render = run(plus({"render", "--progress", "-q", "-o", "p.png"}, small));
    ASSERT_EQ(render.code, 0) << render.err;
    EXPECT_THAT(render.err, HasSubstr("front end shadow ray groups"));
}

// simulate --trace reads a pipe (a FIFO here, as `--trace <(...)` gives) to
// its end: the same JSON as from the file; a pipe that ends early is one line,
// exit 2, and no result file.
TEST_F(Cli, SimulateReadsATraceFromAPipe) {
    const RunResult t = run({"trace", "-q", "-o", "t.trace", "--set", "image.width=24", "--set", "image.height=16"});
    ASSERT_EQ(t.code, 0) << t.err;
    const std::string bytes = slurp(dir / "t.trace");
    const RunResult f = run({"simulate", "-q", "--trace", "t.trace", "--json", "file.json"});
    ASSERT_EQ(f.code, 0) << f.err;
    auto through_fifo = [&](const std::string& name, const std::string& content, const std::string& json) {
        const fs::path fifo = dir / name;
        EXPECT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
        // The writer waits for raplas to open the FIFO, but not past the run's
        // end (a run that never opens it must not hang the test); a reader
        // that stops early gives EPIPE, not SIGPIPE.
        std::atomic<bool> ran{false};
        void (*old_handler)(int) = std::signal(SIGPIPE, SIG_IGN);
        std::thread writer([&] {
            int fd = -1;
            while (fd < 0 && !ran) {
                fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);  // ENXIO until a reader opens it
                if (fd < 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
            }
            if (fd < 0) return;
            ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
            for (std::size_t done = 0; done < content.size();) {
                const ssize_t w = ::write(fd, content.data() + done, content.size() - done);
                if (w <= 0) break;
                done += std::size_t(w);
            }
            ::close(fd);
        });
        const RunResult r = run({"simulate", "-q", "--trace", fifo.string(), "--json", json});
        ran = true;
        writer.join();
        std::signal(SIGPIPE, old_handler);
        return r;
    };
    const RunResult p = through_fifo("t.fifo", bytes, "pipe.json");
    ASSERT_EQ(p.code, 0) << p.err;
    EXPECT_EQ(p.err, "");
    auto drop_wall = [](nlohmann::json j) {
        j.erase("wall");
        return j;
    };
    EXPECT_EQ(drop_wall(nlohmann::json::parse(slurp(dir / "pipe.json"))),
              drop_wall(nlohmann::json::parse(slurp(dir / "file.json"))));
    const RunResult cut = through_fifo("cut.fifo", bytes.substr(0, bytes.size() / 2), "cut.json");
    EXPECT_EQ(cut.code, 2);
    EXPECT_THAT(cut.err, AllOf(StartsWith("raplas: error: " + (dir / "cut.fifo").string() + ": truncated trace"),
                               Not(HasSubstr("\n\n"))));
    EXPECT_EQ(std::count(cut.err.begin(), cut.err.end(), '\n'), 1) << cut.err;
    EXPECT_FALSE(fs::exists(dir / "cut.json"));
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
    // A machine config key given to render or trace says where it belongs.
    expect_input_error({"render", "--set", "icc.rti_pipes=2"}, "--set icc.rti_pipes: a machine config key");
    expect_input_error({"trace", "--out", "t.trace", "--set", "rti_pipes=2"}, "--set icc.rti_pipes: a machine config key");
    expect_input_error({"render", "--set", "image.widht=2"}, "unknown scene key 'image.widht'");
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

// A 5,000-triangle sphere over a square floor, as one OBJ.
std::string sphere_over_plane_obj() {
    std::ostringstream o;
    const int nu = 50, nv = 51;
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
            o << "v " << std::sin(th) * std::cos(ph) << " " << 1.2 + std::cos(th) << " " << std::sin(th) * std::sin(ph)
              << "\n";
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const int a = j * nu + i + 1, b = j * nu + (i + 1) % nu + 1, c = a + nu, d = b + nu;
            if (j > 0) o << "f " << a << " " << b << " " << d << "\n";
            if (j < nv - 1) o << "f " << a << " " << d << " " << c << "\n";
        }
    const int base = (nv + 1) * nu + 1;
    o << "v -4 0 -4\nv 4 0 -4\nv 4 0 4\nv -4 0 4\n";
    o << "f " << base << " " << base + 2 << " " << base + 1 << "\nf " << base << " " << base + 3 << " " << base + 2
      << "\n";
    return o.str();
}

TEST_F(Cli, AutomaticFramingFillsTheImageAndDumpsAsPastableValues) {
    const std::string mesh = write("sphere_plane.obj", sphere_over_plane_obj());
    const RunResult a = run({"render", "-q", "--mesh", mesh, "-o", "a.png", "--json", "a.json"});
    ASSERT_EQ(a.code, 0) << a.err;
    std::ifstream json(dir / "a.json");
    const std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
    const auto at = text.find("\"hit_pixels\":");
    ASSERT_NE(at, std::string::npos);
    const long hits = std::stol(text.substr(at + 13));
    // A floor seen from the side filled a sixth of the image; from above it fills much more.
    EXPECT_GT(hits, 4096 * 35 / 100) << "of 4096 pixels";
    // --dump-scene prints the camera and light it chose, and the mesh: a scene file for the same image.
    const RunResult d = run({"render", "--mesh", mesh, "--dump-scene"});
    ASSERT_EQ(d.code, 0) << d.err;
    EXPECT_THAT(d.out, Not(HasSubstr("(auto)")));
    EXPECT_THAT(d.out, AllOf(HasSubstr("\neye = ["), HasSubstr("\nlook_at = ["), HasSubstr("\ncorner = [")));
    const std::string scene = write("dumped.toml", d.out);
    const RunResult b = run({"render", "-q", "--scene", scene, "-o", "b.png"});
    ASSERT_EQ(b.code, 0) << b.err;
    EXPECT_TRUE(slurp(dir / "a.png") == slurp(dir / "b.png")) << "the dumped scene renders another image";
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

namespace {

using namespace raplas_test;

// ---- provenance: what a result says about where it comes from ----------------

class Provenance : public TempDirTest {
protected:
    nlohmann::json simulate(const std::vector<std::string>& extra, const std::string& name) const {
        const std::vector<std::string> base = {"simulate", "-q", "--config", "paper", "--set", "image.width=16",
                                               "--set", "image.height=16", "--set", "workload.group_size=8",
                                               "--set", "workload.shadow_group_size=4", "--json", name + ".json"};
        const RunResult r = run(plus(base, extra));
        EXPECT_EQ(r.code, 0) << r.err;
        return nlohmann::json::parse(slurp(dir / (name + ".json")));
    }
};

TEST_F(Provenance, WallSaysWhereTheCpuTimeWentAndWhoWaited) {
    const nlohmann::json j = simulate({"--iccs", "4"}, "cpu");  // streamed from the built-in scene, compute mode
    const nlohmann::json& w = j["wall"];
    for (const char* key :
         {"cpu_s", "model_cpu_s", "loads_cpu_s", "observers_cpu_s", "frontend_cpu_s", "model_waits_s", "load_waits_s",
          "frontend_waits_s"}) {
        ASSERT_TRUE(w.contains(key) && w[key].is_number()) << key;
        EXPECT_GE(w[key].get<double>(), 0.0) << key;
    }
    // Each side did work: the model stepped passes, the loads tested the
    // groups' planes and rays, the observers hashed and counted every group
    // on their own thread, the front end loaded and traced the scene.
    EXPECT_GT(w["model_cpu_s"].get<double>(), 0.0);
    EXPECT_GT(w["loads_cpu_s"].get<double>(), 0.0);
    EXPECT_GT(w["observers_cpu_s"].get<double>(), 0.0);
    EXPECT_GT(w["frontend_cpu_s"].get<double>(), 0.0);
    // The parts are parts of the process's time, and the model's waits part of its wall time.
    const double parts = w["model_cpu_s"].get<double>() + w["loads_cpu_s"].get<double>() + w["observers_cpu_s"].get<double>();
    EXPECT_LE(parts, w["cpu_s"].get<double>() + 1e-3);
    EXPECT_NEAR(w["frontend_cpu_s"].get<double>(), w["cpu_s"].get<double>() - parts, 1e-9);
    EXPECT_LE(w["model_waits_s"].get<double>() + w["load_waits_s"].get<double>(), w["model_s"].get<double>() + 1e-3);
}

TEST_F(Provenance, OverridesNameEveryChangedKeyAndTheHashesTellRunsApart) {
    const nlohmann::json plain = simulate({}, "plain");
    EXPECT_EQ(plain["config"], "paper");
    // workload.* differ from paper.toml (16 and 16): named, with their values.
    EXPECT_EQ(plain["overrides"], nlohmann::json({{"workload.group_size", 8}, {"workload.shadow_group_size", 4}}));
    EXPECT_EQ(plain["config_hash"].get<std::string>().size(), 16u);
    EXPECT_EQ(plain["workload_hash"].get<std::string>().size(), 16u);
    EXPECT_EQ(plain["resolved_config"]["icc.rti_pipes"], 1);
    EXPECT_EQ(plain["resolved_config"]["icc.triangle_select"], "any");

    // Setting a key to the config's own value changes nothing.
    const nlohmann::json same = simulate({"--set", "icc.rti_pipes=1", "--iccs", "1"}, "same");
    EXPECT_EQ(same["overrides"], plain["overrides"]);
    EXPECT_EQ(same["config_hash"], plain["config_hash"]);

    // Another machine: named, another config hash, the same workload.
    const nlohmann::json pipes = simulate({"--set", "icc.rti_pipes=2", "--fifo", "10"}, "pipes");
    EXPECT_EQ(pipes["overrides"]["icc.rti_pipes"], 2);
    EXPECT_EQ(pipes["overrides"]["fifo.triangle_depth"], 10);
    EXPECT_EQ(pipes["overrides"]["fifo.sphere_depth"], 10);
    EXPECT_NE(pipes["config_hash"], plain["config_hash"]);
    EXPECT_EQ(pipes["workload_hash"], plain["workload_hash"]);

    // Another workload (a scene key): the same machine, another workload hash.
    const nlohmann::json wider = simulate({"--set", "image.width=24"}, "wider");
    EXPECT_EQ(wider["config_hash"], plain["config_hash"]);
    EXPECT_NE(wider["workload_hash"], plain["workload_hash"]);

    // The CSV row carries the same figures.
    ASSERT_EQ(run({"simulate", "-q", "--config", "paper", "--set", "image.width=16", "--set", "image.height=16",
                   "--set", "workload.group_size=8", "--set", "workload.shadow_group_size=4", "--set",
                   "icc.rti_pipes=2", "--fifo", "10", "--csv", "pipes.csv"})
                  .code,
              0);
    const auto lines = lines_of(slurp(dir / "pipes.csv"));
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_THAT(lines[1], HasSubstr(",paper,fifo.sphere_depth=10;fifo.triangle_depth=10;icc.rti_pipes=2;"
                                    "workload.group_size=8;workload.shadow_group_size=4,"));
    EXPECT_THAT(lines[1], HasSubstr("," + pipes["config_hash"].get<std::string>() + "," +
                                    pipes["workload_hash"].get<std::string>()));
}

TEST_F(Provenance, WorkloadHashIsTheSameFromATraceFileAndForEitherTraceUnderBoth) {
    const std::vector<std::string> scene = {"--set", "image.width=16", "--set", "image.height=16", "--set",
                                            "groups.size=8", "--set", "groups.shadow_size=4"};
    ASSERT_EQ(run(plus(plus({"trace", "-q", "-o", "any.trace"}, scene), {})).code, 0);
    ASSERT_EQ(run(plus(plus({"trace", "-q", "-o", "both.trace", "--triangle-select", "both"}, scene), {})).code, 0);
    auto hash = [&](const std::vector<std::string>& args) {
        const RunResult r = run(plus(plus({"simulate", "-q", "--json", "h.json"}, args), {}));
        EXPECT_EQ(r.code, 0) << r.err;
        return nlohmann::json::parse(slurp(dir / "h.json"))["workload_hash"].get<std::string>();
    };
    const std::string from_scene = hash(scene);
    EXPECT_EQ(hash({"--trace", "any.trace"}), from_scene);
    const std::string both = hash({"--trace", "both.trace", "--set", "icc.triangle_select=both"});
    EXPECT_EQ(hash({"--trace", "any.trace", "--set", "icc.triangle_select=both"}), both);
    EXPECT_NE(both, from_scene) << "under `any` the pair-less spheres are part of the workload";
}

// A result describes the run that happened (docs/BAD_INPUT.md, "Rules"): the
// same 8x8 workload simulated from a trace with the config following it, from
// the trace with the config naming 8, and from the scene, gives one config
// hash, one area and the group sizes in the JSON and the CSV.
TEST_F(Provenance, ResultsReportTheWorkloadSimulatedWhicheverPathItCameBy) {
    const std::vector<std::string> scene = {"--set", "image.width=16", "--set", "image.height=16", "--set",
                                            "groups.size=8", "--set", "groups.shadow_size=4"};
    ASSERT_EQ(run(plus({"trace", "-q", "-o", "g8.trace"}, scene)).code, 0);
    auto sim = [&](const std::vector<std::string>& args, const std::string& name) {
        const RunResult r = run(plus(plus({"simulate", "-q", "--config", "paper", "--iccs", "2", "--json",
                                           name + ".json", "--csv", name + ".csv"},
                                          args),
                                     {}));
        EXPECT_EQ(r.code, 0) << r.err;
        const auto table = parse_csv(slurp(dir / (name + ".csv")));  // header, then the row
        std::map<std::string, std::string> row;
        EXPECT_EQ(table.size(), 2u);
        for (std::size_t c = 0; table.size() == 2 && c < table[0].size() && c < table[1].size(); ++c)
            row[table[0][c]] = table[1][c];
        return std::make_pair(nlohmann::json::parse(slurp(dir / (name + ".json"))), row);
    };
    const auto [follow, follow_csv] =
        sim({"--trace", "g8.trace", "--set", "workload.group_size=0", "--set", "workload.shadow_group_size=0"}, "follow");
    const auto [named, named_csv] =
        sim({"--trace", "g8.trace", "--set", "workload.group_size=8", "--set", "workload.shadow_group_size=4"}, "named");
    const auto [from_scene, scene_csv] = sim(plus(scene, {"--set", "workload.group_size=0", "--set",
                                                          "workload.shadow_group_size=0"}),
                                             "scene");
    for (const auto* j : {&follow, &named, &from_scene}) {
        EXPECT_EQ((*j)["resolved_config"]["workload.group_size"], 8);
        EXPECT_EQ((*j)["resolved_config"]["workload.shadow_group_size"], 4);
        EXPECT_EQ((*j)["overrides"]["workload.group_size"], 8) << "paper.toml says 16";
        EXPECT_EQ((*j)["group_size"], 8);
        EXPECT_EQ((*j)["shadow_group_size"], 4);
        EXPECT_EQ((*j)["config_hash"], named["config_hash"]);
        EXPECT_EQ((*j)["area"]["total"], named["area"]["total"]);
        EXPECT_EQ((*j)["total_cycles"], named["total_cycles"]);
    }
    for (const auto* row : {&follow_csv, &named_csv, &scene_csv}) {
        EXPECT_EQ(row->at("group_size"), "8");
        EXPECT_EQ(row->at("shadow_group_size"), "4");
        EXPECT_EQ(row->at("triangles_per_sphere"), std::to_string(named["triangles_per_sphere"].get<int>()));
        EXPECT_EQ(row->at("config_hash"), named["config_hash"]);
    }
    // The paper machine's own 16x16 groups are another run: another hash.
    const auto [sixteen, sixteen_csv] = sim({"--set", "image.width=16", "--set", "image.height=16"}, "sixteen");
    EXPECT_EQ(sixteen["resolved_config"]["workload.group_size"], 16);
    EXPECT_NE(sixteen["config_hash"], named["config_hash"]);
}

// A closed room (floor, ceiling, four walls wound to face inward) with a
// table, or the same box wound to face outward (a closed object), as OBJ text.
std::string box_obj(bool inward) {
    std::ostringstream o;
    const float x0 = -5, x1 = 5, y0 = 0, y1 = 4, z0 = -4, z1 = 4;
    const float v[8][3] = {{x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1},
                           {x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1}};
    for (const auto& p : v) o << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
    // Each face as a quad wound counter-clockwise seen from outside.
    const int q[6][4] = {{1, 2, 3, 4}, {5, 8, 7, 6}, {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 8, 4}, {4, 8, 5, 1}};
    for (const auto& f : q) {
        if (inward) o << "f " << f[0] << " " << f[3] << " " << f[2] << "\nf " << f[0] << " " << f[2] << " " << f[1] << "\n";
        else o << "f " << f[0] << " " << f[1] << " " << f[2] << "\nf " << f[0] << " " << f[2] << " " << f[3] << "\n";
    }
    if (inward)  // a table top in the room, facing up
        o << "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\nf 9 12 11\nf 9 11 10\n";
    return o.str();
}

// An interior is framed from inside, lit from under its ceiling, and says so;
// camera.auto overrides the choice, and a closed object is still seen from outside.
TEST_F(Cli, AnInteriorIsFramedFromInsideWithALightThatReachesTheFloor) {
    std::ofstream(dir / "room.obj") << box_obj(true);
    std::ofstream(dir / "cube.obj") << box_obj(false);
    auto render = [&](const std::string& mesh, const std::vector<std::string>& extra) {
        const RunResult r = run(plus({"render", "--mesh", mesh, "--set", "image.width=32", "--set", "image.height=32",
                                      "--json", "r.json", "-o", "r.png"},
                                     extra));
        EXPECT_EQ(r.code, 0) << r.err;
        return std::make_pair(r.out, nlohmann::json::parse(slurp(dir / "r.json")));
    };
    const auto [room_out, room] = render("room.obj", {});
    EXPECT_THAT(room_out, HasSubstr("automatic camera: inside (the mesh encloses its centre)"));
    EXPECT_EQ(room["scene"]["camera"]["view"], "inside");
    const auto eye = room["scene"]["camera"]["eye"];
    for (int k = 0; k < 3; ++k) {
        const double lo[3] = {-5, 0, -4}, hi[3] = {5, 4, 4};
        EXPECT_GT(eye[k].get<double>(), lo[k]);
        EXPECT_LT(eye[k].get<double>(), hi[k]);
    }
    // The floor in front of the eye is lit: the lower image rows are well
    // above the ambient term (0.15 of the albedo) that a light outside leaves.
    int w = 0, h = 0;
    const std::vector<std::uint8_t> px = raplas::read_rgb8((dir / "r.png").string(), w, h);
    double lower = 0;
    for (int y = h * 3 / 4; y < h; ++y)
        for (int x = 0; x < w; ++x) lower += px[std::size_t(y * w + x) * 3 + 1];
    lower /= double(w * (h - h * 3 / 4));
    EXPECT_GT(lower, 90.0) << "the floor is dark: the light does not reach it";

    const auto [forced_out, forced] = render("room.obj", {"--set", "camera.auto=outside"});
    EXPECT_EQ(forced["scene"]["camera"]["view"], "outside");
    EXPECT_GT(forced["scene"]["camera"]["eye"][1].get<double>(), 4.0) << "from outside, above the room";
    const auto [cube_out, cube] = render("cube.obj", {});
    EXPECT_THAT(cube_out, HasSubstr("automatic camera: outside"));
    EXPECT_EQ(cube["scene"]["camera"]["view"], "outside");
}

}  // namespace
