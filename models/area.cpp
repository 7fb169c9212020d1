#include "area.hpp"

#include <algorithm>
#include <cstdio>

#include "config.hpp"
#include "raplas/frontend/trace_io.hpp"
#include "raplas/util/params.hpp"

namespace raplas::model {

const char* area_model_name(AreaModel m) { return m == AreaModel::pe_units ? "pe_units" : "blocks"; }

AreaWorkload area_workload(std::uint64_t spheres, std::uint64_t triangles, std::uint32_t group_size,
                           std::uint32_t shadow_group_size, const SimConfig& cfg) {
    AreaWorkload w;
    w.spheres = spheres;
    w.triangles = triangles;
    const std::uint32_t n = cfg.group_size ? cfg.group_size : group_size;
    const std::uint32_t ns = cfg.shadow_group_size ? cfg.shadow_group_size : shadow_group_size;
    w.group_size = std::max(n, ns);
    return w;
}

AreaWorkload area_workload(const Trace& t, const SimConfig& cfg) {
    return area_workload(t.spheres.size(), t.triangles.size(), t.group_size, t.shadow_group_size, cfg);
}

namespace {

std::string real_text(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

// Keys the blocks model leaves out, named when the configuration changed them.
std::string blocks_note(const SimConfig& c) {
    std::string note;
    auto add = [&](const std::string& s) { note += (note.empty() ? "" : "; ") + s; };
    if (c.icc.psi.stages != kAreaPsiStages || c.icc.rti.stages != kAreaRtiStages)
        add("icc.psi_stages = " + std::to_string(c.icc.psi.stages) + ", icc.rti_stages = " +
            std::to_string(c.icc.rti.stages) + ": a pipe's area is Table 4's whatever its depth (" +
            std::to_string(kAreaPsiStages) + " and " + std::to_string(kAreaRtiStages) + " stages)");
    if (!(c.format == NumFormat::float32()))
        add("numerics.format = " + c.format.name() +
            ": the intersectors' area is Table 4's (24-bit) in every number format");
    if (c.memory.system != MemorySystem::streaming && c.memory.records_per_cycle != 1.0)
        add("memory.fetch_records_per_cycle = " + real_text(c.memory.records_per_cycle) +
            ": the width of the memory ports is not priced");
    return note;
}

}  // namespace

AreaBreakdown machine_area(const SimConfig& c, const AreaWorkload& w) {
    const AreaParams& a = c.area;
    AreaBreakdown b;
    b.model = a.model;
    b.iccs = c.iccs;
    const double k = c.iccs;
    if (a.model == AreaModel::pe_units) {
        switch (c.memory.system) {
            case MemorySystem::shared: b.total = k * a.pe + a.memory; break;
            case MemorySystem::distributed: b.total = k * (a.pe + a.memory); break;
            default: b.total = k * (a.pe + a.icc_fifos) + a.memory;
        }
        b.note = "area.model = pe_units: PEs and memories in units of the PE (paper §5.2); the area does not "
                 "follow the ICC's pipes, FIFO depths, group size or the scene";
        return b;
    }
    // Every ICC: the same logic in every system.
    b.psi = c.icc.psi.pipes * (a.psi_slices + a.psi_dsps * a.dsp_slices);
    b.rti = c.icc.rti.pipes * (a.rti_slices + a.rti_dsps * a.dsp_slices);
    b.triangle_selector = a.triangle_selector;
    b.ray_data_fetcher = a.ray_data_fetcher;
    b.decoders = 2 * a.decoder;
    b.sphere_selector = a.sphere_selector;
    // FIFOs where ICCs stream (the streaming machine, and a distributed
    // system whose ICCs stream their own copy); the baselines' PEs fetch on
    // demand.
    const bool streams = c.memory.system == MemorySystem::streaming ||
                         (c.memory.system == MemorySystem::distributed && c.memory.distributed_stream);
    const double n = w.group_size;
    if (streams) {
        b.sphere_fifo = a.sram_byte * double(c.icc.sphere_fifo.depth) * c.sphere_record_bytes;
        b.triangle_fifo = a.sram_byte * double(c.icc.triangle_fifo.depth) * c.triangle_record_bytes;
        b.planeid_fifo = a.sram_byte * double(c.icc.planeid_fifo.depth) * (2 * n / 8);  // 2N plane bits
        b.first_tri_fifo = a.sram_byte * double(c.icc.planeid_fifo.depth) * a.first_tri_entry_bytes;
    }
    // N x N rays; double buffers with overlapped passes (a streaming run).
    const double buffers = streams && c.overlap_passes ? 2 : 1;
    b.ray_memory = a.sram_byte * buffers * n * n * a.ray_entry_bytes;
    b.min_distance_memory = a.sram_byte * buffers * n * n * c.icc.min_distance.entry_bytes;
    b.sphere_memory = a.scene_byte * double(w.spheres) * c.sphere_record_bytes;
    b.triangle_memory = a.scene_byte * double(w.triangles) * c.triangle_record_bytes;
    b.scene_copies = c.memory.system == MemorySystem::distributed ? c.iccs : 1;
    b.total = k * b.icc() + b.scene_copies * b.scene_memory();
    b.note = blocks_note(c);
    return b;
}

void add_area_params(ParamSet& p) {
    const AreaParams d;
    p.add_string("area.model", std::string(area_model_name(d.model)),
                 "blocks = the sum of the blocks the machine has, in slice-equivalents (Virtex-4 slices, paper "
                 "Table 4): pipes, fixed blocks, FIFO entries, Ray and Min-distance Memories, scene memories "
                 "(docs/MODEL.md §6); pe_units = paper §5.2: K PEs and the memories in units of the PE "
                 "(area.pe, area.memory, area.icc_fifos), whatever the hardware and the scene (Figure 9)",
                 {"blocks", "pe_units"});
    p.add_real("area.pe", d.pe, 0.0, 1e9, "pe_units: area of one ICC's processing elements (paper: PE:memory = 1:2)");
    p.add_real("area.memory", d.memory, 0.0, 1e9, "pe_units: area of one copy of Sphere and Triangle Memory (paper: 2)");
    p.add_real("area.icc_fifos", d.icc_fifos, 0.0, 1e9,
               "pe_units, streaming: area of one ICC's Sphere and Triangle FIFOs (the paper counts PE and memory only: 0)");
    p.add_real("area.dsp_slices", d.dsp_slices, 0.0, 1e6,
               "blocks: slice-equivalents of one DSP: the FPGA of paper Tables 3 and 4 has 192 DSPs and 15,360 "
               "slices (10,480 slices are 68.2 %), 80 slices per DSP");
    p.add_real("area.psi_slices", d.psi_slices, 0.0, 1e9,
               "blocks: slices of one Plane-Sphere Intersector pipe (paper Table 4: 872)");
    p.add_real("area.psi_dsps", d.psi_dsps, 0.0, 1e6, "blocks: DSPs of one Plane-Sphere Intersector pipe (paper Table 4: 12)");
    p.add_real("area.rti_slices", d.rti_slices, 0.0, 1e9,
               "blocks: slices of one Ray-Triangle Intersector pipe (paper Table 4: 4,726)");
    p.add_real("area.rti_dsps", d.rti_dsps, 0.0, 1e6, "blocks: DSPs of one Ray-Triangle Intersector pipe (paper Table 4: 70)");
    p.add_real("area.triangle_selector", d.triangle_selector, 0.0, 1e9,
               "blocks: slices of an ICC's Triangle Selector (paper Table 4: 287)");
    p.add_real("area.ray_data_fetcher", d.ray_data_fetcher, 0.0, 1e9,
               "blocks: slices of an ICC's Ray Data Fetcher (paper Table 4: 588)");
    p.add_real("area.decoder", d.decoder, 0.0, 1e9,
               "blocks: slices of one Decoder; an ICC has two, as Figure 7's (paper Table 4: 3)");
    p.add_real("area.sphere_selector", d.sphere_selector, 0.0, 1e9,
               "blocks: slices of an ICC's Sphere Selector (0: Figure 7's ICC, whose blocks Table 4 lists, writes the "
               "Sphere Stream Link into its Sphere FIFO directly)");
    p.add_real("area.sram_byte", d.sram_byte, 0.0, 1e6,
               "blocks: slice-equivalents per byte of an ICC's FIFOs and Ray and Min-distance Memories: paper §5.2's "
               "PE:memory = 1:2 with the paper's ICC (32 PSI pipes, 1 RTI pipe: 69,831 slice-equivalents) against the "
               "mean Sphere and Triangle Memory of its three scenes (Table 2: 7,600,764 bytes)");
    p.add_real("area.scene_byte", d.scene_byte, 0.0, 1e6,
               "blocks: slice-equivalents per byte of Sphere and Triangle Memory (as area.sram_byte; 0 leaves "
               "the scene memories out)");
    p.add_real("area.ray_entry_bytes", d.ray_entry_bytes, 0.0, 1e6,
               "blocks: bytes of one Ray Memory entry, one per ray of an N x N group (paper Figure 7: 144 bit); a "
               "Min-distance Memory entry is link.result_bytes");
    p.add_real("area.first_tri_entry_bytes", d.first_tri_entry_bytes, 0.0, 1e6,
               "blocks: bytes of one First-Triangle-ID FIFO entry (a 24-bit triangle id, paper Figure 7); a PlaneID "
               "FIFO entry is the group's 2N plane bits");
}

AreaParams area_from_params(const ParamSet& p) {
    AreaParams a;
    a.model = p.get_string("area.model") == "pe_units" ? AreaModel::pe_units : AreaModel::blocks;
    a.pe = p.get_real("area.pe");
    a.memory = p.get_real("area.memory");
    a.icc_fifos = p.get_real("area.icc_fifos");
    a.dsp_slices = p.get_real("area.dsp_slices");
    a.psi_slices = p.get_real("area.psi_slices");
    a.psi_dsps = p.get_real("area.psi_dsps");
    a.rti_slices = p.get_real("area.rti_slices");
    a.rti_dsps = p.get_real("area.rti_dsps");
    a.triangle_selector = p.get_real("area.triangle_selector");
    a.ray_data_fetcher = p.get_real("area.ray_data_fetcher");
    a.decoder = p.get_real("area.decoder");
    a.sphere_selector = p.get_real("area.sphere_selector");
    a.sram_byte = p.get_real("area.sram_byte");
    a.scene_byte = p.get_real("area.scene_byte");
    a.ray_entry_bytes = p.get_real("area.ray_entry_bytes");
    a.first_tri_entry_bytes = p.get_real("area.first_tri_entry_bytes");
    return a;
}

}  // namespace raplas::model
