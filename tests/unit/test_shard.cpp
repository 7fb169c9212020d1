// One simulation sharded across processes (docs/SHARDING.md): the shards'
// partial results merged equal the unsharded run, JSON (but for `wall`) and
// CSV byte for byte, for every shard count (one, some that do not divide the
// passes, more than the passes), in the event and netlist modes and under
// fifo_bound, under both Triangle Selector readings, with an injected
// mismatch; a wrong merge is refused and writes nothing; the emitted job
// lists run line by line as a Slurm array would and merge to the same run.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "run_in_child.hpp"
#include "run_raplas.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::HasSubstr;
using namespace raplas_test;

// The built-in scene at 16x16 pixels in 8x8 primary and shadow groups.
const std::vector<std::string> kShardScene = {"--set", "image.width=16", "--set", "image.height=16",
                                         "--set", "groups.size=8",  "--set", "groups.shadow_size=8"};

json load(const fs::path& p) { return json::parse(slurp(p)); }

// The result without its wall-clock figures, as its own text.
std::string without_wall(json j) {
    j.erase("wall");
    return j.dump(2);
}

// Where two results differ but for `wall`: the first operations of a JSON
// patch from a to b ("[]" when they are the same).
std::string differences(json a, json b) {
    a.erase("wall");
    b.erase("wall");
    json patch = json::diff(a, b);
    if (patch.size() > 8) patch.erase(patch.begin() + 8, patch.end());
    return patch.dump();
}

class Shard : public TempDirTest {
protected:
    // The workload as a trace file, made once per test.
    void SetUp() override {
        TempDirTest::SetUp();
        const Outcome t = fork_raplas(plus({"trace", "-q", "-o", "t.trace"}, kShardScene));
        ASSERT_EQ(t.code, 0) << t.err;
    }
    // raplas in a forked child, in `dir` (fast: no executable to load).
    Outcome fork_raplas(const std::vector<std::string>& args) const { return run_in_child(dir, args); }

    // simulate `args` whole and in `n` shards merged, for each n; the merge
    // must equal the whole run. `expect_code`: the whole run's exit code
    // (1: a functional mismatch, which one shard and the merge report too).
    // Returns the whole run's pass count.
    std::uint64_t expect_shards_add_up(const std::vector<std::string>& args, std::vector<std::uint32_t> counts,
                                       int expect_code = 0, std::uint32_t beyond_passes = 0) {
        const Outcome w = fork_raplas(plus(plus({"simulate"}, args), {"--json", "whole.json", "--csv", "whole.csv", "-q"}));
        EXPECT_EQ(w.code, expect_code) << w.err;
        const json whole = load(dir / "whole.json");
        const std::uint64_t passes = whole.at("passes").get<std::uint64_t>();
        if (beyond_passes) counts.push_back(std::uint32_t(passes) + beyond_passes);
        for (const std::uint32_t n : counts) {
            SCOPED_TRACE(std::to_string(n) + " shards of " + std::to_string(passes) + " passes");
            std::vector<std::string> parts;
            int failed = 0;
            std::uint64_t simulated = 0;
            for (std::uint32_t i = 0; i < n; ++i) {
                const std::string part = "part-" + std::to_string(i) + ".json";
                const std::string spec = std::to_string(i) + "/" + std::to_string(n);
                const Outcome s = fork_raplas(plus(plus({"simulate"}, args), {"--shard", spec, "--json", part, "-q"}));
                failed += s.code != 0;
                EXPECT_TRUE(s.code == 0 || (s.code == 1 && expect_code == 1)) << s.err;
                const json p = load(dir / part);
                EXPECT_EQ(p.at("shard"), i);
                EXPECT_EQ(p.at("shards"), n);
                EXPECT_EQ(p.at("passes"), passes);
                std::vector<std::uint64_t> mine;
                for (std::uint64_t k = i; k < passes; k += n) mine.push_back(k);
                EXPECT_EQ(p.at("result").at("pass_index").get<std::vector<std::uint64_t>>(), mine);
                simulated += mine.size();
                // Any order will do: odd counts are given last shard first.
                parts.insert(n % 2 ? parts.begin() : parts.end(), part);
            }
            EXPECT_EQ(simulated, passes);
            EXPECT_EQ(failed, expect_code == 1 ? 1 : 0) << "the mismatch is in exactly one shard";
            const Outcome m = fork_raplas(plus(plus({"merge"}, parts), {"--json", "merged.json", "--csv", "merged.csv"}));
            EXPECT_EQ(m.code, expect_code) << m.err;
            EXPECT_EQ(m.err, w.err) << "the merge reports a mismatch as the whole run does";
            const json merged = load(dir / "merged.json");
            EXPECT_EQ(differences(whole, merged), "[]");
            EXPECT_TRUE(without_wall(merged) == without_wall(whole)) << "the same values, but not the same text";
            EXPECT_EQ(slurp(dir / "merged.csv"), slurp(dir / "whole.csv"));
            EXPECT_EQ(merged.at("wall").at("shards"), n);
            EXPECT_THAT(m.out, HasSubstr("merged " + std::to_string(n) + " shards (" + std::to_string(passes) + " passes)"));
            for (const auto& p : parts) fs::remove(dir / p);
        }
        return passes;
    }
};

TEST_F(Shard, EventModeEveryShardCountAddsUpToTheWholeRun) {
    // 3 ICCs and FIFO depth 4: a last pass of the primary groups that is not
    // full, link stalls, and per-ICC maxima; 74 passes, which 4 and 7 do not divide.
    const std::uint64_t passes = expect_shards_add_up(
        {"--trace", "t.trace", "--iccs", "3", "--fifo", "4", "--set", "host.pass_overhead_cycles=7"}, {1, 2, 3, 4, 7});
    EXPECT_EQ(passes, 74u);
}

TEST_F(Shard, MoreShardsThanPassesLeaveSomeEmpty) {
    const std::uint64_t passes = expect_shards_add_up({"--trace", "t.trace", "--iccs", "16", "--fifo", "4"}, {}, 0, 3);
    EXPECT_EQ(passes, 15u);
}

TEST_F(Shard, CycleModeAddsUpToTheWholeRun) {
    expect_shards_add_up({"--trace", "t.trace", "--iccs", "3", "--fifo", "4", "--set", "sim.mode=netlist"}, {2, 3});
}

TEST_F(Shard, FifoBoundAddsUpToTheWholeRun) {
    expect_shards_add_up({"--trace", "t.trace", "--iccs", "3", "--fifo", "4", "--set", "sim.estimate=fifo_bound"}, {1, 3, 7});
}

TEST_F(Shard, BothReadingFromTheSceneAddsUpToTheWholeRun) {
    // The scene itself: every shard runs the same front end.
    expect_shards_add_up(plus(kShardScene, {"--iccs", "3", "--fifo", "4", "--set", "icc.triangle_select=both"}), {2, 5});
}

TEST_F(Shard, InjectedMismatchIsTheWholeRunsOne) {
    // sim.fault = wrong_rti gives the run one wrong answer: the shard that
    // holds the pass where it fires reports it, the others do not fire it.
    expect_shards_add_up({"--trace", "t.trace", "--iccs", "2", "--set", "sim.fault=wrong_rti", "--set", "sim.fault_icc=1"},
                         {2, 3}, 1);
}

TEST_F(Shard, MergeKeepsTheEarliestMismatchAndAddsTheirCounts) {
    const std::vector<std::string> args{"simulate", "--trace", "t.trace", "--iccs", "2", "-q"};
    for (const char* s : {"0/3", "1/3", "2/3"})
        ASSERT_EQ(fork_raplas(plus(args, {"--shard", s, "--json", std::string("p") + s[0] + ".json"})).code, 0);
    // Two shards claim a mismatch: shard 2 in group 9, shard 1 in group 4.
    auto claim = [&](const std::string& part, std::uint64_t group, std::uint64_t rays) {
        json p = load(dir / part);
        p["result"]["rays_mismatched"] = rays;
        p["result"]["first_mismatch"] = {{"group", group},
                                         {"h", 1},
                                         {"v", 2},
                                         {"model", {{"triangle", 5}, {"t", 0.5}}},
                                         {"frontend", {{"triangle", -1}, {"t", 0.0}}},
                                         {"group_primary", true},
                                         {"group_pixel", {8, 0}}};
        write(part, p.dump(2));
    };
    claim("p2.json", 9, 1);
    claim("p1.json", 4, 2);
    const Outcome m = fork_raplas({"merge", "p2.json", "p0.json", "p1.json", "--json", "m.json", "-q"});
    EXPECT_EQ(m.code, 1);
    EXPECT_THAT(m.err, HasSubstr("raplas: error: functional mismatch: 3 of "));
    EXPECT_THAT(m.err, HasSubstr("first: primary ray (h 1, v 2) of group 4, pixel (9, 2): model triangle 5 at t = 0.5, "
                                 "front end no hit"));
    const json j = load(dir / "m.json");
    EXPECT_EQ(j.at("first_mismatch").at("group"), 4);
    EXPECT_EQ(j.at("rays_mismatched"), 3);
    EXPECT_EQ(j.at("functional_match"), false);
}

TEST_F(Shard, WrongMergeIsRefusedAndWritesNothing) {
    const std::vector<std::string> args{"simulate", "--trace", "t.trace", "--iccs", "2", "-q"};
    ASSERT_EQ(fork_raplas(plus(args, {"--shard", "0/2", "--json", "p0.json"})).code, 0);
    ASSERT_EQ(fork_raplas(plus(args, {"--shard", "1/2", "--json", "p1.json"})).code, 0);
    ASSERT_EQ(fork_raplas(plus(args, {"--fifo", "5", "--shard", "1/2", "--json", "f1.json"})).code, 0);
    const json good = load(dir / "p1.json");
    auto refused = [&](const std::vector<std::string>& parts, const std::string& why) {
        SCOPED_TRACE(why);
        const Outcome m = fork_raplas(plus(plus({"merge"}, parts), {"--json", "out.json", "--csv", "out.csv"}));
        EXPECT_EQ(m.code, 2);
        EXPECT_THAT(m.err, HasSubstr(why));
        EXPECT_EQ(lines_of(m.err).size(), 1u) << m.err;
        EXPECT_FALSE(fs::exists(dir / "out.json"));
        EXPECT_FALSE(fs::exists(dir / "out.csv"));
    };
    // Every shard index once, but of two machine configs.
    refused({"p0.json", "f1.json"}, "f1.json: another machine config (config_hash ");
    // Edited parts.
    json p = good;
    p["result"]["pass_index"][0] = 0;
    write("e1.json", p.dump());
    refused({"p0.json", "e1.json"}, "e1.json: corrupt partial result: result.pass_index does not hold the passes of shard 1 of 2");
    p = good;
    p["result"]["iccs"][1].erase("rti.tests");
    write("e1.json", p.dump());
    refused({"p0.json", "e1.json"}, "e1.json: corrupt partial result: result.iccs[1].rti.tests is missing");
    p = good;
    p["result"]["sphere_link"]["bytes"] = -3;
    write("e1.json", p.dump());
    refused({"p0.json", "e1.json"}, "e1.json: corrupt partial result: result.sphere_link.bytes is not a count");
    json q = load(dir / "p0.json");
    std::string text = q["machine_config"].get<std::string>();
    text.replace(text.find("iccs = 2"), 8, "iccs = 3");
    q["machine_config"] = text;
    write("e0.json", q.dump());
    write("e1.json", [&] {
        json x = good;
        x["machine_config"] = text;
        return x.dump();
    }());
    refused({"e0.json", "e1.json"}, "e0.json: corrupt partial result: machine_config does not give config_hash");
    // Parts whose hash the process that fed them folded (simulate --jobs) do
    // not merge without it; the option is for shards only.
    ASSERT_EQ(fork_raplas(plus(args, {"--shard", "0/2", "--json", "h0.json", "--no-workload-hash"})).code, 0);
    ASSERT_EQ(fork_raplas(plus(args, {"--shard", "1/2", "--json", "h1.json", "--no-workload-hash"})).code, 0);
    EXPECT_EQ(load(dir / "h1.json").at("workload_hash"), "");
    refused({"h0.json", "h1.json"}, "h0.json: corrupt partial result: workload_hash is empty");
    const Outcome whole = fork_raplas(plus(args, {"--json", "w.json", "--no-workload-hash"}));
    EXPECT_EQ(whole.code, 2);
    EXPECT_THAT(whole.err, HasSubstr("--no-workload-hash is for the shards of --jobs"));
    EXPECT_FALSE(fs::exists(dir / "w.json"));
    // The good parts still merge.
    EXPECT_EQ(fork_raplas({"merge", "p0.json", "p1.json", "--json", "out.json", "-q"}).code, 0);
}

TEST_F(Shard, EmittedJobsRunLineByLineAsASlurmArrayAndMergeToTheWholeRun) {
    const std::vector<std::string> config{"--iccs", "3", "--fifo", "4"};
    const RunResult e = run(plus(plus(plus({"simulate"}, kShardScene), config),
                                 {"--shards", "3", "--emit-jobs", "jobs", "--json", "out.json", "--csv", "out.csv"}));
    ASSERT_EQ(e.code, 0) << e.err;
    EXPECT_THAT(e.out, HasSubstr("parallel < jobs.traces && parallel < jobs && sh jobs.merge"));
    const auto traces = lines_of(slurp(dir / "jobs.traces"));
    const auto jobs = lines_of(slurp(dir / "jobs"));
    const auto merge = lines_of(slurp(dir / "jobs.merge"));
    ASSERT_EQ(traces.size(), 1u);
    ASSERT_EQ(jobs.size(), 3u);
    ASSERT_EQ(merge.size(), 1u);
    const fs::path real = fs::canonical(dir);  // as the job lines name it
    const std::string cd = "cd " + real.string() + " && ";
    for (const auto& l : plus(traces, jobs)) {
        EXPECT_EQ(l.rfind(cd + "{ test -f " + (real / "out.json.d").string() + "/", 0), 0u) << l;
        EXPECT_THAT(l, HasSubstr(" || " + fs::canonical(RAPLAS_BINARY).string() + " "));
    }
    EXPECT_THAT(jobs[2], HasSubstr(" --shard 2/3 --json " + (real / "out.json.d/shard-2-of-3.json").string()));
    EXPECT_EQ(merge[0].rfind(cd, 0), 0u);
    EXPECT_FALSE(fs::exists(dir / "out.json.d/workload.trace")) << "--emit-jobs must not run anything";

    // As a Slurm array task runs its line, from anywhere: the trace, then the
    // shards in any order, then the merge.
    auto task = [&](const std::string& file, int id) {
        const std::string cmd = "cd / && SLURM_ARRAY_TASK_ID=" + std::to_string(id) + " sh -c 'sed -n \"${SLURM_ARRAY_TASK_ID}p\" " +
                                (dir / file).string() + " | sh' >/dev/null 2>&1";
        return std::system(cmd.c_str());
    };
    ASSERT_EQ(task("jobs.traces", 1), 0);
    for (int id : {3, 1, 2}) ASSERT_EQ(task("jobs", id), 0);
    ASSERT_EQ(std::system(("sh " + quoted((dir / "jobs.merge").string()) + " >/dev/null").c_str()), 0);

    const Outcome w = fork_raplas(plus(plus(plus({"simulate"}, kShardScene), config), {"--json", "whole.json", "--csv", "whole.csv", "-q"}));
    ASSERT_EQ(w.code, 0) << w.err;
    EXPECT_EQ(differences(load(dir / "whole.json"), load(dir / "out.json")), "[]");
    EXPECT_TRUE(without_wall(load(dir / "out.json")) == without_wall(load(dir / "whole.json")));
    EXPECT_EQ(slurp(dir / "out.csv"), slurp(dir / "whole.csv"));

    // A line whose result exists is skipped (it would fail without the trace).
    fs::remove(dir / "out.json.d/workload.trace");
    EXPECT_EQ(task("jobs", 2), 0);
    // The same jobs again are fine; another run's in the same work dir are not.
    EXPECT_EQ(run(plus(plus(plus({"simulate"}, kShardScene), config),
                       {"--shards", "3", "--emit-jobs", "jobs", "--json", "out.json", "--csv", "out.csv", "-q"}))
                  .code,
              0);
    const RunResult other = run(plus(plus({"simulate"}, kShardScene), {"--iccs", "4", "--shards", "3", "--emit-jobs", "jobs",
                                                                  "--json", "out.json", "-q"}));
    EXPECT_EQ(other.code, 2);
    EXPECT_THAT(other.err, HasSubstr("shards.json: the work dir holds the jobs of another run"));
    EXPECT_EQ(lines_of(other.err).size(), 1u);
    // Another shard count of the same run shares the work dir and its trace.
    EXPECT_EQ(run(plus(plus(plus({"simulate"}, kShardScene), config),
                       {"--shards", "2", "--emit-jobs", "jobs2", "--json", "out.json", "-q"}))
                  .code,
              0);
    EXPECT_THAT(slurp(dir / "jobs2"), HasSubstr("/out.json.d/shard-1-of-2.json"));
}

// --jobs N: one front end streams its trace to N shard processes at once, and
// the merged result is the whole run's, from a scene or a trace, with a
// mismatch too; a failing shard stops the run with one line and no result.
TEST_F(Shard, JobsOnOneMachineAddUpToTheWholeRun) {
    const std::vector<std::string> config{"--iccs", "3", "--fifo", "4"};
    for (const bool mismatch : {false, true}) {
        SCOPED_TRACE(mismatch ? "with a wrong RTI answer" : "exact");
        const std::vector<std::string> cfg =
            mismatch ? plus(config, {"--set", "sim.fault=wrong_rti", "--set", "sim.fault_icc=1"}) : config;
        const int code = mismatch ? 1 : 0;
        const Outcome w = fork_raplas(plus(plus(plus({"simulate"}, kShardScene), cfg), {"--json", "whole.json", "--csv", "whole.csv", "-q"}));
        ASSERT_EQ(w.code, code) << w.err;
        for (const auto& [input, jobs] : {std::pair<std::vector<std::string>, std::string>{kShardScene, "3"},
                                          {{"--trace", "t.trace"}, "2"}}) {
            SCOPED_TRACE("--jobs " + jobs);
            fs::remove(dir / "j.json");
            fs::remove(dir / "j.csv");
            const RunResult j = run(plus(plus(plus({"simulate"}, input), cfg), {"--jobs", jobs, "--json", "j.json", "--csv", "j.csv", "-q"}));
            ASSERT_EQ(j.code, code) << j.err;
            EXPECT_EQ(differences(load(dir / "whole.json"), load(dir / "j.json")), "[]");
            EXPECT_EQ(slurp(dir / "j.csv"), slurp(dir / "whole.csv"));
            EXPECT_EQ(load(dir / "j.json")["wall"]["shards"], std::stoi(jobs));
        }
    }
    // Without --json and --csv the summary is the output; --progress follows the groups handed over.
    const RunResult plain = run(plus(plus(plus({"simulate"}, kShardScene), config), {"--jobs", "2", "--progress"}));
    ASSERT_EQ(plain.code, 0) << plain.err;
    EXPECT_EQ(plain.out.rfind("merged 2 shards (", 0), 0u) << plain.out;
    EXPECT_THAT(plain.out, HasSubstr(" cycles = "));
    EXPECT_THAT(plain.err, HasSubstr(" ray groups to 2 shards"));
    // A shard that fails (a stuck RTI: the watchdog) stops the run: one line naming it, no result.
    fs::remove(dir / "j.json");
    const RunResult stuck = run(plus(plus(plus({"simulate"}, kShardScene), config),
                                     {"--set", "sim.fault=stuck_rti", "--set", "sim.watchdog_cycles=20000", "--jobs", "2",
                                      "--json", "j.json"}));
    EXPECT_EQ(stuck.code, 2);
    EXPECT_THAT(stuck.err, HasSubstr("shard 0/2 (exit 2): watchdog:"));
    EXPECT_EQ(lines_of(stuck.err).size(), 1u) << stuck.err;
    EXPECT_FALSE(fs::exists(dir / "j.json"));
    // What cannot be run that way is refused up front.
    for (const auto& extra : {std::vector<std::string>{"--vcd", "w.vcd"}, {"--shard", "0/2"}, {"--whole-frame"}}) {
        const RunResult bad = run(plus(plus({"simulate"}, kShardScene), plus({"--jobs", "2", "--json", "j.json"}, extra)));
        EXPECT_EQ(bad.code, 2) << extra[0];
        EXPECT_THAT(bad.err, HasSubstr("--jobs 2: ")) << extra[0];
        EXPECT_EQ(lines_of(bad.err).size(), 1u) << bad.err;
    }
}

TEST_F(Shard, EmittedJobsOfATraceHaveNoTracePhase) {
    const RunResult e = run({"simulate", "--trace", "t.trace", "--shards", "2", "--emit-jobs", "jobs", "--csv", "out.csv"});
    ASSERT_EQ(e.code, 0) << e.err;
    EXPECT_FALSE(fs::exists(dir / "jobs.traces"));
    EXPECT_THAT(e.out, HasSubstr("parallel < jobs && sh jobs.merge"));
    const auto jobs = lines_of(slurp(dir / "jobs"));
    ASSERT_EQ(jobs.size(), 2u);
    const fs::path wd = fs::canonical(dir) / "out.csv.d";
    EXPECT_THAT(jobs[0], HasSubstr(" simulate --trace t.trace --shard 0/2 --json " + (wd / "shard-0-of-2.json").string()));
    EXPECT_THAT(slurp(dir / "jobs.merge"), HasSubstr(" merge " + (wd / "shard-0-of-2.json").string() + " " +
                                                     (wd / "shard-1-of-2.json").string() + " --csv out.csv\n"));
}

}  // namespace
