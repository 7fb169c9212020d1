// Internal to the app layer: one simulation sharded across processes and
// nodes (docs/SHARDING.md). `simulate --shard I/N` simulates the passes p
// with p mod N = I and writes a partial result; `raplas merge` adds the
// parts up to exactly the unsharded result; `simulate --shards N
// --emit-jobs FILE` writes the job lists that run the shards.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "baseline_memory.hpp"
#include "commands.hpp"
#include "config.hpp"
#include "raplas/app/sim_report.hpp"

namespace raplas {

struct ShardSpec {
    std::uint32_t index = 0, count = 1;
};
// Job lists name every shard's file in one merge command: a bound that keeps
// that command well inside the kernel's argument limits.
constexpr std::uint32_t kMaxShards = 10000;

// "I/N" with 0 <= I < N <= kMaxShards; InputError naming --shard otherwise.
ShardSpec parse_shard(const std::string& text);
// InputError, starting with `option`, when the configured run's passes are
// not independent or there are no passes to share out.
void check_shardable(const model::SimConfig& cfg, const std::string& option);

// The partial result of one shard (simulate --shard I/N --json).
struct PartialInput {
    ShardSpec shard;
    SimReportInput report;       // what a whole run reports from (result, memory, workload, provenance, names)
    std::string machine_config;  // the resolved machine config as TOML (ParamSet::dump)
    nlohmann::json inputs;       // what made it (run_inputs.hpp)
};
nlohmann::json partial_json(const PartialInput& in);
// What a shard prints on stdout: one line.
std::string shard_summary(const PartialInput& in, const std::string& json_path);

// Refuses (InputError naming the key) a config key given with --set that
// changes nothing in the machine `mp` (model::inert_config_key), a scene key
// with a trace (the trace fixes the scene), or one a workload key overrides.
void check_keys_apply(const ParamSet& mp, const std::vector<std::string>& config_keys,
                      const std::vector<std::string>& scene_sets, const std::string& trace);
// Refuses a trace made with other workload values than the config's
// workload.* keys ask for (0 follows the trace).
void check_trace_workload(const Trace& t, const ParamSet& mp, const std::string& name);

// `raplas simulate --shards N --emit-jobs FILE`: the job lists; `mp` is the
// resolved machine config, `cfg` the config from it.
int emit_shard_jobs(const SimulateArgs& a, const ParamSet& mp, const model::SimConfig& cfg);

// InputError when `out`, given to `option`, cannot be written: a directory,
// in a directory that does not exist, or one of the `parts` read.
void check_result_path(const std::string& option, const std::string& out, const std::vector<std::string>& parts);

// `raplas simulate --jobs N` on one frame: the front end (or the trace read)
// feeding `stream` on `frontend`'s thread is written as a trace to N shard
// processes, `raplas simulate --trace /dev/stdin CHILD_ARGS --shard I/N`,
// run at once; their parts are merged into `json` / `csv` (what simulate
// would write), and the run's summary printed unless `quiet`. Returns the
// exit code: the merge's, or the first failed shard's (one line on stderr;
// nothing written), or kFrontEndFailed when the front end failed (its
// FrontEndThread says why; nothing written).
struct LocalShards {
    std::uint32_t jobs = 2;
    std::vector<std::string> child_args;  // the machine config's options, as simulate was given them
    std::string json, csv;
    bool quiet = false;
    bool progress = false, tty = false;  // a progress line on stderr (the groups handed to the shards), on a terminal or not
    bool pairless = false;               // the workload hash covers the pair-less spheres (WorkloadTally)
};
class GroupStream;
class FrontEndThread;
constexpr int kFrontEndFailed = -1;
int simulate_local_shards(const LocalShards& run, GroupStream& stream, FrontEndThread& frontend);

struct MergeArgs {
    std::vector<std::string> parts;
    std::string json, csv;
    bool quiet = false;
    bool summary_only = false;  // neither --json nor --csv needed: the summary is the output (simulate --jobs)
    std::string workload_hash;  // simulate --jobs: the hash it folded; the parts leave theirs empty
};
void add_merge_options(CLI::App* cmd, MergeArgs& a);
int cmd_merge(const MergeArgs& a);

}  // namespace raplas
