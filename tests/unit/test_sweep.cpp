// `raplas sweep` end to end: point order, agreement with separate
// `raplas simulate` runs, resume after SIGKILL, independence of --jobs, job
// lists for GNU parallel / Slurm with --merge.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "run_raplas.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

using namespace raplas_test;

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> v;
    std::string cell;
    std::istringstream in(line);
    while (std::getline(in, cell, ',')) v.push_back(cell);
    return v;
}

// The CSV as one map per row, keyed by column name.
std::vector<std::map<std::string, std::string>> parse_csv(const std::string& text) {
    const auto lines = lines_of(text);
    std::vector<std::map<std::string, std::string>> rows;
    if (lines.empty()) return rows;
    const auto header = split(lines[0]);
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const auto cells = split(lines[i]);
        std::map<std::string, std::string> row;
        for (std::size_t c = 0; c < header.size() && c < cells.size(); ++c) row[header[c]] = cells[c];
        rows.push_back(row);
    }
    return rows;
}

// A small workload: built-in scene, 16x16 pixels, 8x8 primary and 4x4 shadow groups.
const std::vector<std::string> kScene = {"--set", "image.width=16", "--set", "image.height=16",
                                         "--set", "groups.size=8",  "--set", "groups.shadow_size=4"};
const std::vector<unsigned> kIccs = {1, 2, 4};
const std::vector<unsigned> kFifo = {2, 10};

std::vector<std::string> sweep_args(const std::string& out) {
    std::vector<std::string> a{"sweep"};
    a.insert(a.end(), kScene.begin(), kScene.end());
    a.insert(a.end(), {"--iccs", "1,2,4", "--fifo", "2,10", "--out", out, "-q"});
    return a;
}

class Sweep : public TempDirTest {
protected:
    static RunResult run_in(const fs::path& where, const std::vector<std::string>& args) {
        return run_raplas(where, args);
    }
    // The CSV of an uninterrupted sweep with --jobs 2, made once per process.
    static const std::string& reference_csv() {
        static const std::string csv = [] {
            const fs::path where = make_temp_dir("raplas_sweep");
            const RunResult r = run_in(where, plus(sweep_args("ref.csv"), {"--jobs", "2"}));
            std::string text = r.code == 0 ? slurp(where / "ref.csv") : std::string();
            if (r.code != 0) std::cerr << "reference sweep failed: " << r.err;
            std::error_code ec;
            fs::remove_all(where, ec);
            return text;
        }();
        return csv;
    }
};

TEST_F(Sweep, RowsInPointOrderMatchSeparateSimulateRuns) {
    const std::string& reference = reference_csv();
    ASSERT_FALSE(reference.empty());
    const auto rows = parse_csv(reference);
    ASSERT_EQ(rows.size(), kIccs.size() * kFifo.size());
    ASSERT_EQ(lines_of(reference)[0].rfind("scene,config,overrides,iccs,fifo_depth,", 0), 0u) << lines_of(reference)[0];
    std::size_t i = 0;
    for (unsigned k : kIccs)
        for (unsigned d : kFifo) {
            SCOPED_TRACE("iccs " + std::to_string(k) + ", fifo " + std::to_string(d));
            auto row = rows[i++];
            EXPECT_EQ(row.at("scene"), "builtin");
            EXPECT_EQ(row.at("iccs"), std::to_string(k));
            EXPECT_EQ(row.at("fifo_depth"), std::to_string(d));
            EXPECT_EQ(row.at("functional_match"), "true");
            // The sweep simulates a trace; `simulate --scene` runs the front end itself.
            const RunResult r = run(plus(plus({"simulate"}, kScene), {"--iccs", std::to_string(k), "--fifo",
                                                                      std::to_string(d), "--csv", "one.csv", "-q"}));
            ASSERT_EQ(r.code, 0) << r.err;
            const auto single = parse_csv(slurp(dir / "one.csv"));
            ASSERT_EQ(single.size(), 1u);
            EXPECT_EQ(row.at("total_cycles"), single[0].at("total_cycles"));
            // The sweep adds the series' figures to simulate's columns.
            for (const char* derived : {"speedup", "efficiency", "base_iccs", "base_fifo"}) EXPECT_EQ(row.erase(derived), 1u);
            EXPECT_EQ(row, single[0]);
        }
}

TEST_F(Sweep, WorkloadHashFoldedOnceMatchesEachReadingsOwn) {
    // The sweep folds each trace's workload hash once and hands it to the
    // trace's points: under either reading it is the one a point's own run
    // folds, and the two readings' differ (the pair-less spheres count under
    // `any` alone).
    const RunResult r = run(plus(plus({"sweep"}, kScene), {"--vary", "icc.triangle_select=any,both", "--iccs", "2",
                                                           "--fifo", "10", "--out", "h.csv", "-q"}));
    ASSERT_EQ(r.code, 0) << r.err;
    const auto rows = parse_csv(slurp(dir / "h.csv"));
    ASSERT_EQ(rows.size(), 2u);
    std::size_t traces = 0;
    for (const auto& e : fs::directory_iterator(dir / "h.csv.d")) traces += e.path().extension() == ".trace";
    EXPECT_EQ(traces, 1u);  // (the trace made for `any` serves both)
    for (std::size_t i = 0; i < 2; ++i) {
        const std::string reading = i == 0 ? "any" : "both";
        EXPECT_EQ(rows[i].at("triangle_select"), reading);
        const RunResult one = run(plus(plus({"simulate"}, kScene), {"--set", "icc.triangle_select=" + reading, "--iccs",
                                                                    "2", "--fifo", "10", "--csv", "one.csv", "-q"}));
        ASSERT_EQ(one.code, 0) << one.err;
        const auto single = parse_csv(slurp(dir / "one.csv"));
        ASSERT_EQ(single.size(), 1u);
        EXPECT_EQ(rows[i].at("workload_hash"), single[0].at("workload_hash")) << reading;
        EXPECT_EQ(rows[i].at("total_cycles"), single[0].at("total_cycles")) << reading;
    }
    EXPECT_NE(rows[0].at("workload_hash"), rows[1].at("workload_hash"));
}

TEST_F(Sweep, KilledSweepResumesWithNothingLostOrDuplicated) {
    const std::string& reference = reference_csv();
    ASSERT_FALSE(reference.empty());
    const auto t0 = std::chrono::steady_clock::now();
    const fs::path wd = dir / "killed.csv.d";
    std::vector<std::string> args = plus(sweep_args("killed.csv"), {"--jobs", "1"});
    std::vector<char*> argv;
    std::string binary = RAPLAS_BINARY;
    argv.push_back(binary.data());
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        if (::chdir(dir.c_str()) != 0) ::_exit(127);
        ::execv(binary.c_str(), argv.data());
        ::_exit(127);
    }
    // Kill it (SIGKILL: no clean-up) as soon as the first point's result exists.
    bool exited = false;
    int status = 0;
    for (int i = 0; i < 6000 && !fs::exists(wd / "point-0.csv"); ++i) {
        if (::waitpid(pid, &status, WNOHANG) == pid) {
            exited = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_FALSE(exited) << "the sweep ended before its first point was written";
    ASSERT_TRUE(fs::exists(wd / "point-0.csv"));
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status));
    std::size_t finished = 0;
    for (std::size_t i = 0; i < kIccs.size() * kFifo.size(); ++i)
        finished += fs::exists(wd / ("point-" + std::to_string(i) + ".csv"));
    EXPECT_LT(finished, kIccs.size() * kFifo.size()) << "the kill came too late to test a resume";

    const RunResult r = run(plus(sweep_args("killed.csv"), {"--jobs", "1"}));
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string csv = slurp(dir / "killed.csv");
    EXPECT_EQ(csv, reference);
    const auto lines = lines_of(csv);
    EXPECT_EQ(std::set<std::string>(lines.begin(), lines.end()).size(), lines.size()) << "duplicated rows";
    // Nothing left behind by the killed processes.
    for (const auto& e : fs::directory_iterator(wd))
        EXPECT_EQ(e.path().filename().string().find("raplas-tmp"), std::string::npos) << e.path();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "[ kill test ] killed after " << finished << " of " << kIccs.size() * kFifo.size()
              << " points; kill and resume took " << s << " s\n";
}

TEST_F(Sweep, JobCountDoesNotChangeTheCsv) {
    const std::string& reference = reference_csv();  // --jobs 2
    ASSERT_FALSE(reference.empty());
    const RunResult r = run(plus(sweep_args("one.csv"), {"--jobs", "1"}));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(slurp(dir / "one.csv"), reference);
    // Three jobs over six points: an odd count splits the points differently.
    const RunResult three = run(plus(sweep_args("three.csv"), {"--jobs", "3"}));
    ASSERT_EQ(three.code, 0) << three.err;
    EXPECT_EQ(slurp(dir / "three.csv"), reference);
    // A re-run finds every point done and writes the same file.
    const RunResult again = run(plus(sweep_args("one.csv"), {"--jobs", "2"}));
    ASSERT_EQ(again.code, 0) << again.err;
    EXPECT_EQ(slurp(dir / "one.csv"), reference);
}

TEST_F(Sweep, JobListRunBySlurmStyleLinesThenMergeGivesTheSameCsv) {
    const std::string& reference = reference_csv();
    ASSERT_FALSE(reference.empty());
    const RunResult e = run(plus(sweep_args("jobs.csv"), {"--emit-jobs", "jobs.txt"}));
    ASSERT_EQ(e.code, 0) << e.err;
    const auto traces = lines_of(slurp(dir / "jobs.txt.traces"));
    const auto points = lines_of(slurp(dir / "jobs.txt"));
    EXPECT_EQ(traces.size(), 1u);
    ASSERT_EQ(points.size(), kIccs.size() * kFifo.size());
    EXPECT_FALSE(fs::exists(dir / "jobs.csv.d" / "trace-0.trace")) << "--emit-jobs must not run anything";

    // Before any point ran, --merge writes the header and reports what is missing.
    const RunResult early = run({"sweep", "--merge", "--work-dir", "jobs.csv.d", "--out", "early.csv"});
    EXPECT_EQ(early.code, 2);
    EXPECT_THAT(early.err, HasSubstr("6 of 6 points have no result"));
    EXPECT_EQ(lines_of(slurp(dir / "early.csv")).size(), 1u);

    // Each line as a Slurm array task runs it, from another directory.
    const fs::path elsewhere = dir / "node";
    fs::create_directories(elsewhere);
    auto task = [&](const std::string& file, std::size_t id) {
        const std::string cmd = "cd " + quoted(elsewhere.string()) + " && sed -n '" + std::to_string(id) + "p' " +
                                quoted((dir / file).string()) + " | sh";
        return std::system(cmd.c_str());
    };
    for (std::size_t id = 1; id <= traces.size(); ++id) ASSERT_EQ(task("jobs.txt.traces", id), 0);
    for (std::size_t id = points.size(); id >= 1; --id) ASSERT_EQ(task("jobs.txt", id), 0);  // any order

    const RunResult m = run({"sweep", "--merge", "--work-dir", "jobs.csv.d", "--out", "merged.csv"});
    ASSERT_EQ(m.code, 0) << m.err;
    EXPECT_EQ(slurp(dir / "merged.csv"), reference);
    // A normal run on the same work dir finds everything done.
    const RunResult r = run(sweep_args("jobs.csv"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(slurp(dir / "jobs.csv"), reference);
}

TEST_F(Sweep, RefusesAnotherSweepInTheSameWorkDir) {
    ASSERT_EQ(run({"sweep", "--iccs", "1", "--out", "a.csv", "--emit-jobs", "jobs"}).code, 0);
    const RunResult r = run({"sweep", "--iccs", "2", "--out", "a.csv", "--emit-jobs", "jobs"});
    EXPECT_EQ(r.code, 2);
    EXPECT_THAT(r.err, HasSubstr("sweep.json: the work dir holds a different sweep (iccs [1] there, [2] here)"));
    EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
    const RunResult bad = run({"sweep", "--iccs", "4,4", "--out", "b.csv"});
    EXPECT_EQ(bad.code, 2);
    EXPECT_THAT(bad.err, HasSubstr("--iccs: 4 is given twice"));
}

TEST_F(Sweep, FailingTraceIsReportedAndTheOtherPointsFinish) {
    std::ofstream(dir / "bad.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 9\n";
    std::ofstream(dir / "mini.toml") << "name = \"mini\"\n[image]\nwidth = 16\nheight = 16\n"
                                        "[groups]\nsize = 8\nshadow_size = 4\n";
    // Inputs in command-line order: the broken mesh is input 0, the scene input 1.
    const RunResult r =
        run({"sweep", "--mesh", "bad.obj", "--scene", "mini.toml", "--iccs", "1,2", "--out", "f.csv", "-q"});
    EXPECT_EQ(r.code, 2);
    EXPECT_THAT(r.err, HasSubstr("trace --mesh bad.obj"));
    EXPECT_THAT(r.err, HasSubstr("bad.obj:3:"));
    EXPECT_THAT(r.err, HasSubstr("2 of 4 points failed"));
    const auto rows = parse_csv(slurp(dir / "f.csv"));
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].at("scene"), "mini");
    EXPECT_EQ(rows[0].at("iccs"), "1");
    EXPECT_EQ(rows[1].at("iccs"), "2");
    EXPECT_TRUE(fs::exists(dir / "f.csv.d" / "point-2.csv"));
    EXPECT_FALSE(fs::exists(dir / "f.csv.d" / "point-0.csv"));
}

// ---- --vary, derived figures, reference tables ---------------------------------

double num(const std::map<std::string, std::string>& row, const std::string& col) { return std::stod(row.at(col)); }

// A config key and a scene key varied: 2 x 2 combinations x 2 ICC counts.
std::vector<std::string> vary_args(const std::string& out, const std::string& iccs = "1,2") {
    return {"sweep", "--set", "image.width=16", "--set", "image.height=16", "--set", "groups.size=8",
            "--vary", "icc.rti_pipes=1..2", "--vary", "groups.shadow_size=2,4", "--iccs", iccs, "--fifo", "10",
            "--out", out, "-q"};
}

TEST_F(Sweep, VaryIsACrossProductWhosePointsShareTracesAndMatchSimulate) {
    const RunResult r = run(vary_args("v.csv"));
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string text = slurp(dir / "v.csv");
    EXPECT_EQ(lines_of(text)[0].rfind("scene,config,icc.rti_pipes,groups.shadow_size,overrides,iccs,", 0), 0u)
        << lines_of(text)[0];
    const auto rows = parse_csv(text);
    ASSERT_EQ(rows.size(), 8u);
    // The scene key changes the workload, the config key does not: two traces.
    std::size_t traces = 0;
    for (const auto& e : fs::directory_iterator(dir / "v.csv.d")) traces += e.path().extension() == ".trace";
    EXPECT_EQ(traces, 2u);
    std::size_t i = 0;
    std::set<std::string> workloads, configs;
    for (const char* pipes : {"1", "2"})
        for (const char* shadow : {"2", "4"})
            for (const char* k : {"1", "2"}) {
                SCOPED_TRACE(std::string("rti_pipes ") + pipes + ", shadow_size " + shadow + ", iccs " + k);
                auto row = rows[i++];
                EXPECT_EQ(row.at("icc.rti_pipes"), pipes);
                EXPECT_EQ(row.at("groups.shadow_size"), shadow);
                EXPECT_EQ(row.at("iccs"), k);
                workloads.insert(row.at("workload_hash"));
                configs.insert(row.at("config_hash"));
                // The overridden config keys are named; the scene key is the workload's.
                if (std::string(pipes) == "2") EXPECT_THAT(row.at("overrides"), HasSubstr("icc.rti_pipes=2"));
                else EXPECT_THAT(row.at("overrides"), Not(HasSubstr("icc.rti_pipes"))) << "1 is the default";
                const RunResult one = run({"simulate", "--set", "image.width=16", "--set", "image.height=16", "--set",
                                           "groups.size=8", "--set", std::string("groups.shadow_size=") + shadow,
                                           "--set", std::string("icc.rti_pipes=") + pipes, "--iccs", k, "--fifo",
                                           "10", "--csv", "one.csv", "-q"});
                ASSERT_EQ(one.code, 0) << one.err;
                const auto single = parse_csv(slurp(dir / "one.csv"));
                ASSERT_EQ(single.size(), 1u);
                for (const char* extra :
                     {"icc.rti_pipes", "groups.shadow_size", "speedup", "efficiency", "base_iccs", "base_fifo"})
                    EXPECT_EQ(row.erase(extra), 1u) << extra;
                EXPECT_EQ(row, single[0]);
            }
    EXPECT_EQ(workloads.size(), 2u);
    // rti_pipes x iccs x shadow group size: a result's config reports the
    // workload it simulated (workload.shadow_group_size = 0 follows the scene).
    EXPECT_EQ(configs.size(), 8u);
    // --merge rebuilds the same table from the work dir alone (the varied keys come from sweep.json).
    const RunResult m = run({"sweep", "--merge", "--work-dir", "v.csv.d", "--out", "merged.csv", "-q"});
    ASSERT_EQ(m.code, 0) << m.err;
    EXPECT_EQ(slurp(dir / "merged.csv"), text);
}

TEST_F(Sweep, VaryRefusesWhatCannotBeSwept) {
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"--vary", "icc.rti_pipes=0..2"}, "--vary icc.rti_pipes: config key 'icc.rti_pipes' = 0 is out of range [1, 64]"},
        {{"--vary", "icc.rti_pipes=3..1"}, "--vary icc.rti_pipes: range 3..1 is empty"},
        {{"--vary", "icc.rti_pipes=1,2,1"}, "--vary icc.rti_pipes: value 1 is given twice"},
        {{"--vary", "icc.rti_pipes=1,,2"}, "--vary icc.rti_pipes: empty value"},
        {{"--vary", "icc.rti_pipes"}, "expected KEY=V1,V2,... or KEY=A..B"},
        {{"--vary", "machine.iccs=1,2"}, "give the ICC counts with --iccs"},
        {{"--vary", "fifo.sphere_depth=1,2", "--fifo", "10"}, "--fifo sets it for every point"},
        {{"--vary", "icc.rti_pipes=1,2", "--set", "icc.rti_pipes=3"}, "also given with --set"},
        {{"--vary", "icc.rti_pipes=1,2", "--vary", "icc.rti_pipes=3"}, "given twice"},
        {{"--vary", "icc.triangle_select=any,some"}, "is not one of: both, any"},
        {{"--vary", "icc.rti_pipes=1,2", "--normalize", "icc.rti_pipes=3"}, "--normalize icc.rti_pipes: 3 is not one of"},
        {{"--normalize", "icc.psi_pipes=8"}, "--normalize icc.psi_pipes: not a varied key"},
        {{"--iccs", "1,2", "--base-iccs", "4"}, "--base-iccs 4: not one of the sweep's --iccs"},
        {{"--check", "ref.csv", "--tolerance", "total_cycles=-1"}, "--tolerance total_cycles: '-1' is not a relative tolerance"},
    };
    for (const auto& [args, message] : cases) {
        SCOPED_TRACE(::testing::PrintToString(args));
        const RunResult r = run(plus(plus({"sweep", "--out", "x.csv"}, args), {"-q"}));
        EXPECT_EQ(r.code, 2);
        EXPECT_THAT(r.err, HasSubstr(message));
        EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
        EXPECT_FALSE(fs::exists(dir / "x.csv.d")) << "a refused sweep must leave nothing";
    }
}

TEST_F(Sweep, SpeedupAndEfficiencyAreRelativeToTheBaseOfEachSeries) {
    const auto base_args = vary_args("d.csv", "1,2,3");
    const RunResult r = run(plus(base_args, {"--normalize", "icc.rti_pipes=1"}));
    ASSERT_EQ(r.code, 0) << r.err;
    const auto rows = parse_csv(slurp(dir / "d.csv"));
    ASSERT_EQ(rows.size(), 12u);
    // Rows of one series are consecutive (ICC count varies fastest but one, FIFO depth fixed).
    for (std::size_t s = 0; s < 4; ++s) {
        const auto& base = rows[3 * s];
        EXPECT_EQ(base.at("iccs"), "1");
        for (std::size_t j = 0; j < 3; ++j) {
            const auto& row = rows[3 * s + j];
            const double speedup = num(base, "total_cycles") / num(row, "total_cycles");
            EXPECT_NEAR(num(row, "speedup"), speedup, 1e-9 * speedup);
            EXPECT_NEAR(num(row, "efficiency"), speedup / num(row, "iccs"), 1e-9);
            EXPECT_EQ(row.at("base_iccs"), "1");
            // area x time over the rti_pipes = 1 point with everything else equal
            const auto& ref = rows[(s % 2) * 3 + j];
            EXPECT_EQ(ref.at("icc.rti_pipes"), "1");
            EXPECT_EQ(ref.at("groups.shadow_size"), row.at("groups.shadow_size"));
            EXPECT_NEAR(num(row, "area_time_normalized"), num(row, "area_time") / num(ref, "area_time"), 1e-9);
        }
    }
    EXPECT_GT(num(rows[2], "speedup"), 1.5) << "three ICCs should be well ahead of one";
    // Another base: the same work dir, every point done; only the derived columns move.
    const RunResult b = run(plus(vary_args("d2.csv", "1,2,3"), {"--base-iccs", "2", "--work-dir", "d.csv.d"}));
    ASSERT_EQ(b.code, 0) << b.err;
    const auto rows2 = parse_csv(slurp(dir / "d2.csv"));
    ASSERT_EQ(rows2.size(), 12u);
    for (std::size_t i = 0; i < 12; ++i) {
        const auto& base = rows2[i / 3 * 3 + 1];
        EXPECT_EQ(rows2[i].at("total_cycles"), rows[i].at("total_cycles"));
        EXPECT_EQ(rows2[i].at("base_iccs"), "2");
        const double speedup = num(base, "total_cycles") / num(rows2[i], "total_cycles");
        EXPECT_NEAR(num(rows2[i], "speedup"), speedup, 1e-9 * speedup);
        EXPECT_NEAR(num(rows2[i], "efficiency"), speedup * 2 / num(rows2[i], "iccs"), 1e-9);
        EXPECT_EQ(rows2[i].count("area_time_normalized"), 0u);
    }
}

TEST_F(Sweep, ReferenceTablesUpdateCheckAndShowEveryDifference) {
    const auto args = plus(sweep_args("c.csv"), {"--jobs", "2"});
    const RunResult u = run(plus(args, {"--update", "ref.csv"}));
    ASSERT_EQ(u.code, 0) << u.err;
    const std::string ref = slurp(dir / "ref.csv");
    const auto ref_lines = lines_of(ref);
    ASSERT_GE(ref_lines.size(), 3u);
    EXPECT_EQ(ref_lines[0].rfind("# generated by: raplas sweep ", 0), 0u) << ref_lines[0];
    EXPECT_THAT(ref_lines[0], HasSubstr("--update ref.csv"));
    EXPECT_EQ(ref.substr(ref.find("\nscene,") + 1), slurp(dir / "c.csv")) << "the table is the result CSV";

    // Equal: exit 0.
    const RunResult same = run(plus(args, {"--check", "ref.csv"}));
    EXPECT_EQ(same.code, 0) << same.err;

    // One cell changed, one row removed, one row added (a copy with another ICC count).
    std::vector<std::string> lines = ref_lines;
    const auto header = split(lines[2]);
    const std::size_t cyc = std::find(header.begin(), header.end(), "total_cycles") - header.begin();
    const std::size_t iccs = std::find(header.begin(), header.end(), "iccs") - header.begin();
    auto cells = split(lines[3]);
    const std::string old_cycles = cells[cyc];
    cells[cyc] = std::to_string(std::stoull(old_cycles) + 1000);
    auto join = [](const std::vector<std::string>& v) {
        std::string s;
        for (const auto& c : v) s += (s.empty() ? "" : ",") + c;
        return s;
    };
    lines[3] = join(cells);
    auto extra = split(lines[4]);
    extra[iccs] = "99";
    const std::string removed = lines[5];
    lines.erase(lines.begin() + 5);
    lines.push_back(join(extra));
    std::string edited;
    for (const auto& l : lines) edited += l + "\n";
    std::ofstream(dir / "edited.csv") << edited;
    const RunResult diff = run(plus(args, {"--check", "edited.csv"}));
    EXPECT_EQ(diff.code, 1) << diff.err;
    EXPECT_THAT(diff.err, HasSubstr("edited.csv: the sweep differs from the reference table (3 differences"));
    EXPECT_THAT(diff.out, HasSubstr("scene=builtin iccs=1 fifo_depth=2: total_cycles " + old_cycles + " (reference " +
                                    cells[cyc] + ", "));
    EXPECT_THAT(diff.out, HasSubstr("iccs=99 fifo_depth=10: row only in the reference"));
    const auto removed_cells = split(removed);
    EXPECT_THAT(diff.out, HasSubstr("iccs=" + removed_cells[iccs] + " fifo_depth=" +
                                    removed_cells[std::find(header.begin(), header.end(), "fifo_depth") - header.begin()] +
                                    ": row not in the reference"));
    // A tolerance covers the changed cell, not the rows.
    const RunResult tol = run(plus(args, {"--check", "edited.csv", "--tolerance", "total_cycles=0.5",
                                          "--tolerance", "speedup=0.5", "--tolerance", "efficiency=0.5",
                                          "--tolerance", "time_ms=0.5", "--tolerance", "area_time=0.5",
                                          "--tolerance", "triangle_link_avg_gbps=0.5", "--tolerance",
                                          "rti_utilisation=0.5"}));
    EXPECT_EQ(tol.code, 1);
    EXPECT_THAT(tol.err, HasSubstr("(2 differences"));
    EXPECT_THAT(tol.out, Not(HasSubstr("total_cycles")));

    // Not a table of this sweep, or not a table: exit 2, one line.
    std::ofstream(dir / "quotes.csv") << "scene,iccs\n\"builtin,1\n";
    std::ofstream(dir / "ragged.csv") << "scene,iccs,fifo_depth\nbuiltin,1\n";
    std::ofstream(dir / "nokey.csv") << "scene,iccs\nbuiltin,1\n";
    for (const auto& [file, message] : std::vector<std::pair<std::string, std::string>>{
             {"quotes.csv", "quotes.csv:2: not a CSV table (a quote out of place, or a quoted cell not closed)"},
             {"ragged.csv", "ragged.csv:2: 2 cells, but the header has 3 columns"},
             {"nokey.csv", "nokey.csv: no column 'fifo_depth'"},
             {"missing.csv", "missing.csv: cannot open reference table: No such file or directory"}}) {
        const RunResult bad = run(plus(args, {"--check", file}));
        EXPECT_EQ(bad.code, 2) << file;
        EXPECT_THAT(bad.err, HasSubstr(message));
        EXPECT_EQ(lines_of(bad.err).size(), 1u) << bad.err;
    }
}

}  // namespace

namespace {

// --find against a full sweep of the same points: the value it gives is the
// smallest that meets the target there, and the one below it does not.
std::map<std::string, double> column_by(const std::vector<std::map<std::string, std::string>>& rows,
                                        const std::string& key, const std::string& value_col,
                                        const std::string& where_col = "", const std::string& where = "") {
    std::map<std::string, double> m;
    for (const auto& r : rows)
        if (where_col.empty() || r.at(where_col) == where) m[r.at(key)] = std::stod(r.at(value_col));
    return m;
}

const std::vector<std::string> kTiny = {"--set", "image.width=16", "--set", "image.height=16"};

}  // namespace

TEST_F(Sweep, FindGivesTheSmallestFifoDepthAFullSweepGives) {
    const RunResult r = run(plus(plus({"sweep", "-q", "--iccs", "1,4", "--find", "fifo", "--target", "efficiency>=0.57",
                                       "--out", "find.csv"},
                                      kTiny),
                                 {}));
    ASSERT_EQ(r.code, 0) << r.err;
    std::string fifos;
    for (int d = 1; d <= 16; ++d) fifos += (d > 1 ? "," : "") + std::to_string(d);
    const RunResult full = run(plus(plus({"sweep", "-q", "--iccs", "1,4", "--fifo", fifos, "--out", "full.csv"}, kTiny), {}));
    ASSERT_EQ(full.code, 0) << full.err;
    const auto eff = column_by(parse_csv(slurp(dir / "full.csv")), "fifo_depth", "efficiency", "iccs", "4");
    int smallest = 0;
    for (int d = 16; d >= 1; --d)
        if (eff.at(std::to_string(d)) >= 0.57) smallest = d;
        else break;
    ASSERT_GT(smallest, 1) << "the target is met at every depth: no search to test";
    // What --find wrote: the comment line names the answer, the rows the points it visited.
    const std::string text = slurp(dir / "find.csv");
    EXPECT_THAT(text, HasSubstr(": fifo = " + std::to_string(smallest) + "\n")) << text.substr(0, 200);
    std::string body;
    for (const auto& line : lines_of(text))
        if (line.rfind("#", 0) != 0) body += line + "\n";
    bool below = false;
    for (const auto& row : parse_csv(body)) {
        const int v = std::stoi(row.at("find_value"));
        EXPECT_EQ(row.at("find_meets") == "true", v >= smallest) << "fifo " << v;
        if (row.at("iccs") == "4") {
            EXPECT_EQ(std::stod(row.at("efficiency")), eff.at(std::to_string(v))) << "fifo " << v;
        }
        below = below || v == smallest - 1;
    }
    EXPECT_TRUE(below) << "the bracket's lower end was visited";
    // A target no depth meets stops at the closed-form limit of deep FIFOs, exit 1.
    const RunResult never = run(plus(plus({"sweep", "-q", "--iccs", "1,4", "--find", "fifo", "--target",
                                           "efficiency>=0.99", "--out", "never.csv"},
                                          kTiny),
                                     {}));
    EXPECT_EQ(never.code, 1) << never.err;
    EXPECT_THAT(never.err, HasSubstr("no FIFO depth meets efficiency>=0.99: with FIFOs unbounded"));
}

TEST_F(Sweep, FindGivesTheCrossoverWithTheSharedMemoryAFullSweepGives) {
    const RunResult r = run(plus(plus({"sweep", "-q", "--find", "iccs", "--target", "speedup_vs=shared>=1", "--out",
                                       "cross.csv"},
                                      kTiny),
                                 {}));
    ASSERT_EQ(r.code, 0) << r.err;
    std::string iccs;
    for (int k = 1; k <= 40; ++k) iccs += (k > 1 ? "," : "") + std::to_string(k);
    const RunResult full = run(plus(plus({"sweep", "-q", "--jobs", "2", "--iccs", iccs, "--vary",
                                          "memory.system=streaming,shared", "--out", "full.csv"},
                                         kTiny),
                                    {}));
    ASSERT_EQ(full.code, 0) << full.err;
    const auto rows = parse_csv(slurp(dir / "full.csv"));
    const auto streaming = column_by(rows, "iccs", "total_cycles", "memory.system", "streaming");
    const auto shared = column_by(rows, "iccs", "total_cycles", "memory.system", "shared");
    int crossover = 0;
    for (int k = 1; k <= 40 && !crossover; ++k)
        if (shared.at(std::to_string(k)) >= streaming.at(std::to_string(k))) crossover = k;
    ASSERT_GT(crossover, 1) << "no crossover within 40 ICCs to test";
    EXPECT_THAT(slurp(dir / "cross.csv"), HasSubstr(": iccs = " + std::to_string(crossover) + "\n"));
}

TEST_F(Sweep, FindRefusesWhatItCannotSearch) {
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"--find", "fifo", "--target", "efficiency>0.9"}, "expected METRIC>=VALUE or METRIC<=VALUE"},
        {{"--find", "fifo", "--target", "colour>=1"}, "unknown METRIC 'colour'"},
        {{"--find", "fifo", "--target", "efficiency>=high"}, "'high' is not a number"},
        {{"--find", "icc.triangle_select", "--target", "efficiency>=0.9"}, "not fifo, iccs or an integer config key"},
        {{"--find", "fifo", "--fifo", "10", "--target", "efficiency>=0.9"}, "give no --fifo"},
        {{"--find", "fifo"}, "--find KEY and --target METRIC>=VALUE go together"},
    };
    for (const auto& [extra, needle] : cases) {
        const RunResult r = run(plus(plus({"sweep", "--out", "x.csv"}, kTiny), extra));
        EXPECT_EQ(r.code, 2) << needle;
        EXPECT_THAT(r.err, HasSubstr(needle));
        EXPECT_FALSE(fs::exists(dir / "x.csv")) << needle;
    }
}

// A table of one engine checks against another's when every figure is equal
// (config_hash leaves the engine out, --check the engine column), and still
// fails on a differing figure; a baseline row says its answers were not checked.
TEST_F(Sweep, CheckAcrossEnginesPassesWhenEveryFigureIsEqual) {
    const std::vector<std::string> base = plus(
        {"sweep", "-q", "--iccs", "1,2", "--fifo", "4", "--vary", "memory.system=streaming,shared"}, kTiny);
    const RunResult ref = run(plus(base, {"--out", "event.csv", "--update", "ref.csv"}));
    ASSERT_EQ(ref.code, 0) << ref.err;
    const RunResult net = run(plus(base, {"--set", "sim.mode=netlist", "--out", "netlist.csv", "--check", "ref.csv"}));
    EXPECT_EQ(net.code, 0) << net.out << net.err;
    const auto rows = parse_csv(slurp(dir / "netlist.csv"));
    ASSERT_EQ(rows.size(), 4u);
    for (const auto& r : rows) {
        EXPECT_EQ(r.at("engine"), "netlist");
        const bool streaming = r.at("memory.system") == "streaming";
        EXPECT_EQ(r.at("functional_checked"), streaming ? "true" : "false") << "a baseline checks no answer";
    }
    // One figure changed in the reference: the check fails, naming it.
    std::string text = slurp(dir / "ref.csv");
    const std::string cycles = parse_csv(slurp(dir / "event.csv"))[0].at("total_cycles");
    const std::size_t at = text.find("," + cycles + ",");
    ASSERT_NE(at, std::string::npos);
    text.replace(at + 1, cycles.size(), std::to_string(std::stoull(cycles) + 1));
    std::ofstream(dir / "ref2.csv") << text;
    const RunResult off = run(plus(base, {"--set", "sim.mode=netlist", "--out", "netlist2.csv", "--check", "ref2.csv"}));
    EXPECT_EQ(off.code, 1);
    EXPECT_THAT(off.out, HasSubstr("total_cycles " + cycles));
}
