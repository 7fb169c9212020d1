// The area model (docs/MODEL.md §6) against closed forms computed by hand
// from the coefficients: the defaults' derivation from the paper, every key
// of the blocks model in each memory system, the old PE-unit model, the note
// on keys the area does not follow, and the area a simulation reports.
#include <gtest/gtest.h>

#include <functional>

#include "area.hpp"
#include "baseline_memory.hpp"
#include "hand_trace.hpp"
#include "raplas/util/error.hpp"

using namespace raplas;
using namespace raplas::model;

namespace {

// A small machine with coefficients that are exact binary fractions, so that
// every closed form below is exact:
//   PSI pipe 100 + 2 x 10 = 120, RTI pipe 1000 + 5 x 10 = 1050,
//   fixed 7 + 11 + 2 x 3 + 13 = 37, SRAM 0.5 and scene memory 0.25 per byte.
// 2 ICCs, 4 PSI and 2 RTI pipes, FIFOs 10 / 20 / 30, N = 8, 16 / 39-byte
// records, 6-byte results; 100 spheres and 300 triangles.
SimConfig small_machine(MemorySystem sys) {
    SimConfig c;
    c.iccs = 2;
    c.memory.system = sys;
    c.icc.psi.pipes = 4;
    c.icc.rti.pipes = 2;
    c.icc.sphere_fifo.depth = 10;
    c.icc.triangle_fifo.depth = 20;
    c.icc.planeid_fifo.depth = 30;
    c.sphere_record_bytes = 16;
    c.triangle_record_bytes = 39;
    c.icc.min_distance.entry_bytes = 6;
    c.area.dsp_slices = 10;
    c.area.psi_slices = 100;
    c.area.psi_dsps = 2;
    c.area.rti_slices = 1000;
    c.area.rti_dsps = 5;
    c.area.triangle_selector = 7;
    c.area.ray_data_fetcher = 11;
    c.area.decoder = 3;
    c.area.sphere_selector = 13;
    c.area.sram_byte = 0.5;
    c.area.scene_byte = 0.25;
    c.area.ray_entry_bytes = 18;
    c.area.first_tri_entry_bytes = 3;
    return c;
}

AreaWorkload small_workload() {
    AreaWorkload w;
    w.spheres = 100;
    w.triangles = 300;
    w.group_size = 8;
    return w;
}

// One ICC of small_machine:
//   PSI 4 x 120 = 480, RTI 2 x 1050 = 2100, fixed 37;
//   FIFOs (streaming only) 0.5 x (10 x 16 + 20 x 39 + 30 x 16/8 + 30 x 3) = 80 + 390 + 30 + 45 = 545;
//   Ray and Min-distance Memories 0.5 x 64 x (18 + 6) = 576 + 192 = 768.
// Scene memories 0.25 x (100 x 16 + 300 x 39) = 400 + 2925 = 3325.
constexpr double kStreamingIcc = 480 + 2100 + 37 + 545 + 768;  // 3930
constexpr double kDemandIcc = 480 + 2100 + 37 + 768;           // 3385
constexpr double kScene = 3325;

double total(const SimConfig& c, const AreaWorkload& w) { return machine_area(c, w).total; }

}  // namespace

TEST(AreaModel, DefaultsAreThePapersFiguresAndTheirDerivation) {
    const SimConfig c = config_from_params(machine_params());
    const AreaParams& a = c.area;
    EXPECT_EQ(a.model, AreaModel::blocks);
    EXPECT_EQ(a.dsp_slices, 80.0);  // paper Table 3's FPGA: 15,360 slices, 192 DSPs
    EXPECT_EQ(15360.0 / 192.0, a.dsp_slices);
    EXPECT_EQ(a.psi_slices, 872.0);  // Table 4
    EXPECT_EQ(a.psi_dsps, 12.0);
    EXPECT_EQ(a.rti_slices, 4726.0);
    EXPECT_EQ(a.rti_dsps, 70.0);
    EXPECT_EQ(a.triangle_selector, 287.0);
    EXPECT_EQ(a.ray_data_fetcher, 588.0);
    EXPECT_EQ(a.decoder, 3.0);
    EXPECT_EQ(a.sphere_selector, 0.0);
    EXPECT_EQ(a.ray_entry_bytes, 18.0);  // Figure 7: Ray Memory 144 bit
    EXPECT_EQ(a.first_tri_entry_bytes, 3.0);
    EXPECT_EQ(a.pe, 1.0);
    EXPECT_EQ(a.memory, 2.0);
    EXPECT_EQ(a.icc_fifos, 0.0);
    // PE:memory = 1:2 (§5.2): the paper's ICC (32 PSI pipes, 1 RTI pipe, the
    // fixed blocks) against the mean Sphere and Triangle Memory of Table 2's
    // three scenes (Z33, Bunny, Conference: spheres x 16 B + triangles x 39 B).
    const double pe = 32 * (872 + 12 * 80) + (4726 + 70 * 80) + 287 + 588 + 2 * 3;
    EXPECT_EQ(pe, 69831.0);
    const double mean_bytes =
        ((23638 + 69452 + 172264) * 16.0 + (61828 + 69455 + 344528) * 39.0) / 3;
    EXPECT_NEAR(mean_bytes, 7600764.33, 0.01);
    EXPECT_NEAR(a.sram_byte, 2 * pe / mean_bytes, 5e-7);  // 0.0183747, given as 0.018375
    EXPECT_EQ(a.scene_byte, a.sram_byte);
    // §5.3: a 1,000-entry FIFO of 39-byte triangle records is the paper's 40 KB.
    EXPECT_EQ(c.triangle_record_bytes * 1000u, 39000u);
}

TEST(AreaModel, ThePaperMachineInClosedForm) {
    // Defaults (configs/paper.toml's ICC): 32 PSI pipes, 1 RTI pipe, FIFOs of
    // 1,000, N = 16; 16 ICCs, 1,000 spheres and 2,000 triangles.
    SimConfig c;
    c.iccs = 16;
    AreaWorkload w;
    w.spheres = 1000;
    w.triangles = 2000;
    w.group_size = 16;
    const AreaBreakdown b = machine_area(c, w);
    EXPECT_EQ(b.psi, 32 * 1832.0);   // 872 + 12 x 80
    EXPECT_EQ(b.rti, 10326.0);       // 4726 + 70 x 80
    EXPECT_EQ(b.fixed(), 881.0);     // 287 + 588 + 2 x 3 + 0
    // (1000 x 16 + 1000 x 39 + 1000 x 4 + 1000 x 3) bytes = 62,000 bytes
    EXPECT_NEAR(b.fifos(), 1139.25, 1e-9);
    // 256 rays x (18 + 6) bytes = 6,144 bytes
    EXPECT_NEAR(b.ray_memories(), 112.896, 1e-9);
    EXPECT_NEAR(b.icc(), 71083.146, 1e-6);
    // (1000 x 16 + 2000 x 39) bytes = 94,000 bytes, one copy
    EXPECT_NEAR(b.scene_memory(), 1727.25, 1e-9);
    EXPECT_EQ(b.scene_copies, 1u);
    EXPECT_NEAR(b.total, 16 * 71083.146 + 1727.25, 1e-6);
    EXPECT_EQ(b.note, "");
}

TEST(AreaModel, TheSmallMachineBlockByBlock) {
    const AreaBreakdown s = machine_area(small_machine(MemorySystem::streaming), small_workload());
    EXPECT_EQ(s.psi, 480.0);
    EXPECT_EQ(s.rti, 2100.0);
    EXPECT_EQ(s.triangle_selector, 7.0);
    EXPECT_EQ(s.ray_data_fetcher, 11.0);
    EXPECT_EQ(s.decoders, 6.0);
    EXPECT_EQ(s.sphere_selector, 13.0);
    EXPECT_EQ(s.sphere_fifo, 80.0);
    EXPECT_EQ(s.triangle_fifo, 390.0);
    EXPECT_EQ(s.planeid_fifo, 30.0);
    EXPECT_EQ(s.first_tri_fifo, 45.0);
    EXPECT_EQ(s.ray_memory, 576.0);
    EXPECT_EQ(s.min_distance_memory, 192.0);
    EXPECT_EQ(s.sphere_memory, 400.0);
    EXPECT_EQ(s.triangle_memory, 2925.0);
    EXPECT_EQ(s.icc(), kStreamingIcc);
    EXPECT_EQ(s.total, 2 * kStreamingIcc + kScene);  // 11,185
    // Shared: ICCs without FIFOs, one copy of the scene.
    const AreaBreakdown sh = machine_area(small_machine(MemorySystem::shared), small_workload());
    EXPECT_EQ(sh.fifos(), 0.0);
    EXPECT_EQ(sh.scene_copies, 1u);
    EXPECT_EQ(sh.total, 2 * kDemandIcc + kScene);  // 10,095
    // Distributed, fetching on demand: ICCs without FIFOs, a copy each.
    const AreaBreakdown d = machine_area(small_machine(MemorySystem::distributed), small_workload());
    EXPECT_EQ(d.scene_copies, 2u);
    EXPECT_EQ(d.total, 2 * (kDemandIcc + kScene));  // 13,420
    // Distributed, each ICC streaming its own copy: a one-ICC RAPLAS each.
    SimConfig c = small_machine(MemorySystem::distributed);
    c.memory.distributed_stream = true;
    EXPECT_EQ(total(c, small_workload()), 2 * (kStreamingIcc + kScene));  // 14,510
}

// Each key against the small machine: the total after changing it alone, per
// system (streaming, shared, distributed on demand), by hand.
TEST(AreaModel, EveryKeyChangesTheAreaByItsClosedForm) {
    const double base[3] = {2 * kStreamingIcc + kScene, 2 * kDemandIcc + kScene, 2 * (kDemandIcc + kScene)};
    EXPECT_EQ(base[0], 11185.0);
    EXPECT_EQ(base[1], 10095.0);
    EXPECT_EQ(base[2], 13420.0);
    struct Case {
        const char* key;
        std::function<void(SimConfig&, AreaWorkload&)> change;
        double streaming, shared, distributed;  // the change in total area
    };
    const std::vector<Case> cases = {
        // one more ICC: an ICC (and, distributed, a copy of the scene)
        {"machine.iccs", [](SimConfig& c, AreaWorkload&) { c.iccs = 3; }, kStreamingIcc, kDemandIcc,
         kDemandIcc + kScene},
        // 2 ICCs x one pipe
        {"icc.psi_pipes", [](SimConfig& c, AreaWorkload&) { c.icc.psi.pipes = 5; }, 240, 240, 240},
        {"icc.rti_pipes", [](SimConfig& c, AreaWorkload&) { c.icc.rti.pipes = 3; }, 2100, 2100, 2100},
        // 2 ICCs x 0.5 x one more entry of 16, 39, and 2 + 3 bytes; no FIFOs in the baselines
        {"fifo.sphere_depth", [](SimConfig& c, AreaWorkload&) { c.icc.sphere_fifo.depth = 11; }, 16, 0, 0},
        {"fifo.triangle_depth", [](SimConfig& c, AreaWorkload&) { c.icc.triangle_fifo.depth = 21; }, 39, 0, 0},
        {"fifo.planeid_depth", [](SimConfig& c, AreaWorkload&) { c.icc.planeid_fifo.depth = 31; }, 5, 0, 0},
        // N = 9: PlaneID entries of 18 bits (2 x 0.5 x 30 x 2/8 = 7.5), 81 rays
        // (2 x 0.5 x 17 x 24 = 408)
        {"workload.group_size", [](SimConfig&, AreaWorkload& w) { w.group_size = 9; }, 7.5 + 408, 408, 408},
        // 2 ICCs x 0.5 x 64 rays x 1 byte
        {"link.result_bytes", [](SimConfig& c, AreaWorkload&) { c.icc.min_distance.entry_bytes = 7; }, 64, 64, 64},
        // double buffers in streaming ICCs only: 2 x 768
        {"host.overlap_passes", [](SimConfig& c, AreaWorkload&) { c.overlap_passes = true; }, 1536, 0, 0},
        // one more sphere / triangle: 0.25 x its bytes per copy
        {"spheres", [](SimConfig&, AreaWorkload& w) { w.spheres = 101; }, 4, 4, 8},
        {"triangles", [](SimConfig&, AreaWorkload& w) { w.triangles = 301; }, 9.75, 9.75, 19.5},
        // a record byte more: the FIFO (2 x 0.5 x 10 / 20) and the memories (0.25 x 100 / 300 per copy)
        {"link.sphere_record_bytes", [](SimConfig& c, AreaWorkload&) { c.sphere_record_bytes = 17; }, 10 + 25, 25, 50},
        {"link.triangle_record_bytes", [](SimConfig& c, AreaWorkload&) { c.triangle_record_bytes = 40; }, 20 + 75, 75,
         150},
        // 2 ICCs x (4 x 2 + 2 x 5) DSPs
        {"area.dsp_slices", [](SimConfig& c, AreaWorkload&) { c.area.dsp_slices = 11; }, 36, 36, 36},
        {"area.psi_slices", [](SimConfig& c, AreaWorkload&) { c.area.psi_slices = 101; }, 8, 8, 8},
        {"area.psi_dsps", [](SimConfig& c, AreaWorkload&) { c.area.psi_dsps = 3; }, 80, 80, 80},
        {"area.rti_slices", [](SimConfig& c, AreaWorkload&) { c.area.rti_slices = 1001; }, 4, 4, 4},
        {"area.rti_dsps", [](SimConfig& c, AreaWorkload&) { c.area.rti_dsps = 6; }, 40, 40, 40},
        {"area.triangle_selector", [](SimConfig& c, AreaWorkload&) { c.area.triangle_selector = 8; }, 2, 2, 2},
        {"area.ray_data_fetcher", [](SimConfig& c, AreaWorkload&) { c.area.ray_data_fetcher = 12; }, 2, 2, 2},
        {"area.decoder", [](SimConfig& c, AreaWorkload&) { c.area.decoder = 4; }, 4, 4, 4},
        {"area.sphere_selector", [](SimConfig& c, AreaWorkload&) { c.area.sphere_selector = 14; }, 2, 2, 2},
        // SRAM bytes per ICC: streaming 1,090 + 1,536, baselines 1,536; x 2 ICCs x 0.5 more
        {"area.sram_byte", [](SimConfig& c, AreaWorkload&) { c.area.sram_byte = 1; }, 2626, 1536, 1536},
        {"area.scene_byte", [](SimConfig& c, AreaWorkload&) { c.area.scene_byte = 0.5; }, kScene, kScene, 2 * kScene},
        // 2 ICCs x 0.5 x 64 rays; 2 ICCs x 0.5 x 30 entries
        {"area.ray_entry_bytes", [](SimConfig& c, AreaWorkload&) { c.area.ray_entry_bytes = 19; }, 64, 64, 64},
        {"area.first_tri_entry_bytes", [](SimConfig& c, AreaWorkload&) { c.area.first_tri_entry_bytes = 4; }, 30, 0,
         0},
        // keys of the other model change nothing here
        {"area.pe", [](SimConfig& c, AreaWorkload&) { c.area.pe = 5; }, 0, 0, 0},
        {"area.memory", [](SimConfig& c, AreaWorkload&) { c.area.memory = 5; }, 0, 0, 0},
        {"area.icc_fifos", [](SimConfig& c, AreaWorkload&) { c.area.icc_fifos = 5; }, 0, 0, 0},
    };
    const MemorySystem systems[3] = {MemorySystem::streaming, MemorySystem::shared, MemorySystem::distributed};
    for (const Case& k : cases) {
        const double delta[3] = {k.streaming, k.shared, k.distributed};
        for (int s = 0; s < 3; ++s) {
            SimConfig c = small_machine(systems[s]);
            AreaWorkload w = small_workload();
            k.change(c, w);
            EXPECT_EQ(total(c, w), base[s] + delta[s]) << k.key << ", " << memory_system_name(systems[s]);
        }
    }
}

TEST(AreaModel, PlaneIdDepthZeroFollowsTheTriangleFifo) {
    // Through the config keys: fifo.planeid_depth = 0 is as deep as the
    // Triangle FIFO (20 instead of 30: 2 ICCs x 0.5 x 10 x (2 + 3) = 50 less).
    ParamSet p = machine_params();
    for (const char* s : {"machine.iccs=2", "icc.psi_pipes=4", "icc.rti_pipes=2", "fifo.sphere_depth=10",
                          "fifo.triangle_depth=20", "fifo.planeid_depth=30", "area.dsp_slices=10", "area.psi_slices=100",
                          "area.psi_dsps=2", "area.rti_slices=1000", "area.rti_dsps=5", "area.triangle_selector=7",
                          "area.ray_data_fetcher=11", "area.decoder=3", "area.sphere_selector=13", "area.sram_byte=0.5",
                          "area.scene_byte=0.25"})
        p.set(s);
    EXPECT_EQ(total(config_from_params(p), small_workload()), 11185.0);
    p.set("fifo.planeid_depth=0");
    EXPECT_EQ(total(config_from_params(p), small_workload()), 11185.0 - 50);
    p.set("fifo.triangle_depth=30");  // the PlaneID FIFOs follow: 30 again; 2 x 0.5 x 10 x 39 more
    EXPECT_EQ(total(config_from_params(p), small_workload()), 11185.0 + 390);
}

TEST(AreaModel, TheWorkloadComesFromTheTraceUnlessTheConfigSetsTheGroupSize) {
    Trace t = test::hand_trace(30, 8, 0b1, 0b1, std::vector<bool>(30, true));
    t.triangles.resize(45);
    SimConfig c;
    AreaWorkload w = area_workload(t, c);
    EXPECT_EQ(w.spheres, 30u);
    EXPECT_EQ(w.triangles, 45u);
    EXPECT_EQ(w.group_size, 8u);
    t.shadow_group_size = 12;  // the largest group an ICC holds
    EXPECT_EQ(area_workload(t, c).group_size, 12u);
    c.group_size = 16;  // workload.group_size names the machine's groups
    EXPECT_EQ(area_workload(t, c).group_size, 16u);
    c.group_size = 4;
    c.shadow_group_size = 6;
    EXPECT_EQ(area_workload(t, c).group_size, 6u);
}

TEST(AreaModel, PeUnitsReproduceTheOldFormulaExactly) {
    // pe_units: streaming K (PE + FIFOs) + memory, shared K PE + memory,
    // distributed K (PE + memory), whatever the hardware and the workload.
    for (std::uint32_t k : {1u, 3u, 16u, 48u}) {
        SimConfig c = small_machine(MemorySystem::streaming);
        c.area.model = AreaModel::pe_units;
        c.iccs = k;
        EXPECT_EQ(total(c, small_workload()), k * 1.0 + 2.0) << k;  // the defaults: K + 2
        c.area.pe = 1.5;
        c.area.memory = 2.25;
        c.area.icc_fifos = 0.5;
        EXPECT_EQ(total(c, small_workload()), k * 2.0 + 2.25) << k;
        c.memory.system = MemorySystem::shared;
        EXPECT_EQ(total(c, small_workload()), k * 1.5 + 2.25) << k;
        c.memory.system = MemorySystem::distributed;
        EXPECT_EQ(total(c, small_workload()), k * 3.75) << k;
        c.memory.distributed_stream = true;
        EXPECT_EQ(total(c, small_workload()), k * 3.75) << k;
    }
    // No hardware key or workload figure moves it.
    SimConfig c = small_machine(MemorySystem::streaming);
    c.area.model = AreaModel::pe_units;
    c.icc.psi.pipes = 32;
    c.icc.rti.pipes = 16;
    c.icc.sphere_fifo.depth = c.icc.triangle_fifo.depth = c.icc.planeid_fifo.depth = 1;
    c.overlap_passes = true;
    c.area.sram_byte = 100;
    AreaWorkload w = small_workload();
    w.spheres = w.triangles = 1000000;
    w.group_size = 64;
    const AreaBreakdown b = machine_area(c, w);
    EXPECT_EQ(b.total, 2 * 1.0 + 2.0);
    EXPECT_EQ(b.icc(), 0.0);
    EXPECT_NE(b.note.find("pe_units"), std::string::npos);
}

TEST(AreaModel, TheNoteNamesTheKeysTheAreaDoesNotFollow) {
    SimConfig c = small_machine(MemorySystem::streaming);
    EXPECT_EQ(machine_area(c, small_workload()).note, "");
    c.icc.psi.stages = 12;
    std::string note = machine_area(c, small_workload()).note;
    EXPECT_NE(note.find("icc.psi_stages = 12"), std::string::npos) << note;
    c.icc.psi.stages = 10;
    c.icc.rti.stages = 30;
    note = machine_area(c, small_workload()).note;
    EXPECT_NE(note.find("icc.rti_stages = 30"), std::string::npos) << note;
    c.icc.rti.stages = 25;
    c.format = NumFormat::float64();
    note = machine_area(c, small_workload()).note;
    EXPECT_NE(note.find("numerics.format = float64"), std::string::npos) << note;
    EXPECT_EQ(note.find("stages"), std::string::npos) << note;
    c.format = NumFormat::float32();
    c.memory.records_per_cycle = 2;  // streaming has no memory ports to widen
    EXPECT_EQ(machine_area(c, small_workload()).note, "");
    c.memory.system = MemorySystem::shared;
    note = machine_area(c, small_workload()).note;
    EXPECT_NE(note.find("memory.fetch_records_per_cycle = 2"), std::string::npos) << note;
}

TEST(AreaModel, BadCoefficientsAreOneLineNamingTheKey) {
    for (const char* bad : {"area.sram_byte=-1", "area.psi_dsps=-0.5", "area.dsp_slices=1e7", "area.scene_byte=nan",
                            "area.model=gates", "area.ray_entry_bytes=\"x\""}) {
        ParamSet p = machine_params();
        const std::string key = std::string(bad).substr(0, std::string(bad).find('='));
        try {
            p.set(bad);
            (void)config_from_params(p);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(key), std::string::npos) << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        }
    }
}

TEST(AreaModel, ASimulationReportsTheAreaOfItsTrace) {
    // 200 spheres of one triangle, N = 16, the default machine with 2 ICCs:
    // ICCs of 71,083.146 (as ThePaperMachineInClosedForm) and one copy of
    // 200 x (16 + 39) bytes x 0.018375 = 202.125.
    Trace t = test::hand_trace(200, 16, 0, 0, std::vector<bool>(200, false), 3);
    SimConfig c;
    c.iccs = 2;
    c.functional = FunctionalMode::trace;
    for (MemorySystem sys : {MemorySystem::streaming, MemorySystem::shared, MemorySystem::distributed}) {
        c.memory.system = sys;
        MemoryStats st;
        simulate_system(t, c, st);
        const double icc = sys == MemorySystem::streaming ? 71083.146 : 71083.146 - 1139.25;  // no FIFOs
        const double copies = sys == MemorySystem::distributed ? 2 : 1;
        EXPECT_NEAR(st.area.total, 2 * icc + copies * 202.125, 1e-6) << memory_system_name(sys);
    }
}
