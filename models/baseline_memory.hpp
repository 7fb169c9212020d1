// The memory systems of the paper's Figure 5 (§5.2) on one trace: the
// streaming machine (the SystemC model of top.hpp) and two baselines computed
// in closed form from the same trace, a shared memory (one memory port,
// arbitrated among the ICCs) and a distributed memory (each ICC its own copy
// of Sphere and Triangle Memory); each with its area (models/area.hpp).
// docs/MODEL.md §6 gives every formula and the reasoning behind it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "area.hpp"
#include "config.hpp"
#include "top.hpp"

namespace raplas::model {

const char* memory_system_name(MemorySystem s);

// What one ray group asks of a memory system: what its Triangle Selector
// would keep under the reading `select` (docs/MODEL.md §3, §6).
struct GroupWork {
    std::uint64_t triangles_needed = 0;  // triangles kept: of the spheres cut by a row and a column plane,
                                         // and under `any` also of those cut by row or column planes only
    std::uint64_t pairless_triangles = 0;  // ... of which with no (ray, triangle) pair (`any` only)
    std::uint64_t rt_tests = 0;          // ray-triangle tests: sum of |rows| x |cols| x triangles
    bool primary = true;
};
std::vector<GroupWork> group_work(const Trace& t, TriangleSelect select = TriangleSelect::both);
// ... of one group of trace t (only t's spheres are read).
GroupWork group_work(const Trace& t, const TraceGroup& g, bool primary, TriangleSelect select);
// An ICC's Ray-Triangle Intersector time for a group (memory.pe = rti, and
// the streaming machine's PE bound): its tests over the pipes, plus
// icc.rdf_empty_cycles for each triangle with no pair.
std::uint64_t group_rti_cycles(const GroupWork& w, const SimConfig& cfg);

// Greedy list scheduling in issue order: each job goes to the ICC that is free
// first (ties: lowest index); returns the time the last job ends.
std::uint64_t list_schedule_makespan(const std::vector<std::uint64_t>& durations, std::uint32_t iccs);

struct MemoryStats {
    MemorySystem system = MemorySystem::streaming;
    std::uint64_t sphere_records_read = 0;    // records read out of the memories (all copies)
    std::uint64_t triangle_records_read = 0;
    std::uint64_t memory_bound_cycles = 0;    // the system's time with ideal PEs
    std::uint64_t pe_bound_cycles = 0;        // the time with ideal memories: RTI work only
    AreaBreakdown area;                       // of the system on the trace's workload
};

// A baseline's result from the trace alone. group_cycles: for the distributed
// system with memory.distributed_fetch = stream, each group's cycles on one
// streaming ICC (pass_cycles of a one-ICC run), else ignored.
SimResult baseline_result(const Trace& t, const SimConfig& cfg, MemoryStats& stats,
                          const std::vector<std::uint64_t>* group_cycles = nullptr);

// Runs the configured memory system: the SystemC model for streaming (and the
// one-ICC streaming run a distributed system with stream fetch needs), the
// closed form for the baselines. One call per process (SystemC).
SimResult simulate_system(const Trace& t, const SimConfig& cfg, MemoryStats& stats, const SimOptions& opt = {});
// The same with the groups from a source (a stream from the front end); the
// baselines need the whole trace (a source whose total is known).
SimResult simulate_system(GroupSource& groups, const SimConfig& cfg, MemoryStats& stats, const SimOptions& opt = {});

}  // namespace raplas::model
