#include "raplas/app/reports.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

namespace raplas {

namespace {
nlohmann::json counts_json(const GroupCounts& c) {
    return {{"plane_sphere_tests", c.plane_tests}, {"sphere_hits", c.sphere_hits}, {"ray_triangle_tests", c.rt_tests}};
}
nlohmann::json vec_json(const Vec3d& v) { return nlohmann::json::array({v.x, v.y, v.z}); }
}  // namespace

std::string render_json(const RenderReport& r) {
    const Scene& s = *r.scene;
    const Frame& f = *r.frame;
    GroupCounts total = f.primary_counts;
    total += f.shadow_counts;
    std::size_t hit_pixels = 0;
    for (const auto& h : f.pixel_hit) hit_pixels += h.tri >= 0;
    nlohmann::json j;
    j["scene"] = {{"name", s.name},
                  {"mesh", s.mesh.source},
                  {"width", s.width},
                  {"height", s.height},
                  {"group_size", s.group_size},
                  {"shadow_group_size", s.shadow_group_size},
                  {"triangles_per_sphere", s.tris_per_sphere},
                  {"sphere_method", s.sphere_method},
                  {"camera", {{"eye", vec_json(s.camera.eye)}, {"look_at", vec_json(s.camera.look_at)},
                              {"fov_deg", s.camera.fov_deg}, {"auto", s.camera_auto},
                              {"view", s.camera_auto ? (s.camera_inside ? "inside" : "outside") : "given"},
                              {"choice", s.camera_note}}},
                  {"light", {{"corner", vec_json(s.light.corner)}, {"edge_u", vec_json(s.light.edge_u)},
                             {"edge_v", vec_json(s.light.edge_v)}, {"auto", s.light_auto}}}};
    j["format"] = r.format.name();
    j["counts"] = {{"triangles", f.spheres.triangle_count()},
                   {"spheres", f.spheres.sphere_count()},
                   {"primary_ray_groups", f.primary.size()},
                   {"shadow_ray_groups", f.shadow_group_count},
                   {"hit_pixels", hit_pixels},
                   {"facing_away_skipped", f.facing_away},
                   {"plane_sphere_tests", total.plane_tests},
                   {"sphere_hits", total.sphere_hits},
                   {"ray_triangle_tests", total.rt_tests},
                   {"primary", counts_json(f.primary_counts)},
                   {"shadow", counts_json(f.shadow_counts)}};
    j["spheres"] = {{"method", s.sphere_method},
                    {"margin", f.sphere_margin},
                    {"sum_radius", r.quality.sum_radius},
                    {"sum_volume", r.quality.sum_volume},
                    {"mean_triangles_per_sphere", r.quality.mean_tris_per_sphere},
                    {"naive_sum_radius", r.naive_quality.sum_radius},
                    {"naive_sum_volume", r.naive_quality.sum_volume}};
    // Wall-clock seconds, the only figures that differ between identical runs.
    j["wall"] = {{"load_s", r.load_s},
                 {"spheres_s", f.times.spheres_s},
                 {"primary_s", f.times.primary_s},
                 {"shadow_s", f.times.shadow_s},
                 {"shade_s", f.times.shade_s},
                 {"write_s", r.write_s}};
    return j.dump(2) + "\n";
}

std::string hits_csv(const Frame& f) {
    std::string out = "x,y,ox,oy,oz,dx,dy,dz,tri,t\n";
    char buf[512];
    for (int y = 0; y < f.height; ++y) {
        for (int x = 0; x < f.width; ++x) {
            std::size_t px = std::size_t(y) * std::size_t(f.width) + std::size_t(x);
            const Ray& r = f.pixel_ray[px];
            const Hit& h = f.pixel_hit[px];
            int tri = h.tri < 0 ? -1 : f.spheres.tri_mesh_index[static_cast<std::size_t>(h.tri)];
            if (tri < 0)
                std::snprintf(buf, sizeof buf, "%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,-1,\n", x, y, r.o.x, r.o.y, r.o.z,
                              r.d.x, r.d.y, r.d.z);
            else
                std::snprintf(buf, sizeof buf, "%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d,%.17g\n", x, y, r.o.x, r.o.y,
                              r.o.z, r.d.x, r.d.y, r.d.z, tri, h.t);
            out += buf;
        }
    }
    return out;
}

std::string render_summary(const RenderReport& r) {
    const Frame& f = *r.frame;
    GroupCounts total = f.primary_counts;
    total += f.shadow_counts;
    std::ostringstream o;
    o << r.scene->name << ": " << f.spheres.triangle_count() << " triangles in " << f.spheres.sphere_count()
      << " spheres, " << f.width << "x" << f.height << " px, " << f.primary.size() << " primary + "
      << f.shadow_group_count << " shadow ray groups (" << r.format.name() << ")\n"
      << "  plane-sphere tests " << total.plane_tests << ", sphere hits " << total.sphere_hits
      << ", ray-triangle tests " << total.rt_tests << "\n";
    if (r.scene->camera_auto) o << "  automatic camera: " << r.scene->camera_note << " (camera.auto)\n";
    char buf[256];
    std::snprintf(buf, sizeof buf, "  wall: load %.3f s, spheres %.3f s, primary %.3f s, shadow %.3f s, shade+write %.3f s\n",
                  r.load_s, f.times.spheres_s, f.times.primary_s, f.times.shadow_s, f.times.shade_s + r.write_s);
    o << buf;
    return o.str();
}

}  // namespace raplas
