// Internal to the app layer: what made a result, as hashes (docs/BAD_INPUT.md,
// "Rules"). Work dirs (sweeps, simulate --shards --emit-jobs, simulate
// --frames --emit-jobs) keep it, so that results made from other inputs are
// never reused; shard and frame results carry it, so that merge refuses
// parts of different runs.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace raplas {

struct RunInputs {
    std::string scene;                    // scene file as given (a shipped scene's name is resolved), or empty
    std::string mesh;                     // --mesh, or empty
    std::vector<std::string> scene_sets;  // scene keys given with --set
    std::string config;                   // machine config file (resolved), or empty
    std::vector<std::string> config_sets; // the config's overrides as given (--set, --iccs, --fifo)
    std::string trace;                    // a trace file given with --trace, or empty
};

struct SimulateArgs;
struct SceneOptions;
class RunFiles;
// The files a scene option set reads, as inputs of `files`: the scene file,
// the --mesh file and every mesh file the scene resolves to.
void add_scene_inputs(RunFiles& files, const SceneOptions& so);
// The inputs of `raplas simulate` with these arguments (its --set keys routed
// to the config or the scene as simulate routes them).
RunInputs simulate_inputs(const SimulateArgs& a);

// {"model": model_identity(), "scene": {"path", "hash"} or null, "meshes":
// [{"path", "hash"}...] (every mesh file the scene resolves to), "config":
// {"path", "hash"} or null, "sets": [...], "trace": {"path", "hash"} or null}.
// A trace is hashed by its bytes when `hash_trace_file`, else recorded by
// `trace_content` (TraceReader::content_hash, as 16 hex digits) when given.
nlohmann::json hash_inputs(const RunInputs& in, bool hash_trace_file = true, const std::string& trace_content = "");

// "" when two records agree; else what differs, for a message ("the scene
// file s.toml changed", "the mesh m.obj changed", "raplas's model changed").
std::string inputs_change(const nlohmann::json& there, const nlohmann::json& here);

}  // namespace raplas
