#include "baseline_memory.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <queue>
#include <utility>

#include "raplas/core/bits.hpp"
#include "raplas/util/cpu_time.hpp"
#include "raplas/util/error.hpp"

namespace raplas::model {

const char* memory_system_name(MemorySystem s) {
    switch (s) {
        case MemorySystem::shared: return "shared";
        case MemorySystem::distributed: return "distributed";
        default: return "streaming";
    }
}

GroupWork group_work(const Trace& t, const TraceGroup& g, bool primary, TriangleSelect select) {
    GroupWork w;
    w.primary = primary;
    for (const SphereHitRec& h : g.sphere_hits) {
        const std::uint64_t n = t.tri_count[h.sphere];
        w.triangles_needed += n;
        w.rt_tests += std::uint64_t(bit_count(h.rows)) * std::uint64_t(bit_count(h.cols)) * n;
    }
    // (a run's spheres hold consecutive triangles: a trace's spheres follow one another's triangles)
    if (select == TriangleSelect::any)
        for (const SphereRun& r : g.pairless) {
            const std::uint32_t last = r.end() - 1;
            w.pairless_triangles += std::uint64_t(t.first_tri[last]) + t.tri_count[last] - t.first_tri[r.first];
        }
    w.triangles_needed += w.pairless_triangles;
    return w;
}

std::vector<GroupWork> group_work(const Trace& t, TriangleSelect select) {
    std::vector<GroupWork> w(t.groups.size());
    for (std::size_t g = 0; g < t.groups.size(); ++g) w[g] = group_work(t, t.groups[g], g < t.primary_groups, select);
    return w;
}

std::uint64_t group_rti_cycles(const GroupWork& w, const SimConfig& cfg) {
    const std::uint64_t pipes = cfg.icc.rti.pipes;
    return (w.rt_tests + pipes - 1) / pipes + w.pairless_triangles * cfg.icc.fetcher.empty_cycles;
}

std::uint64_t list_schedule_makespan(const std::vector<std::uint64_t>& durations, std::uint32_t iccs) {
    // (time the ICC is free, ICC index), smallest first.
    using Slot = std::pair<std::uint64_t, std::uint32_t>;
    std::priority_queue<Slot, std::vector<Slot>, std::greater<Slot>> free;
    const std::uint32_t k = std::max<std::uint32_t>(1, std::min<std::uint64_t>(iccs, durations.size()));
    for (std::uint32_t i = 0; i < k; ++i) free.push({0, i});
    std::uint64_t end = 0;
    for (std::uint64_t d : durations) {
        Slot s = free.top();
        free.pop();
        s.first += d;
        end = std::max(end, s.first);
        free.push(s);
    }
    return end;
}

namespace {

// Cycles a port delivering r records per cycle needs for n records.
std::uint64_t port_cycles(std::uint64_t n, double r) {
    if (n == 0) return 0;
    return std::uint64_t(std::ceil(double(n) / r - 1e-9));
}

// Makespan of the primary groups, then of the shadow groups (a shadow group's
// origin is a primary hit, so none starts before every primary group is done).
std::uint64_t phased_makespan(const std::vector<GroupWork>& w, const std::vector<std::uint64_t>& d, std::uint32_t k) {
    std::vector<std::uint64_t> p, s;
    for (std::size_t g = 0; g < w.size(); ++g) (w[g].primary ? p : s).push_back(d[g]);
    return list_schedule_makespan(p, k) + list_schedule_makespan(s, k);
}

}  // namespace

SimResult baseline_result(const Trace& t, const SimConfig& cfg, MemoryStats& st,
                          const std::vector<std::uint64_t>* group_cycles) {
    const std::vector<GroupWork> w = group_work(t, cfg.icc.decoder.select);
    const std::uint64_t S = t.spheres.size(), T = t.triangles.size(), G = w.size();
    const std::uint32_t k = cfg.iccs;
    const double r = cfg.memory.records_per_cycle;
    st = MemoryStats{};
    st.system = cfg.memory.system;
    st.area = machine_area(cfg, area_workload(t, cfg));

    std::vector<std::uint64_t> rti(G);  // each group's RTI cycles
    for (std::size_t g = 0; g < G; ++g) rti[g] = group_rti_cycles(w[g], cfg);
    st.pe_bound_cycles = phased_makespan(w, rti, k);

    SimResult res;
    res.host.groups = G;
    res.iccs.resize(k);
    std::uint64_t total = 0;
    if (cfg.memory.system == MemorySystem::shared) {
        // One port serves every ICC's requests; with ideal PEs some request is
        // always pending, so any work-conserving arbiter keeps the port busy
        // until the last one: the time is the phase's requests over the rate.
        for (bool primary : {true, false}) {
            std::uint64_t spheres = 0, tris = 0;
            std::vector<std::uint64_t> d;
            for (std::size_t g = 0; g < G; ++g) {
                if (w[g].primary != primary) continue;
                spheres += cfg.memory.shared_fetch_spheres ? S : 0;
                tris += w[g].triangles_needed;
                d.push_back(rti[g]);
            }
            const std::uint64_t mem = port_cycles(spheres + tris, r);
            const std::uint64_t pe = list_schedule_makespan(d, k);
            st.sphere_records_read += spheres;
            st.triangle_records_read += tris;
            st.memory_bound_cycles += mem;
            total += cfg.memory.pe_rti_bound ? std::max(mem, pe) : mem;
        }
    } else if (cfg.memory.system == MemorySystem::distributed) {
        // Every ICC works through its own groups on its own copy; the groups
        // go to whichever ICC is free first.
        std::vector<std::uint64_t> mem(G), dur(G);
        for (std::size_t g = 0; g < G; ++g) {
            if (cfg.memory.distributed_stream) {
                if (!group_cycles || group_cycles->size() != G)
                    throw std::logic_error("distributed stream fetch needs one-ICC pass cycles per group");
                mem[g] = std::max(S, T);
                dur[g] = (*group_cycles)[g];
                st.triangle_records_read += T;
            } else {
                // Spheres from the Sphere Memory copy, the needed triangles from the
                // Triangle Memory copy, on two ports at once.
                mem[g] = std::max(port_cycles(S, r), port_cycles(w[g].triangles_needed, r));
                dur[g] = cfg.memory.pe_rti_bound ? std::max(mem[g], rti[g]) : mem[g];
                st.triangle_records_read += w[g].triangles_needed;
            }
            st.sphere_records_read += S;
        }
        st.memory_bound_cycles = phased_makespan(w, mem, k);
        total = phased_makespan(w, dur, k);
    } else {
        throw std::logic_error("baseline_result: streaming is the SystemC model");
    }
    res.total_cycles = total;
    // Per-ICC figures: groups and ray-triangle work in issue order, round robin
    // (the figures the report sums; the time above does not depend on them).
    for (std::size_t g = 0; g < G; ++g) {
        IccSnapshot& s = res.iccs[g % k];
        ++s.icc.groups;
        s.rti.tests += w[g].rt_tests;
        s.rti.busy_cycles += rti[g];
    }
    for (IccSnapshot& s : res.iccs) s.icc.pass_cycles = total;
    return res;
}

namespace {

// Streaming: the bounds with ideal PEs (one record per cycle on each link, every
// pass streams all spheres and triangles) and with ideal links (each pass as
// long as its slowest ICC's RTI work, folded as the groups are released).
void streaming_bounds(const Trace& t, const SimConfig& cfg, const SimResult& r, std::uint64_t pe_bound, MemoryStats& st) {
    const std::uint64_t S = t.spheres.size(), T = t.triangles.size();
    st.sphere_records_read = r.sphere_link.records_sent;
    st.triangle_records_read = r.triangle_link.records_sent;
    st.memory_bound_cycles = r.host.passes * std::max(S, T);
    st.pe_bound_cycles = pe_bound;
    st.area = machine_area(cfg, area_workload(t, cfg));
}

}  // namespace

SimResult simulate_system(GroupSource& groups, const SimConfig& cfg, MemoryStats& stats, const SimOptions& opt) {
    if (cfg.memory.system != MemorySystem::streaming) {
        if (!groups.total_known()) throw std::logic_error("simulate_system: a baseline memory system needs the whole trace");
        SimResult r = simulate_system(groups.header(), cfg, stats, opt);
        if (r.error.empty()) groups.release(groups.total_groups());  // the observers see every group
        return r;
    }
    const Trace& t = groups.header();
    check_trace_reading(t, cfg);
    // The PE bound: each pass's slowest group, passes of k groups in each phase.
    const std::uint32_t k = cfg.iccs, primary = t.primary_groups;
    std::uint64_t pe_bound = 0, pass_max = 0;
    groups.observers.push_back([&, k, primary](std::size_t i, const TraceGroup& g) {
        if ((i < primary ? i : i - primary) % k == 0) pe_bound += std::exchange(pass_max, 0);
        pass_max = std::max(pass_max, group_rti_cycles(group_work(t, g, i < primary, cfg.icc.decoder.select), cfg));
    });
    SimResult r;
    {
        // The observers (this bound, and the caller's: the workload's counts
        // and hash) run on their own thread, off the model's.
        ObserveAhead ahead(groups);
        r = simulate(groups, cfg, opt);
        ahead.stop();
        r.observers_cpu_s = ahead.cpu_s();
    }
    groups.observers.pop_back();
    stats = MemoryStats{};
    if (!r.error.empty()) return r;  // the caller reports it
    streaming_bounds(t, cfg, r, pe_bound + pass_max, stats);
    return r;
}

SimResult simulate_system(const Trace& t, const SimConfig& cfg, MemoryStats& stats, const SimOptions& opt) {
    if (cfg.memory.system == MemorySystem::streaming) {
        TraceSource source(t);
        return simulate_system(source, cfg, stats, opt);
    }
    check_trace_reading(t, cfg);
    if (opt.shards > 1)
        throw InputError(std::string("memory.system = ") + memory_system_name(cfg.memory.system) +
                         " is computed from the whole workload: it has no shards");
    if (!opt.vcd_path.empty())
        throw InputError(std::string("--vcd: memory.system = ") + memory_system_name(cfg.memory.system) +
                         " is computed in closed form, it has no waveform");
    if (cfg.memory.system == MemorySystem::distributed && cfg.memory.distributed_stream) {
        // Each group on a one-ICC streaming machine: exact pass cycles from the
        // model (trace mode: the cycles do not depend on the functional mode).
        SimConfig one = cfg;
        one.iccs = 1;
        one.memory.system = MemorySystem::streaming;
        one.functional = FunctionalMode::trace;
        SimOptions o;
        o.progress = opt.progress;
        const SimResult r1 = simulate(t, one, o);
        if (!r1.error.empty()) return r1;
        std::vector<std::uint64_t> cycles = r1.pass_cycles;
        SimResult r = baseline_result(t, cfg, stats, &cycles);
        r.model_wall_s = r1.model_wall_s;
        r.model_cpu_s = r1.model_cpu_s;
        r.loads_cpu_s = r1.loads_cpu_s;
        r.load_waits_s = r1.load_waits_s;
        return r;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = thread_cpu_s();
    SimResult r = baseline_result(t, cfg, stats);
    r.model_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.model_cpu_s = thread_cpu_s() - cpu0;
    return r;
}

}  // namespace raplas::model
