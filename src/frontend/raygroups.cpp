#include "raplas/frontend/raygroups.hpp"

#include <cmath>
#include <limits>

namespace raplas {

Ray group_ray(const RayGroup& g, std::uint32_t h, std::uint32_t v) {
    Vec3d target = g.grid_corner + g.du * (h + 0.5) + g.dv * (v + 0.5);
    Ray r;
    r.o = g.origin;
    r.d = to_f(target - to_d(g.origin));
    r.tmin = 0.0f;
    r.tmax = g.tmax;
    return r;
}

void build_planes(RayGroup& g) {
    g.planes.assign(2 * g.n, Plane{});
    const Vec3d o = to_d(g.origin);
    auto make = [&](const Vec3d& along, const Vec3d& point) {
        Vec3d nrm = normalize(cross(along, point - o));
        Plane p;
        p.n = to_f(nrm);
        p.w = float(-dot(to_d(p.n), o));
        return p;
    };
    for (std::uint32_t v = 0; v < g.n; ++v) g.planes[v] = make(g.du, g.grid_corner + g.dv * (v + 0.5));
    for (std::uint32_t h = 0; h < g.n; ++h) g.planes[g.n + h] = make(g.dv, g.grid_corner + g.du * (h + 0.5));
}

Screen make_screen(const Scene& s) {
    const Camera& c = s.camera;
    Vec3d f = normalize(c.look_at - c.eye);
    Vec3d r = normalize(cross(f, c.up));
    Vec3d u = cross(r, f);
    double hh = std::tan(c.fov_deg * M_PI / 360.0);
    double hw = hh * double(s.width) / double(s.height);
    Screen sc;
    sc.eye = c.eye;
    sc.corner = c.eye + f - r * hw + u * hh;
    sc.du = r * (2.0 * hw / s.width);
    sc.dv = u * (-2.0 * hh / s.height);
    return sc;
}

std::vector<RayGroup> primary_groups(const Scene& s) {
    const Screen sc = make_screen(s);
    const int n = s.group_size;
    std::vector<RayGroup> out;
    for (int ty = 0; ty < s.height; ty += n) {
        for (int tx = 0; tx < s.width; tx += n) {
            RayGroup g;
            g.kind = GroupKind::primary;
            g.n = static_cast<std::uint32_t>(n);
            g.px = tx;
            g.py = ty;
            g.origin = to_f(sc.eye);
            g.grid_corner = sc.corner + sc.du * tx + sc.dv * ty;
            g.du = sc.du;
            g.dv = sc.dv;
            g.tmax = std::numeric_limits<float>::max();
            for (int i = 0; i < n; ++i) {
                if (ty + i < s.height) g.row_valid |= std::uint64_t(1) << i;
                if (tx + i < s.width) g.col_valid |= std::uint64_t(1) << i;
            }
            build_planes(g);
            out.push_back(std::move(g));
        }
    }
    return out;
}

RayGroup shadow_group(const Scene& s, const Vec3f& origin, std::int32_t px, std::int32_t py) {
    const int n = s.shadow_group_size;
    RayGroup g;
    g.kind = GroupKind::shadow;
    g.n = static_cast<std::uint32_t>(n);
    g.px = px;
    g.py = py;
    g.origin = origin;
    g.grid_corner = s.light.corner;
    g.du = s.light.edge_u / double(n);
    g.dv = s.light.edge_v / double(n);
    g.tmax = 1.0f - 1e-4f;  // stop short of the light itself
    g.row_valid = n == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
    g.col_valid = g.row_valid;
    build_planes(g);
    return g;
}

}  // namespace raplas
