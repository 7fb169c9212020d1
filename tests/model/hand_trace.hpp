// Hand-made traces whose cycle counts can be derived in closed form.
#pragma once

#include "raplas/frontend/trace_io.hpp"

namespace raplas::test {

// S spheres of one triangle each, along the x axis; one primary group of
// size n whose planes hit a chosen subset of spheres with masks (rows, cols).
// Spheres not in `hit` are missed by every plane.
inline Trace hand_trace(std::uint32_t spheres, std::uint32_t n, std::uint64_t rows, std::uint64_t cols,
                        const std::vector<bool>& hit, std::uint32_t groups = 1) {
    Trace t;
    t.scene_name = "hand";
    t.format = NumFormat::float32();
    t.width = t.height = n;
    t.group_size = t.shadow_group_size = n;
    t.tris_per_sphere = 1;
    for (std::uint32_t s = 0; s < spheres; ++s) {
        t.spheres.push_back({Vec3f(float(s) * 10.f, 0.f, 0.f), 1.f});
        t.first_tri.push_back(s);
        t.tri_count.push_back(1);
        TriangleRec tr;
        tr.v0 = Vec3f(float(s) * 10.f, 0.f, 0.f);
        tr.e1 = Vec3f(1.f, 0.f, 0.f);
        tr.e2 = Vec3f(0.f, 1.f, 0.f);
        tr.n = Vec3f(0.f, 0.f, 1.f);
        t.triangles.push_back(tr);
        t.tri_mesh_index.push_back(std::int32_t(s));
    }
    t.primary_groups = groups;
    for (std::uint32_t gi = 0; gi < groups; ++gi) {
        TraceGroup g;
        g.kind = GroupKind::primary;
        g.n = n;
        g.origin = Vec3f(0.f, 0.f, 100.f);
        g.tmax = 1e30f;
        g.row_valid = n == 64 ? ~0ull : (1ull << n) - 1;
        g.col_valid = g.row_valid;
        g.planes.assign(2 * n, Plane{Vec3f(0.f, 0.f, 1.f), -1000.f});  // far from every sphere
        g.dirs.assign(std::size_t(n) * n, Vec3f(0.f, 0.f, -1.f));
        for (std::uint32_t s = 0; s < spheres; ++s)
            if (hit[s]) g.sphere_hits.push_back({s, rows, cols});
        g.counts.sphere_hits = g.sphere_hits.size();
        g.hits.assign(std::size_t(n) * n, Hit{});
        t.groups.push_back(g);
    }
    return t;
}

// Marks the spheres in `pairless` of every group as cut by row planes only
// or column planes only (a trace for icc.triangle_select = any). They must
// not be hit spheres of the group.
inline void add_pairless(Trace& t, const std::vector<bool>& pairless) {
    t.pairless = true;
    for (TraceGroup& g : t.groups) {
        g.pairless.clear();
        g.counts.pairless = 0;
        for (std::uint32_t s = 0; s < pairless.size(); ++s) {
            if (!pairless[s]) continue;
            add_to_runs(g.pairless, s);
            ++g.counts.pairless;
        }
    }
}

}  // namespace raplas::test
