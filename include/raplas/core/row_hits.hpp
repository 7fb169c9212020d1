// One triangle against a row of rays that share an origin and (tmin, tmax):
// rays_hit_triangle_native (intersect.hpp) compiled for AVX2 as well as the
// baseline; the loader picks one per machine. There is no FMA either way
// (-ffp-contract=off), so every hit and distance is bit-identical to the
// ray-by-ray division-free test. Used by the front end's tracer and by the
// models' Ray-Triangle Intersector in the compute functional mode.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "raplas/core/intersect.hpp"

namespace raplas {

bool row_hits(const float o[3], float tmin, float tmax, const float* dx, const float* dy, const float* dz,
              std::size_t count, const TriA<ArithF32>& tr, std::uint8_t* hit, float* t);
bool row_hits(const double o[3], double tmin, double tmax, const double* dx, const double* dy, const double* dz,
              std::size_t count, const TriA<ArithF64>& tr, std::uint8_t* hit, double* t);

// The rays' directions by component (dx[i], dy[i], dz[i]), as row_hits takes them.
template <class A>
void directions_by_component(const std::vector<RayA<A>>& rays, std::vector<typename A::T>& dx,
                             std::vector<typename A::T>& dy, std::vector<typename A::T>& dz) {
    dx.resize(rays.size());
    dy.resize(rays.size());
    dz.resize(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        dx[i] = rays[i].d[0];
        dy[i] = rays[i].d[1];
        dz[i] = rays[i].d[2];
    }
}

}  // namespace raplas
