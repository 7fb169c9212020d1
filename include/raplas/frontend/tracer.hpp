// Steps 5-6: the RAPLAS intersection method over a ray group. For every
// sphere, the 2N plane tests give a row mask H and a column mask V; when both
// are non-empty every ray in H x V is tested against every triangle of the
// sphere, keeping the nearest hit per ray. The math is the core library's,
// in the chosen number format.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "raplas/core/numfmt.hpp"
#include "raplas/frontend/raygroups.hpp"
#include "raplas/frontend/spheres.hpp"

namespace raplas {

struct GroupCounts {
    std::uint64_t plane_tests = 0;  // spheres x planes of the group (valid planes)
    std::uint64_t sphere_hits = 0;  // spheres with a row and a column plane hit
    std::uint64_t rt_tests = 0;     // ray-triangle tests
    // Spheres cut by valid row planes only or valid column planes only: no
    // (ray, triangle) pair, but their triangles are kept by a Triangle
    // Selector that keeps every sphere any plane cuts (icc.triangle_select =
    // any). Counted only when the tracer is asked for them.
    std::uint64_t pairless = 0;
    GroupCounts& operator+=(const GroupCounts& o) {
        plane_tests += o.plane_tests;
        sphere_hits += o.sphere_hits;
        rt_tests += o.rt_tests;
        pairless += o.pairless;
        return *this;
    }
};

struct GroupResult {
    std::vector<Hit> hits;  // N*N, index v*N + h; invalid rays stay misses
    GroupCounts counts;
    std::vector<SphereHitRec> sphere_list;     // filled when recording (trace)
    std::vector<SphereRun> pairless;           // filled when recording with pairless on
    std::vector<std::uint32_t> ray_rt_tests;   // per ray, filled when per_ray is on
    std::vector<std::uint32_t> ray_sphere_hits;
};

class Tracer {
public:
    // cull: skip, with a proof, the spheres a group's planes cannot hit
    // (core/cull.hpp); the results are bit-identical either way. threads:
    // with 2 or more, the sphere tree is built while the records are loaded.
    Tracer(const SphereSet& spheres, const NumFormat& format, bool cull = true, unsigned threads = 1);
    ~Tracer();
    Tracer(const Tracer&) = delete;
    Tracer& operator=(const Tracer&) = delete;

    // pairless: also find the spheres cut by row planes only or column planes
    // only (GroupCounts::pairless; GroupResult::pairless when recording).
    void trace(const RayGroup& g, GroupResult& out, bool record, bool per_ray, bool pairless = false) const;
    // Nearest hit over every triangle, no culling (the reference for tests).
    Hit brute_force(const Ray& r) const;
    const NumFormat& format() const { return format_; }
    const SphereSet& spheres() const { return spheres_; }

    struct Impl;

private:
    const SphereSet& spheres_;
    NumFormat format_;
    std::unique_ptr<Impl> impl_;
};

}  // namespace raplas
