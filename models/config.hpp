// Machine configuration: every parameter declared once (default, range,
// description), read from configs/*.toml, overridable with --set, dumpable.
#pragma once

#include <string>

#include "area.hpp"
#include "group_order.hpp"
#include "icc.hpp"
#include "watchdog.hpp"
#include "raplas/util/params.hpp"

namespace raplas::model {

enum class SimMode { event, netlist };
inline const char* sim_mode_name(SimMode m) { return m == SimMode::netlist ? "netlist" : "event"; }
enum class Estimate { exact, sample_passes, fifo_bound };
// sim.rtl: a block of the netlist co-simulated as Verilog RTL (rtl/, made a
// SystemC module by Verilator when the build finds it; docs/MODEL.md §2).
enum class RtlBlock { none, triangle_selector };
inline const char* rtl_block_name(RtlBlock b) { return b == RtlBlock::triangle_selector ? "triangle_selector" : "none"; }
// Whether this build has the RTL blocks (Verilator was found when it was configured).
bool rtl_built();

// The memory system (paper Figure 5, §5.2; docs/MODEL.md §6): the streaming
// machine (the SystemC model), or a baseline computed from the same trace.
enum class MemorySystem { streaming, shared, distributed };
struct MemoryParams {
    MemorySystem system = MemorySystem::streaming;
    bool pe_rti_bound = false;           // memory.pe: false = ideal ("fast enough"), true = the ICC's RTI rate
    bool shared_fetch_spheres = false;   // memory.shared_spheres = fetched
    bool distributed_stream = false;     // memory.distributed_fetch = stream
    double records_per_cycle = 1.0;      // per memory port
};

struct SimConfig {
    std::uint32_t iccs = 1;
    double clock_mhz = 400;
    Icc::Params icc;
    std::uint32_t sphere_record_bytes = 16, triangle_record_bytes = 39;
    std::uint64_t pass_overhead_cycles = 0;
    bool overlap_passes = false;  // a pass's streams start while the previous pass drains (double buffers)
    std::uint64_t triangle_lag_cycles = 0;  // the triangle stream starts this many cycles after the sphere stream
    // Workload overrides of the scene (0 = keep the scene's value).
    std::uint32_t group_size = 0, shadow_group_size = 0, triangles_per_sphere = 0;
    // The order groups are issued in (models/group_order.hpp) and the seed of the random one.
    GroupOrder group_order = GroupOrder::pixel;
    std::uint64_t group_seed = 1;
    NumFormat format = NumFormat::float32();
    FunctionalMode functional = FunctionalMode::compute;
    bool cull = true;  // compute mode: skip spheres a group provably misses (core/cull.hpp)
    SimMode mode = SimMode::event;
    RtlBlock rtl = RtlBlock::none;  // netlist: the block co-simulated as RTL
    std::uint64_t sync_cycles = 4096;      // cycles between watchdog checks (event mode: and kernel time updates)
    std::uint64_t watchdog_cycles = 1000000;
    // sample_passes: simulate every primary pass and a stratified sample of
    // the shadow passes, extrapolate the shadow passes' cycles (passes are
    // independent: each starts from empty FIFOs and record 0).
    // fifo_bound: every pass timed in closed form with unbounded Triangle,
    // PlaneID and First-Triangle-ID FIFOs, a lower bound of the exact count
    // (models/bound_engine.cpp).
    Estimate estimate = Estimate::exact;
    double sample_fraction = 0.1;
    std::uint64_t sample_seed = 1;
    MemoryParams memory;
    AreaParams area;  // models/area.hpp
    Fault fault = Fault::none;  // fault injection (tests of the watchdog)
    std::uint32_t fault_icc = 0;
};

ParamSet machine_params();
SimConfig config_from_params(const ParamSet& p);
// The intersectors' numerics from numerics.format, numerics.rti_test and
// numerics.psi_normalize (the keys may only add to the format's suffixes;
// a contradiction is an InputError naming the key).
NumFormat numerics_from_params(const ParamSet& p);
// Writes the resolved numerics back into the three keys (numerics.format with
// every suffix, the other two agreeing with it), so that --dump-config prints
// a config that loads again to the same format.
void resolve_numerics(ParamSet& p);
// Why config key `key` changes nothing in the machine `p` describes (a key
// that applies only under another setting: sim.sample_fraction without
// sim.estimate = sample_passes, memory.pe on the streaming machine, ...),
// as a phrase for "--set KEY: ..."; "" when it applies. A key set or varied
// by the user that applies to no point is refused (docs/BAD_INPUT.md, "Rules").
std::string inert_config_key(const ParamSet& p, const std::string& key);
// The same for scene key `key`: "" unless a workload key of `p` overrides
// it (workload.group_size, not 0, decides groups.size).
std::string inert_scene_key(const ParamSet& p, const std::string& key);
// The workload keys of `p` (workload.group_size, workload.shadow_group_size,
// workload.triangles_per_sphere) that are 0, "follow the scene or trace",
// set to the values the workload has: what a result reports.
void resolve_workload(ParamSet& p, std::uint32_t group_size, std::uint32_t shadow_group_size,
                      std::uint32_t triangles_per_sphere);
// Keys that choose how a result is computed, not what it is: the engine
// (sim.mode), a block co-simulated as RTL (sim.rtl), the functional check
// (sim.functional), kernel time updates, the watchdog and the compute mode's
// culling. config_hash leaves them out, so a
// run of another engine with equal figures has the same hash; the engine is
// a result column of its own (docs/SWEEPS.md, "Provenance").
bool result_neutral_key(const std::string& key);

// The scene key each workload key overrides (groups.size for
// workload.group_size, ...).
struct WorkloadKey {
    const char* config_key;
    const char* scene_key;
    const char* what;  // "primary ray group size N"
};
extern const WorkloadKey kWorkloadKeys[3];

// memory.* keys (models/baseline_memory.cpp); the area.* keys are add_area_params (models/area.hpp).
void add_memory_system_params(ParamSet& p);
void memory_system_from_params(const ParamSet& p, SimConfig& c);

}  // namespace raplas::model
