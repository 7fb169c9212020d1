// The area model (docs/MODEL.md §6): the area of the configured memory system
// on a workload, for Figure 9's area x time.
//
// blocks (the default): the sum of the blocks the machine has, in
// slice-equivalents (Virtex-4 slices of paper Table 4, a DSP counted as
// AreaParams::dsp_slices slices, a memory byte as AreaParams::sram_byte):
// per ICC its PSI and RTI pipes, its fixed blocks, its FIFO entries and its
// Ray and Min-distance Memories; per copy the Sphere and Triangle Memory,
// sized by the scene. pe_units: the paper's §5.2 reading, K PEs and the
// memories in units of the PE (PE:memory = 1:2), whatever the hardware keys.
#pragma once

#include <cstdint>
#include <string>

namespace raplas {
class ParamSet;
struct Trace;
}  // namespace raplas

namespace raplas::model {

struct SimConfig;

enum class AreaModel { blocks, pe_units };
const char* area_model_name(AreaModel m);

// Every coefficient is an area.* key; these initialisers are the keys'
// defaults (add_area_params reads them), derived in docs/MODEL.md §6.
struct AreaParams {
    AreaModel model = AreaModel::blocks;
    // pe_units, in PEs: one ICC's processing elements, one copy of Sphere and
    // Triangle Memory (paper §5.2: 1:2), one streaming ICC's FIFOs.
    double pe = 1.0, memory = 2.0, icc_fifos = 0.0;
    // blocks, in slice-equivalents.
    double dsp_slices = 80.0;                      // slices per DSP of the FPGA of Table 3 (15,360 / 192)
    double psi_slices = 872.0, psi_dsps = 12.0;    // one Plane-Sphere Intersector pipe (Table 4)
    double rti_slices = 4726.0, rti_dsps = 70.0;   // one Ray-Triangle Intersector pipe (Table 4)
    double triangle_selector = 287.0;              // Table 4
    double ray_data_fetcher = 588.0;               // Table 4
    double decoder = 3.0;                          // one Decoder (Table 4); an ICC has two (Figure 7)
    double sphere_selector = 0.0;                  // not in Figure 7's ICC
    double sram_byte = 0.018375;                   // an ICC's memories, per byte (§5.2 PE:memory = 1:2)
    double scene_byte = 0.018375;                  // Sphere and Triangle Memory, per byte
    double ray_entry_bytes = 18.0;                 // Ray Memory entry (Figure 7: 144 bit)
    double first_tri_entry_bytes = 3.0;            // First-Triangle-ID FIFO entry (a 24-bit triangle id)
};

// The pipeline depths the per-pipe figures stand for (paper Table 1); the
// area does not follow icc.psi_stages or icc.rti_stages (its note says so).
constexpr std::uint32_t kAreaPsiStages = 10, kAreaRtiStages = 25;

// What the area takes from the workload rather than the machine config.
struct AreaWorkload {
    std::uint64_t spheres = 0, triangles = 0;  // records in the Sphere and Triangle Memory
    std::uint32_t group_size = 0;              // N of the largest ray group an ICC holds (N x N rays)
};
// The workload of trace t under cfg: its sphere and triangle counts, and N =
// the larger of the primary and the shadow group size, each
// workload.group_size / workload.shadow_group_size when set, else the trace's.
AreaWorkload area_workload(const Trace& t, const SimConfig& cfg);
// The same from the counts alone (a result merged from shards holds no trace).
AreaWorkload area_workload(std::uint64_t spheres, std::uint64_t triangles, std::uint32_t group_size,
                           std::uint32_t shadow_group_size, const SimConfig& cfg);

// The area of a machine, block by block. Per-ICC figures are of one ICC;
// blocks-model figures are zero under pe_units.
struct AreaBreakdown {
    AreaModel model = AreaModel::blocks;
    std::uint32_t iccs = 0;
    // One ICC: all its pipes,
    double psi = 0, rti = 0;
    // its fixed blocks,
    double triangle_selector = 0, ray_data_fetcher = 0, decoders = 0, sphere_selector = 0;
    // its FIFOs (streaming ICCs only),
    double sphere_fifo = 0, triangle_fifo = 0, planeid_fifo = 0, first_tri_fifo = 0;
    // and its Ray and Min-distance Memories (both buffers when double-buffered).
    double ray_memory = 0, min_distance_memory = 0;
    // One copy of the scene memories, and the copies the system has.
    double sphere_memory = 0, triangle_memory = 0;
    std::uint32_t scene_copies = 0;
    double total = 0;
    // Keys the area does not follow although the configuration changed them
    // (empty when none).
    std::string note;

    double fixed() const { return triangle_selector + ray_data_fetcher + decoders + sphere_selector; }
    double fifos() const { return sphere_fifo + triangle_fifo + planeid_fifo + first_tri_fifo; }
    double ray_memories() const { return ray_memory + min_distance_memory; }
    double icc() const { return psi + rti + fixed() + fifos() + ray_memories(); }
    double scene_memory() const { return sphere_memory + triangle_memory; }
};

// The area of cfg's memory system with cfg.iccs ICCs on workload w.
AreaBreakdown machine_area(const SimConfig& cfg, const AreaWorkload& w);

// The area.* keys (used by machine_params()) and their values.
void add_area_params(ParamSet& p);
AreaParams area_from_params(const ParamSet& p);

}  // namespace raplas::model
