#include "memory_estimate.hpp"

#include <algorithm>
#include <string>

#include "top.hpp"

namespace raplas::model {

namespace {
// Bookkeeping of an ICC beyond its blocks' sizes, measured when its 13
// blocks were SystemC modules (names, hierarchy, process tables): a margin
// now that they are plain classes (docs/MEMORY.md).
constexpr double kSystemCPerIcc = 8 * 1024;
// The netlist (sim.mode = netlist) of an ICC: its 9 modules, 4 FIFO channels,
// some 60 ports, 8 signals and 10 processes with their SystemC bookkeeping.
// Measured: peak RSS of a netlist run over an event run, per ICC, 63 KB
// (512 ICCs against 64, docs/MEMORY.md).
constexpr double kNetlistPerIcc = 64 * 1024;
}  // namespace

std::vector<MemoryItem> model_memory(const SimConfig& c, const TraceShape& t) {
    const double fb = format_bytes_per_value(c.format);
    const bool compute = c.functional == FunctionalMode::compute;
    const std::uint32_t n = std::max(t.group_size, t.shadow_group_size);
    const double groups = double(t.primary_groups + t.shadow_groups);
    const double hits_per_group = groups > 0 ? (t.primary_sphere_hits + t.shadow_sphere_hits) / groups : 0;
    // Every ICC: its FIFOs at full depth (the Sphere FIFO is a counter), RTI
    // and PSI pipelines, statistics and SystemC bookkeeping. ICCs that get a
    // group (at most one per group): Min-distance Memory and the group
    // unit's planes, rays (and their directions by component) and sphere-hit list.
    const double fifo = double(c.icc.triangle_fifo.depth) * sizeof(TriWork) +
                        double(c.icc.planeid_fifo.depth) * (sizeof(PlaneIdEntry) + sizeof(FirstTriEntry));
    const double per_icc = sizeof(Icc) + kSystemCPerIcc + double(c.icc.rti.stages) * (c.icc.rti.pipes * sizeof(RtiOp) + 4) +
                           (c.icc.psi.stages + 2.0) * sizeof(PsiResult) + sizeof(IccSnapshot);
    double per_active = double(n) * n * sizeof(Hit);
    // (pair-less spheres: under icc.triangle_select = any, kept as runs by the
    // group unit and, in event mode, one queued-sphere record each)
    const bool any = c.icc.decoder.select == TriangleSelect::any;
    const double runs_per_group = groups > 0 && any ? t.pairless_runs / groups : 0;
    const double pairless_per_group = groups > 0 && any ? t.pairless_spheres / groups : 0;
    if (compute)
        per_active += 2.0 * n * 4 * fb + double(n) * n * (8 + 3) * fb + 1.5 * hits_per_group * sizeof(SphereHitRec) +
                      1.5 * runs_per_group * sizeof(SphereRun);
    const double active = std::min(double(c.iccs), std::max(groups, 1.0));
    std::vector<MemoryItem> items;
    items.push_back({std::to_string(c.iccs) + " ICCs x FIFO depths " + std::to_string(c.icc.triangle_fifo.depth) + "/" +
                         std::to_string(c.icc.planeid_fifo.depth) + " (Triangle/PlaneID)",
                     double(c.iccs) * fifo});
    items.push_back({std::to_string(c.iccs) + " ICCs' pipelines and group state", double(c.iccs) * per_icc + active * per_active});
    if (c.mode == SimMode::netlist)
        items.push_back({std::to_string(c.iccs) + " ICCs' modules, ports and signals (sim.mode = netlist)",
                         double(c.iccs) * kNetlistPerIcc});
    // Sphere and Triangle Memory; the functional model's geometry in the
    // format; event mode: every ICC's sphere hits of a pass in one list.
    double shared = double(t.spheres) * (sizeof(SphereRecord)) + double(t.triangles) * (sizeof(TriangleRec) + 4);
    if (compute) shared += double(t.spheres) * 4 * fb + double(t.triangles) * 12 * fb;
    if (c.mode == SimMode::event)  // queued-sphere events; the bucket queues, one entry per sphere and triangle
        shared += active * (hits_per_group + pairless_per_group) * 24 + double(t.spheres + t.triangles) * 4;
    items.push_back({"stream memories (" + std::to_string(t.spheres) + " spheres, " + std::to_string(t.triangles) +
                         " triangles)",
                     shared});
    return items;
}

}  // namespace raplas::model
