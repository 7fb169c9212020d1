// Steps 2-4: ray groups and their 2N ray-planes. A group is N x N rays from
// one origin through the cell centres of a grid (the screen tile for primary
// rays, the area light for shadow rays); row v's plane holds the origin and
// grid row v, column h's plane the origin and grid column h; ray (h, v) is
// the line where they meet.
#pragma once

#include <cstdint>
#include <vector>

#include "raplas/core/intersect.hpp"
#include "raplas/scene/scene.hpp"

namespace raplas {

enum class GroupKind : std::uint8_t { primary = 0, shadow = 1 };

struct RayGroup {
    GroupKind kind = GroupKind::primary;
    std::uint32_t n = 0;            // N: N x N rays, 2N planes
    std::int32_t px = 0, py = 0;    // primary: tile's first pixel; shadow: the pixel it shades
    Vec3f origin;
    Vec3d grid_corner, du, dv;      // grid point (h, v) = corner + (h+.5) du + (v+.5) dv
    float tmax = 0;                 // ray parameter bound (the light sample is at t = 1)
    std::uint64_t row_valid = 0;    // bit v: row v has pixels inside the image
    std::uint64_t col_valid = 0;    // bit h
    std::vector<Plane> planes;      // [0, N): row planes, [N, 2N): column planes

    std::uint32_t plane_count() const { return 2 * n; }
    bool ray_valid(std::uint32_t h, std::uint32_t v) const { return (row_valid >> v & 1) && (col_valid >> h & 1); }
};

// The ray (h, v) of a group, exactly as traced.
Ray group_ray(const RayGroup& g, std::uint32_t h, std::uint32_t v);

// Camera screen: pixel (x, y) centre = corner + (x+.5) du + (y+.5) dv.
struct Screen {
    Vec3d eye, corner, du, dv;
};
Screen make_screen(const Scene& s);

// Primary groups: N x N tiles in row-major tile order.
std::vector<RayGroup> primary_groups(const Scene& s);
// Shadow group from a surface point (already offset) to an N x N grid on the light.
RayGroup shadow_group(const Scene& s, const Vec3f& origin, std::int32_t px, std::int32_t py);

// Fills g.planes from the group's origin and grid (host-side, double, stored as float).
void build_planes(RayGroup& g);

}  // namespace raplas
