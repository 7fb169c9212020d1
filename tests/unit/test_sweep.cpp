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
    ASSERT_EQ(lines_of(reference)[0].rfind("scene,config,iccs,fifo_depth,", 0), 0u) << lines_of(reference)[0];
    std::size_t i = 0;
    for (unsigned k : kIccs)
        for (unsigned d : kFifo) {
            SCOPED_TRACE("iccs " + std::to_string(k) + ", fifo " + std::to_string(d));
            const auto& row = rows[i++];
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
            EXPECT_EQ(row, single[0]);
        }
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
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
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

}  // namespace
