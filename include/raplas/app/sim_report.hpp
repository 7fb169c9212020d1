// Statistics of a simulation, written directly as JSON and CSV.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "baseline_memory.hpp"
#include "top.hpp"
#include "raplas/frontend/group_source.hpp"
#include "raplas/util/params.hpp"

namespace raplas {

// Where a result comes from: the machine config keys changed from the named
// config (or from the defaults when none is named), hashes of the resolved
// config and of the workload, and the resolved config itself.
struct Provenance {
    std::vector<std::pair<std::string, std::string>> overrides;  // key, value as TOML, in declaration order
    std::string config_hash;    // 16 hex digits
    std::string workload_hash;  // 16 hex digits (workload_hash in trace_io.hpp)
    nlohmann::json resolved_config;  // key -> value
};
// `named`: the config as loaded from its file (or the defaults); `resolved`:
// with --set, --iccs and --fifo applied. Both get their numerics resolved.
// `workload_hash`: of the groups simulated (WorkloadTally::hasher).
Provenance make_provenance(ParamSet named, ParamSet resolved, const std::string& workload_hash);
// The config_hash of a resolved machine config (numerics resolved first).
std::string config_hash(ParamSet resolved);

// What a report says of the workload: the trace's sizes (from its header),
// the group count and counts folded over its groups, and the kind and first
// pixel of the group of the result's first mismatching ray.
struct WorkloadFacts {
    std::uint64_t ray_groups = 0, primary_groups = 0, spheres = 0, triangles = 0;
    std::uint64_t untraced_groups = 0;  // --sample-front-end: groups the front end left out
    std::uint32_t group_size = 0, shadow_group_size = 0, triangles_per_sphere = 0;
    GroupCounts counts;
    bool mismatch_primary = true;
    std::int32_t mismatch_px = 0, mismatch_py = 0;
};
WorkloadFacts workload_facts(const Trace& header, const WorkloadTally& tally, const model::SimResult& r);

struct SimReportInput {
    const model::SimResult* result = nullptr;
    const model::SimConfig* config = nullptr;
    const WorkloadFacts* workload = nullptr;
    std::string config_name;
    std::string scene_name;
    double frontend_wall_s = 0;
    // The process's CPU seconds when the run ended (0: not reported) and the
    // front end's waits for the model (GroupStream::frontend_waits_s).
    double cpu_s = 0, frontend_waits_s = 0;
    // A result merged from shards (raplas merge): their count and the longest
    // shard's model time, reported under "wall" (0: not merged).
    std::uint32_t shards = 0;
    double model_wall_max_s = 0;
    const model::MemoryStats* memory = nullptr;  // memory system figures (none: not reported)
    const Provenance* provenance = nullptr;
};

// Deterministic figures under their own keys; wall-clock figures only under "wall".
nlohmann::json sim_json(const SimReportInput& in);
// One flat row of the scalar figures (the sweep's columns).
// One line on a `first_mismatch` object of sim_json: which ray (kind, group,
// pixel) and both answers; "none" for null.
std::string describe_mismatch(const nlohmann::json& first_mismatch);
std::string sim_csv_header();
std::string sim_csv_row(const nlohmann::json& j);
std::string sim_summary(const nlohmann::json& j);

}  // namespace raplas
