#include "config.hpp"

#include "raplas/util/error.hpp"

namespace raplas::model {

// Memory system keys (docs/MODEL.md §6), used by machine_params().
void add_memory_system_params(ParamSet& p) {
    p.add_string("memory.system", std::string("streaming"),
                 "streaming = the RAPLAS machine (SystemC model); shared = one memory, arbitrated among the ICCs; "
                 "distributed = each ICC its own copy of the scene (baselines of paper Figure 5, docs/MODEL.md §6)",
                 {"streaming", "shared", "distributed"});
    p.add_string("memory.pe", std::string("ideal"),
                 "baselines: ideal = PEs fast enough, time set by the memory ports (paper §5.2); "
                 "rti = also bounded by each ICC's Ray-Triangle Intersector (icc.rti_pipes tests per cycle)",
                 {"ideal", "rti"});
    p.add_string("memory.shared_spheres", std::string("excluded"),
                 "shared memory: excluded = the port serves triangle fetches only (the paper's Figure 10 counts "
                 "triangle transfers); fetched = every ray group also reads every sphere through the port",
                 {"excluded", "fetched"});
    p.add_string("memory.distributed_fetch", std::string("demand"),
                 "distributed memory: demand = an ICC reads every sphere and only the triangles of its hit spheres "
                 "from its own memories; stream = an ICC streams its copy like a one-ICC RAPLAS (exact one-ICC pass "
                 "cycles from the SystemC model)",
                 {"demand", "stream"});
    p.add_real("memory.fetch_records_per_cycle", 1.0, 1e-6, 1e6,
               "baselines: records (spheres or triangles) one memory port delivers per cycle (paper Table 1: 1)");
}

void memory_system_from_params(const ParamSet& p, SimConfig& c) {
    const std::string s = p.get_string("memory.system");
    c.memory.system = s == "shared" ? MemorySystem::shared
                      : s == "distributed" ? MemorySystem::distributed
                                           : MemorySystem::streaming;
    c.memory.pe_rti_bound = p.get_string("memory.pe") == "rti";
    c.memory.shared_fetch_spheres = p.get_string("memory.shared_spheres") == "fetched";
    c.memory.distributed_stream = p.get_string("memory.distributed_fetch") == "stream";
    c.memory.records_per_cycle = p.get_real("memory.fetch_records_per_cycle");
}

ParamSet machine_params() {
    ParamSet p("config");
    p.listed_by("raplas simulate --dump-config");
    p.add_string("name", std::string("custom"), "configuration name used in reports");
    p.add_int("machine.iccs", 1, 1, 4096, "number of Intersection Calculation Cores (ICCs)");
    p.add_real("machine.clock_mhz", 400.0, 1.0, 100000.0, "clock frequency, MHz (time and bandwidth reports)");
    p.add_int("icc.psi_pipes", 32, 1, 128, "Plane-Sphere Intersector pipes per ICC (paper: 32; FPGA ICC: 8)");
    p.add_int("icc.psi_stages", 10, 1, 1000, "pipeline stages of a Plane-Sphere Intersector (paper: 10)");
    p.add_int("icc.rti_pipes", 1, 1, 64, "Ray-Triangle Intersector pipes per ICC (paper: 1)");
    p.add_int("icc.rti_stages", 25, 1, 1000, "pipeline stages of the Ray-Triangle Intersector (paper: 25)");
    p.add_string("icc.triangle_select", std::string("any"),
                 "which spheres' triangles the Triangle Selector keeps: both = spheres cut by a row and a column "
                 "plane (Step 6); any = every sphere any valid ray-plane cuts (paper §4: 'if it finds no intersected "
                 "planes, the triangle data are discarded'), so a sphere cut by rows only or columns only sends "
                 "triangles that give no (ray, triangle) pair (docs/MODEL.md §3)",
                 {"both", "any"});
    p.add_int("icc.rdf_empty_cycles", 1, 0, 1000,
              "cycles the Ray Data Fetcher spends on a triangle with no (ray, triangle) pair (icc.triangle_select = "
              "any), counting the cycle it is popped in; 0 = dropped at no cost");
    p.add_int("fifo.sphere_depth", 1000, 1, 100000000, "Sphere FIFO depth, records (paper: 10/100/1000)");
    p.add_int("fifo.triangle_depth", 1000, 1, 100000000, "Triangle FIFO depth, records (paper: 10/100/1000)");
    p.add_int("fifo.planeid_depth", 1000, 0, 100000000,
              "PlaneID FIFO and First-Triangle-ID FIFO depth, kept spheres (not in the paper); 0 = the Triangle "
              "FIFO's depth (follows --fifo)");
    p.add_string("link.stall_policy", std::string("any_full"),
                 "when the Triangle Stream Link stops: any_full = any Triangle FIFO full (paper §3.1); "
                 "needed_full = only when an ICC that needs the triangle is full",
                 {"any_full", "needed_full"});
    p.add_int("link.stall_latency", 0, 0, 1000000,
              "cycles an ICC's Triangle FIFO hold takes to stop the Triangle Stream Link (a pipelined bus or daisy "
              "chain): the link stops in cycle c when a FIFO held in cycle c - L, and a FIFO raises its hold at "
              "depth - L entries so that the L records already on the link still fit (needs link.stall_policy = "
              "any_full and L < fifo.triangle_depth; docs/MODEL.md §3)");
    p.add_real("link.stall_latency_per_icc", 0.0, 0.0, 1000.0,
               "growth of the stall latency with the ICC count: L = link.stall_latency + "
               "floor(link.stall_latency_per_icc x machine.iccs)");
    p.add_int("link.resume_occupancy", -1, -1, 100000000,
              "after a Triangle FIFO's hold stops the link, the hold falls only when that FIFO has drained to this "
              "occupancy; -1 = as soon as it is below the occupancy that raised it (no hysteresis)");
    p.add_int("link.triangle_lag_cycles", 0, 0, 1000000,
              "cycles the Triangle Stream Link waits at the start of a pass before its first record "
              "(it also waits, as always, for undecided spheres)");
    p.add_int("link.sphere_record_bytes", 16, 1, 1024, "bytes per sphere record (paper: 6.4 GB/s at 400 MHz)");
    p.add_int("link.triangle_record_bytes", 39, 1, 1024, "bytes per triangle record (paper: 15.6 GB/s at 400 MHz)");
    p.add_int("link.result_bytes", 6, 1, 1024, "bytes per ray result on the Output Link (Min-distance Memory entry)");
    p.add_int("host.pass_overhead_cycles", 0, 0, 100000000, "cycles added per pass (group load, result read-out)");
    p.add_bool("host.overlap_passes", false,
               "true: double-buffered Ray and Min-distance Memories; a pass's streams start as soon as the previous "
               "pass's streams are done and the pass before it has drained, while the previous pass's Ray Data "
               "Fetchers and RTIs drain (the last pass of the primary and of the shadow phase drains fully)");
    p.add_int("workload.group_size", 0, 0, 64, "primary ray group size N (0 = the scene's groups.size)");
    p.add_int("workload.shadow_group_size", 0, 0, 64, "shadow ray group size (0 = the scene's groups.shadow_size)");
    p.add_int("workload.triangles_per_sphere", 0, 0, 64, "triangles per sphere (0 = the scene's value)");
    p.add_string("workload.group_order", std::string("pixel"),
                 "the order the Host issues groups to passes and ICCs, primary and shadow groups each among "
                 "themselves: pixel = the trace's (tiles row by row, shadow groups in pixel order); random = "
                 "shuffled (workload.group_seed); morton = by the Z-order of the group's pixel; strided = pass k, "
                 "ICC i takes group i*P + k of the P passes (each ICC a stretch of the image)",
                 {"pixel", "random", "morton", "strided"});
    p.add_int("workload.group_seed", 1, 0, 1000000000, "workload.group_order = random: the shuffle's seed");
    p.add_string("numerics.format", std::string("float32"),
                 "number format of the intersectors: float32, float64, fp1-E-M[-rtz][-ftz][-psiunnorm], each optionally "
                 "followed by -wt (numerics.rti_test = watertight)");
    p.add_string("numerics.rti_test", std::string("division_free"),
                 "ray-triangle test of the RTI: division_free = the paper's Eq. 2; watertight = Woop, Benthin and Wald "
                 "(JCGT 2013): no ray passes between triangles sharing an edge; same RTI latency and throughput, only hits "
                 "(and the shadow rays they place) may differ (same as the format suffix -wt; docs/ACCURACY.md §6)",
                 {"division_free", "watertight"});
    p.add_bool("numerics.psi_normalize", true,
               "false: the Plane-Sphere Intersector's adders do not renormalise (paper §4; same as the format "
               "suffix -psiunnorm; emulated, so float32 runs as fp1-8-23)");
    p.add_string("sim.functional", std::string("compute"),
                 "compute = intersectors compute with the math library (hits checked against the front end); "
                 "trace = plane-hit masks taken from the trace (faster, hits not checked)",
                 {"compute", "trace"});
    p.add_bool("sim.cull", true,
               "compute mode: skip, with a proof, the spheres a group's planes cannot hit when computing "
               "plane-hit masks (bit-identical masks; false tests every sphere, as the hardware does, and also "
               "finds the pair-less spheres a trace in the model's format carries)");
    p.add_string("sim.mode", std::string("event"),
                 "netlist = the machine as SystemC modules with ports, channels and one clock, every block stepped "
                 "every cycle, memories behind TLM-2.0 (the reference); event = exact event-driven stepping that "
                 "skips what cannot change (the same cycle counts and statistics, much faster; --vcd runs the netlist)",
                 {"event", "netlist"});
    p.retire_choice("sim.mode", "cycle",
                    "is retired: sim.mode = netlist steps every block in every cycle (the reference, docs/MODEL.md §2)");
    p.add_string("sim.rtl", std::string("none"),
                 "sim.mode = netlist: a block co-simulated as Verilog RTL in place of its C++ module (rtl/, made a "
                 "SystemC module by Verilator at build time), with the same cycles and statistics: "
                 "triangle_selector = the Triangle Selector with its Triangle FIFO (docs/MODEL.md §2)",
                 {"none", "triangle_selector"});
    p.add_string("sim.estimate", std::string("exact"),
                 "exact = simulate every pass; sample_passes = simulate every primary pass and a stratified "
                 "sample of the shadow passes and extrapolate total cycles, with a 95 % confidence half-width "
                 "(the other statistics then cover the simulated passes only); fifo_bound = a lower bound of "
                 "the exact total in closed form from the trace: every pass timed with unbounded Triangle, "
                 "PlaneID and First-Triangle-ID FIFOs (exact when none of them fills; the per-block "
                 "statistics are not computed)",
                 {"exact", "sample_passes", "fifo_bound"});
    p.add_real("sim.sample_fraction", 0.1, 1e-6, 1.0, "sample_passes: fraction of the shadow passes simulated (at least 2)");
    p.add_int("sim.sample_seed", 1, 0, 1000000000, "sample_passes: seeds the pass drawn in each stratum");
    p.add_int("sim.sync_cycles", 4096, 1, 1000000000, "cycles between watchdog checks, and (event mode) between SystemC time updates");
    p.add_int("sim.watchdog_cycles", 1000000, 1, 1000000000000,
              "stop with an error when nothing moves for this many cycles");
    add_memory_system_params(p);
    add_area_params(p);
    p.add_string("sim.fault", std::string("none"),
                 "fault injection, to provoke the watchdog: stuck_rti = ICC sim.fault_icc's Ray-Triangle "
                 "Intersector takes no pair; stuck_psi = its Plane-Sphere Intersector takes no sphere; or the "
                 "functional check: wrong_rti = the first ray-triangle test of that ICC that misses reports a "
                 "hit at distance 0 (needs sim.functional = compute); or the RTL check: rtl_full_early = that "
                 "ICC's RTL Triangle FIFO reports full one entry early (the broken variant built beside the RTL; "
                 "needs sim.rtl = triangle_selector)",
                 {"none", "stuck_rti", "stuck_psi", "wrong_rti", "rtl_full_early"});
    p.add_int("sim.fault_icc", 0, 0, 4095, "the ICC sim.fault applies to (it must have a group to stall or test)");
    return p;
}

NumFormat numerics_from_params(const ParamSet& p) {
    NumFormat f;
    try {
        f = NumFormat::parse(p.get_string("numerics.format"));
    } catch (const std::invalid_argument& e) {
        throw InputError(p.origin("numerics.format") + ": " + e.what());
    }
    if (p.is_given("numerics.rti_test")) {
        const bool wt = p.get_string("numerics.rti_test") == "watertight";
        if (!wt && f.rti == RtiTest::watertight)
            throw InputError(p.origin("numerics.rti_test") + ": division_free contradicts numerics.format '" + f.name() +
                             "'");
        if (wt) f.rti = RtiTest::watertight;
    }
    if (p.is_given("numerics.psi_normalize")) {
        const bool on = p.get_bool("numerics.psi_normalize");
        if (on && !f.psi_normalize)
            throw InputError(p.origin("numerics.psi_normalize") + ": true contradicts numerics.format '" + f.name() +
                             "'");
        try {
            f.set_psi_normalize(on);
        } catch (const std::invalid_argument& e) {
            throw InputError(p.origin("numerics.psi_normalize") + ": " + e.what());
        }
    }
    return f;
}

void resolve_numerics(ParamSet& p) {
    const NumFormat f = numerics_from_params(p);
    p.set("numerics.format=" + f.name());
    p.set(std::string("numerics.rti_test=") + (f.rti == RtiTest::watertight ? "watertight" : "division_free"));
    p.set(std::string("numerics.psi_normalize=") + (f.psi_normalize ? "true" : "false"));
}

SimConfig config_from_params(const ParamSet& p) {
    SimConfig c;
    c.iccs = std::uint32_t(p.get_int("machine.iccs"));
    c.clock_mhz = p.get_real("machine.clock_mhz");
    c.icc.psi.pipes = std::uint32_t(p.get_int("icc.psi_pipes"));
    c.icc.psi.stages = std::uint32_t(p.get_int("icc.psi_stages"));
    c.icc.rti.pipes = std::uint32_t(p.get_int("icc.rti_pipes"));
    c.icc.rti.stages = std::uint32_t(p.get_int("icc.rti_stages"));
    c.icc.decoder.select = p.get_string("icc.triangle_select") == "any" ? TriangleSelect::any : TriangleSelect::both;
    c.icc.fetcher.empty_cycles = std::uint32_t(p.get_int("icc.rdf_empty_cycles"));
    c.icc.sphere_fifo.depth = std::uint32_t(p.get_int("fifo.sphere_depth"));
    c.icc.triangle_fifo.depth = std::uint32_t(p.get_int("fifo.triangle_depth"));
    c.icc.planeid_fifo.depth = std::uint32_t(p.get_int("fifo.planeid_depth"));
    if (c.icc.planeid_fifo.depth == 0) c.icc.planeid_fifo.depth = c.icc.triangle_fifo.depth;
    c.icc.selector.policy = p.get_string("link.stall_policy") == "needed_full" ? StallPolicy::needed_full : StallPolicy::any_full;
    {
        // The stall latency: L = base + floor(per ICC x ICCs) (the small
        // epsilon keeps 1/16 x 48 at 3 rather than 2.999...).
        const double per = p.get_real("link.stall_latency_per_icc");
        const std::uint64_t L = std::uint64_t(p.get_int("link.stall_latency")) +
                                std::uint64_t(per * double(c.iccs) * (1 + 1e-12));
        const std::string key = p.get_int("link.stall_latency") == 0 && per > 0 ? "link.stall_latency_per_icc"
                                                                               : "link.stall_latency";
        const std::string what = p.origin(key) + ": a stall latency of " + std::to_string(L) + " cycles";
        if (L > 0 && c.icc.selector.policy != StallPolicy::any_full)
            throw InputError(what + " needs link.stall_policy = any_full: under needed_full an ICC stops the link "
                                    "only for a triangle it needs, which a hold raised cycles earlier cannot know");
        if (L >= c.icc.triangle_fifo.depth)
            throw InputError(what + " needs a Triangle FIFO deeper than that (fifo.triangle_depth = " +
                             std::to_string(c.icc.triangle_fifo.depth) +
                             "): the FIFO raises its hold at depth - latency entries so that the records still on "
                             "the link fit; a deeper latency would overflow it");
        c.icc.selector.stall_latency = std::uint32_t(L);
        c.icc.selector.resume_occupancy = p.get_int("link.resume_occupancy");
        const std::int64_t R = c.icc.selector.resume_occupancy;
        const std::uint64_t at = c.icc.selector.hold_at(c.icc.triangle_fifo.depth);
        if (R >= 0 && std::uint64_t(R) >= at)
            throw InputError(p.origin("link.resume_occupancy") + ": link.resume_occupancy = " + std::to_string(R) +
                             " must be below the occupancy at which a Triangle FIFO stops the link (" +
                             std::to_string(at) + " = fifo.triangle_depth " + std::to_string(c.icc.triangle_fifo.depth) +
                             " - stall latency " + std::to_string(L) + ")");
    }
    c.sphere_record_bytes = std::uint32_t(p.get_int("link.sphere_record_bytes"));
    c.triangle_record_bytes = std::uint32_t(p.get_int("link.triangle_record_bytes"));
    c.icc.output.entry_bytes = std::uint32_t(p.get_int("link.result_bytes"));
    c.icc.min_distance.entry_bytes = c.icc.output.entry_bytes;
    c.pass_overhead_cycles = std::uint64_t(p.get_int("host.pass_overhead_cycles"));
    c.overlap_passes = p.get_bool("host.overlap_passes");
    c.triangle_lag_cycles = std::uint64_t(p.get_int("link.triangle_lag_cycles"));
    c.group_size = std::uint32_t(p.get_int("workload.group_size"));
    c.shadow_group_size = std::uint32_t(p.get_int("workload.shadow_group_size"));
    c.triangles_per_sphere = std::uint32_t(p.get_int("workload.triangles_per_sphere"));
    c.group_order = group_order_from_name(p.get_string("workload.group_order"));
    c.group_seed = std::uint64_t(p.get_int("workload.group_seed"));
    c.format = numerics_from_params(p);
    c.functional = p.get_string("sim.functional") == "trace" ? FunctionalMode::trace : FunctionalMode::compute;
    c.cull = p.get_bool("sim.cull");
    const std::string mode = p.get_string("sim.mode");
    c.mode = mode == "netlist" ? SimMode::netlist : SimMode::event;
    c.rtl = p.get_string("sim.rtl") == "triangle_selector" ? RtlBlock::triangle_selector : RtlBlock::none;
    c.sync_cycles = std::uint64_t(p.get_int("sim.sync_cycles"));
    const std::string estimate = p.get_string("sim.estimate");
    c.estimate = estimate == "sample_passes" ? Estimate::sample_passes
                 : estimate == "fifo_bound"  ? Estimate::fifo_bound
                                             : Estimate::exact;
    c.sample_fraction = p.get_real("sim.sample_fraction");
    c.sample_seed = std::uint64_t(p.get_int("sim.sample_seed"));
    c.watchdog_cycles = std::uint64_t(p.get_int("sim.watchdog_cycles"));
    memory_system_from_params(p, c);
    c.area = area_from_params(p);
    const std::string fault = p.get_string("sim.fault");
    c.fault = fault == "stuck_rti"   ? Fault::stuck_rti
              : fault == "stuck_psi" ? Fault::stuck_psi
              : fault == "wrong_rti" ? Fault::wrong_rti
              : fault == "rtl_full_early" ? Fault::rtl_full_early
                                     : Fault::none;
    c.fault_icc = std::uint32_t(p.get_int("sim.fault_icc"));
    if (c.estimate == Estimate::fifo_bound && c.fault != Fault::none)
        throw InputError(p.origin("sim.fault") + ": sim.fault = " + fault +
                         " needs a simulation, but sim.estimate = fifo_bound computes the cycles in closed form");
    if (c.rtl != RtlBlock::none) {
        const std::string what = p.origin("sim.rtl") + ": sim.rtl = " + rtl_block_name(c.rtl);
        if (!rtl_built())
            throw InputError(what + " needs the RTL co-simulation, which this build lacks (Verilator was not found "
                                    "when it was configured): install verilator (tools/install-deps.sh) and configure "
                                    "the build again");
        if (c.mode != SimMode::netlist)
            throw InputError(what + " replaces a block of the netlist: it needs sim.mode = netlist (here " +
                             sim_mode_name(c.mode) + ")");
        if (c.estimate == Estimate::fifo_bound)
            throw InputError(what + " needs a simulation, but sim.estimate = fifo_bound computes the cycles in "
                                    "closed form");
        if (!c.icc.selector.plain())
            throw InputError(what + " has the Triangle FIFO's plain hold only (full, in the same cycle): it needs "
                                    "link.stall_latency = 0, link.stall_latency_per_icc = 0 and "
                                    "link.resume_occupancy = -1");
    }
    if (c.fault == Fault::rtl_full_early && c.rtl != RtlBlock::triangle_selector)
        throw InputError(p.origin("sim.fault") +
                         ": sim.fault = rtl_full_early breaks the RTL Triangle FIFO: it needs sim.rtl = triangle_selector");
    if (c.fault == Fault::wrong_rti && c.functional != FunctionalMode::compute)
        throw InputError(p.origin("sim.fault") +
                         ": sim.fault = wrong_rti needs sim.functional = compute (the trace mode takes its answers "
                         "from the trace and checks none)");
    if (c.overlap_passes && c.estimate == Estimate::sample_passes)
        throw InputError(p.origin("host.overlap_passes") +
                         ": overlapped passes depend on the pass before them, but sim.estimate = sample_passes "
                         "simulates passes alone; use sim.estimate = exact or fifo_bound");
    if (c.fault_icc >= c.iccs)
        throw InputError(p.origin("sim.fault_icc") + ": sim.fault_icc = " + std::to_string(c.fault_icc) +
                         " but the machine has " + std::to_string(c.iccs) + " ICCs");
    return c;
}

const WorkloadKey kWorkloadKeys[3] = {
    {"workload.group_size", "groups.size", "primary ray group size"},
    {"workload.shadow_group_size", "groups.shadow_size", "shadow ray group size"},
    {"workload.triangles_per_sphere", "spheres.triangles_per_sphere", "triangles per sphere"},
};

bool result_neutral_key(const std::string& key) {
    return key == "sim.mode" || key == "sim.functional" || key == "sim.sync_cycles" || key == "sim.watchdog_cycles" ||
           key == "sim.cull" || key == "sim.rtl";
}

bool rtl_built() {
#ifdef RAPLAS_HAVE_RTL
    return true;
#else
    return false;
#endif
}

std::string inert_config_key(const ParamSet& p, const std::string& key) {
    const std::string estimate = p.get_string("sim.estimate"), system = p.get_string("memory.system");
    if ((key == "sim.sample_fraction" || key == "sim.sample_seed") && estimate != "sample_passes")
        return "applies only with sim.estimate = sample_passes (here " + estimate + ")";
    if (key == "workload.group_seed" && p.get_string("workload.group_order") != "random")
        return "seeds workload.group_order = random (here " + p.get_string("workload.group_order") + ")";
    if (key == "sim.fault_icc" && p.get_string("sim.fault") == "none")
        return "names the ICC of sim.fault, and sim.fault = none";
    if ((key == "memory.pe" || key == "memory.fetch_records_per_cycle") && system == "streaming")
        return "applies only to the baseline memory systems (memory.system = shared or distributed; here streaming)";
    if (key == "memory.shared_spheres" && system != "shared")
        return "applies only with memory.system = shared (here " + system + ")";
    if (key == "memory.distributed_fetch" && system != "distributed")
        return "applies only with memory.system = distributed (here " + system + ")";
    return "";
}

std::string inert_scene_key(const ParamSet& p, const std::string& key) {
    for (const WorkloadKey& w : kWorkloadKeys)
        if (key == w.scene_key && p.get_int(w.config_key) != 0)
            return std::string("the machine config's ") + w.config_key + " = " + std::to_string(p.get_int(w.config_key)) +
                   " decides the " + w.what + " (set " + w.config_key + " instead, or " + w.config_key +
                   " = 0 to take the scene's " + w.scene_key + ")";
    return "";
}

void resolve_workload(ParamSet& p, std::uint32_t group_size, std::uint32_t shadow_group_size,
                      std::uint32_t triangles_per_sphere) {
    const std::uint32_t v[3] = {group_size, shadow_group_size, triangles_per_sphere};
    for (int i = 0; i < 3; ++i)
        if (p.get_int(kWorkloadKeys[i].config_key) == 0 && v[i] != 0)
            p.set(std::string(kWorkloadKeys[i].config_key) + "=" + std::to_string(v[i]), "the workload");
}

}  // namespace raplas::model
