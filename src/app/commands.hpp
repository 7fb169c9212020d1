// Internal to the app layer: options shared by the front-end commands and
// the entry points of each subcommand.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "raplas/core/numfmt.hpp"
#include "raplas/scene/scene.hpp"

namespace raplas {

// What scene, with which overrides, in which number format.
struct SceneOptions {
    std::string scene, mesh, format = "float32";
    std::vector<std::string> sets;
    unsigned threads = 0;
    bool dump_scene = false;
    bool no_cull = false;
    bool quiet = false;
    bool progress = false;  // --progress: also when stderr is not a terminal
    int frame = -1;         // --frame F: frame F of the scene's animation instead of the still scene
    bool animate = false;   // the command draws frames (--frames): the built-in scene gets its animation
    // Set by load(): the loaded scene's frame count and rate (before --frame picks one).
    mutable int frames_in_animation = 1;
    mutable double animation_fps = 0;

    void add_to(CLI::App* cmd, bool with_format = true);
    // Progress lines on stderr: asked for, or stderr is a terminal and not -q.
    bool show_progress() const;
    NumFormat parsed_format() const;
    // Loads the scene parameters (file, then --set), letting `adjust` change
    // them before the scene is built. Returns false when --dump-scene printed
    // them. With --frame F the scene is that frame's; with --frame or
    // `animate`, the built-in scene given no [animation] key gets
    // animation.builtin = default.
    bool load(Scene& out, double& load_s, const std::function<void(ParamSet&)>& adjust = {}) const;
};

struct SimulateArgs {
    SceneOptions so;
    std::string config, trace, json, csv, vcd;
    std::string shard;                 // I/N: simulate only the passes of shard I (docs/SHARDING.md)
    std::uint32_t shards = 0;          // with emit_jobs: write the job lists of N shards
    std::string emit_jobs, work_dir;
    std::vector<std::string> config_sets;
    std::uint32_t iccs = 0;  // 0: from the config
    std::uint32_t fifo = 0;  // 0: from the config
    std::string frames;        // --frames N|A:B|all: simulate these frames, each in its own process
    unsigned jobs = 0;         // with --frames: frames simulated at once (0: number of cores)
    std::uint32_t window = 4;  // passes the front end may trace ahead of the model
    bool whole_frame = false;  // trace the whole frame first instead of streaming it
    bool sample_front_end = false;  // sample_passes: trace only the shadow groups of the sampled passes
    bool dump_config = false;
    bool animation_row = false;  // --animation-row: the CSV row a sweep of animated scenes reads
    bool fresh = false;          // --fresh: a work dir of other inputs is emptied, not refused
    bool no_workload_hash = false;  // (internal) a shard of --jobs: the feeding process folds the hash
    std::string workload_hash;      // (internal) HASH@CONTENT: a sweep's point, its trace's hash folded by the sweep
};

// A machine config: a file, or a name in configs/ (the working directory's,
// then the installed data folder's or the source tree's: util/data_dir.hpp).
std::string resolve_config(const std::string& name);

// The CLI11 check of --iccs and --fifo: an integer in 1..max, or with `list`
// comma-separated integers in 1..max. A text that is not an integer is
// refused, naming the integer probably meant ("'1e3' is not an integer;
// write 1000"); so is 1,000 in a list (1 and 000).
CLI::Validator count_check(std::uint32_t max, bool list);
// The integers of texts that passed count_check(max, true).
std::vector<std::uint32_t> count_list(const std::vector<std::string>& texts);
// A config key given with --set that --iccs or --fifo, also given, would
// override without a word (machine.iccs; fifo.sphere_depth or
// fifo.triangle_depth) is refused: one line naming both.
void check_not_set_by_option(const std::string& key, bool iccs_given, bool fifo_given);

void add_simulate_options(CLI::App* cmd, SimulateArgs& a);
int cmd_simulate(const SimulateArgs& a);

struct SweepArgs {
    std::vector<std::string> scenes, meshes;
    std::string config, out, work_dir, emit_jobs;
    std::vector<std::string> sets;
    std::vector<std::string> vary;          // KEY=V1,V2,... or KEY=A..B (repeatable)
    std::vector<std::uint32_t> iccs, fifo;  // empty: the config's value
    std::uint32_t base_iccs = 0;            // speedup base; 0: the smallest ICC count of each series
    std::uint32_t base_fifo = 0;            // speedup base's FIFO depth; 0: the point's own
    std::string normalize;                  // KEY=VALUE: area_time over that point's (area_time_normalized)
    std::string check, update;              // reference tables
    std::vector<std::string> tolerance;     // COL=REL for --check
    unsigned jobs = 0;                      // 0: number of cores
    bool merge = false, progress = false, quiet = false;
    bool fresh = false;                     // --fresh: recompute the points whose inputs changed
    bool retry_failed = false;              // --retry-failed: simulate the points that failed before again
    std::string find, target;               // --find KEY --target METRIC>=VALUE
    std::uint64_t find_limit = 0;           // 0: the key's range
    const CLI::App* cmd = nullptr;          // gives the order of --scene and --mesh
    std::string command_line;               // as typed (the --update header)
};

void add_sweep_options(CLI::App* cmd, SweepArgs& a);
int cmd_sweep(const SweepArgs& a);

}  // namespace raplas
