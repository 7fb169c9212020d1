#include "raplas/scene/scene.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include "raplas/scene/animation.hpp"
#include "raplas/util/data_dir.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"

#ifndef RAPLAS_SOURCE_DIR
#define RAPLAS_SOURCE_DIR "."
#endif

namespace raplas {

ParamSet scene_params() {
    ParamSet p("scene");
    p.listed_by("raplas render --dump-scene");
    p.add_string("name", std::string("scene"), "scene name used in reports");
    p.add_string("mesh", std::nullopt, "OBJ file; relative paths resolve via the scene search path; unset = built-in scene");
    p.add_bool("floor", false, "add a floor quad under the mesh (2 triangles appended after the mesh's)");
    p.add_int("builtin_detail", 3, 0, 6, "tessellation level of the built-in scene's spheres");
    p.add_vec3("camera.eye", std::nullopt, "camera position (unset = automatic framing)");
    p.add_vec3("camera.look_at", std::nullopt, "point the camera looks at (unset = automatic)");
    p.add_vec3("camera.up", Vec3d(0, 1, 0), "camera up direction");
    p.add_real("camera.fov_deg", 40.0, 1.0, 170.0, "vertical field of view, degrees");
    p.add_string("camera.auto", std::string("detect"),
                 "automatic framing (no camera.eye): outside = the mesh seen from outside; inside = the eye inside "
                 "it, looking along its longest free line of sight, with the automatic light under its ceiling; "
                 "detect = inside when the mesh encloses its bounding box's centre with inward-facing surfaces "
                 "(a room, an atrium), else outside",
                 {"detect", "outside", "inside"});
    p.add_vec3("light.corner", std::nullopt, "area light corner (unset = automatic light above the mesh)");
    p.add_vec3("light.edge_u", std::nullopt, "area light first edge; the light emits toward edge_u x edge_v");
    p.add_vec3("light.edge_v", std::nullopt, "area light second edge");
    p.add_vec3("light.emission", Vec3d(1, 1, 1), "light colour (scales the direct term)");
    p.add_int("image.width", 64, 1, 16384, "image width, pixels");
    p.add_int("image.height", 64, 1, 16384, "image height, pixels");
    p.add_int("groups.size", 16, 1, 64, "N: primary ray groups are N x N pixel tiles (2N ray-planes)");
    p.add_int("groups.shadow_size", 16, 1, 64, "shadow ray groups: N x N samples on the area light");
    p.add_int("spheres.triangles_per_sphere", 2, 1, 64, "K: at most K triangles per bounding sphere");
    p.add_string("spheres.method", std::string("median-split"), "how triangles are grouped into spheres",
                 {"median-split", "file-order"});
    p.add_real("shading.ambient", 0.15, 0.0, 1.0, "ambient term of the Lambert shading");
    p.add_real("shading.shadow_offset", 1e-4, 0.0, 0.1,
               "shadow ray origin offset along the normal, as a fraction of the scene diagonal");
    p.add_bool("shading.skip_facing_away", false,
               "issue no shadow group for a hit point whose surface faces away from the whole light "
               "(its direct term is zero whatever the shadow rays find; the image does not change)");
    add_animation_params(p);
    return p;
}

namespace {

bool ends_with_ci(const std::string& s, const std::string& tail) {
    if (s.size() < tail.size()) return false;
    for (std::size_t i = 0; i < tail.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - tail.size() + i])) != tail[i]) return false;
    return true;
}

}  // namespace

void check_mesh_option(const std::string& path) {
    if (ends_with_ci(path, ".toml"))
        throw InputError("--mesh " + path + ": a scene file (TOML), not an OBJ mesh; give it with --scene " + path);
}

std::string find_scene_file(const std::string& name) {
    if (ends_with_ci(name, ".obj"))
        throw InputError("--scene " + name + ": an OBJ mesh, not a scene file; give it with --mesh " + name +
                         ", or name it in a scene file (mesh = \"" + name + "\")");
    return find_named_file(name, {"scene", "scenes", "scene files", "raplas render --dump-scene"});
}

std::vector<std::string> scene_search_path(const std::string& scene_dir) {
    std::vector<std::string> dirs;
    if (!scene_dir.empty()) dirs.push_back(scene_dir);
    dirs.push_back(".");
    if (const char* env = std::getenv("RAPLAS_SCENE_PATH")) {
        std::string s = env;
        std::size_t start = 0;
        while (start <= s.size()) {
            auto colon = s.find(':', start);
            std::string d = s.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
            if (!d.empty()) dirs.push_back(d);
            if (colon == std::string::npos) break;
            start = colon + 1;
        }
    }
    dirs.push_back("../shared/scenes");
    if (!scene_dir.empty()) dirs.push_back(scene_dir + "/../../shared/scenes");
    dirs.push_back(std::string(RAPLAS_SOURCE_DIR) + "/../shared/scenes");
    // Each folder once (a scene in the working directory has "." as its folder too).
    std::vector<std::string> once;
    for (const auto& d : dirs) {
        const std::string norm = std::filesystem::path(d).lexically_normal().string();
        bool seen = false;
        for (const auto& o : once) seen = seen || std::filesystem::path(o).lexically_normal().string() == norm;
        if (!seen) once.push_back(d);
    }
    return once;
}

std::string resolve_mesh_path(const std::string& mesh, const std::string& scene_dir) {
    if (!mesh.empty() && mesh[0] == '/') return mesh;
    for (const auto& d : scene_search_path(scene_dir)) {
        std::string cand = d + "/" + mesh;
        if (is_file(cand)) return cand;
    }
    std::string tried;
    for (const auto& d : scene_search_path(scene_dir)) tried += (tried.empty() ? "" : ", ") + d;
    throw InputError("mesh '" + mesh + "' not found (searched: " + tried + ")");
}

std::vector<std::string> scene_mesh_files(const ParamSet& p, const std::string& mesh_override) {
    std::vector<std::string> files;
    if (!mesh_override.empty()) files.push_back(mesh_override);
    const std::string mesh = p.get_string("mesh");
    if (mesh_override.empty() && !mesh.empty()) files.push_back(resolve_mesh_path(mesh, p.file_dir()));
    for (auto& f : animation_mesh_files(p)) files.push_back(std::move(f));
    return files;
}

Camera auto_camera(const Mesh& m, std::size_t triangles, double fov_deg, double aspect) {
    Aabb b;
    for (std::size_t t = 0; t < triangles; ++t)
        for (auto i : m.triangles[t]) b.grow(to_d(m.vertices[i]));
    const Vec3d c = b.center();
    const Vec3d up{0, 1, 0};
    const double r = std::max(length(b.extent()) * 0.5, 1e-6);
    // Candidate views from the same side, from low (the direction (0.45,
    // 0.35, 1): 17.7 degrees up) to high above: the one whose projected
    // bounding rectangle fills the image best, so that a flat mesh (a floor,
    // a room seen from outside) is seen from higher up. A later candidate
    // must fill 10 % more to win: compact meshes keep the low view.
    const Vec3d side = normalize(Vec3d(0.45, 0.0, 1.0));
    const double elevations[] = {std::atan2(0.35, std::sqrt(0.45 * 0.45 + 1.0)), 30 * M_PI / 180, 45 * M_PI / 180,
                                 60 * M_PI / 180};
    struct View {
        Vec3d w, u, v;
        double cx = 0, cy = 0, fill = 0;
    };
    View best;
    for (double e : elevations) {
        View view;
        view.w = normalize(side * std::cos(e) + up * std::sin(e));  // toward the eye
        view.u = normalize(cross(up, view.w));
        view.v = cross(view.w, view.u);
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        for (std::size_t t = 0; t < triangles; ++t)
            for (auto i : m.triangles[t]) {
                const Vec3d q = to_d(m.vertices[i]) - c;
                x0 = std::min(x0, dot(q, view.u)), x1 = std::max(x1, dot(q, view.u));
                y0 = std::min(y0, dot(q, view.v)), y1 = std::max(y1, dot(q, view.v));
            }
        const double bw = std::max(x1 - x0, 1e-12 * r), bh = std::max(y1 - y0, 1e-12 * r);
        const double scale = std::max(bw / aspect, bh);  // image height that holds the rectangle
        view.fill = bw * bh / (scale * scale * aspect);
        view.cx = (x0 + x1) / 2;
        view.cy = (y0 + y1) / 2;
        if (view.fill > best.fill * 1.1) best = view;
    }
    // Look at the centre of the projected rectangle, from the smallest
    // distance at which every corner is inside the view (vertical and
    // horizontal field of view), plus 2 %.
    Camera cam;
    cam.up = up;
    cam.fov_deg = fov_deg;
    cam.look_at = c + best.u * best.cx + best.v * best.cy;
    const double tv = std::tan(fov_deg * M_PI / 360.0), th = tv * aspect;
    double dist = 0;
    for (std::size_t t = 0; t < triangles; ++t)
        for (auto i : m.triangles[t]) {
            const Vec3d q = to_d(m.vertices[i]) - cam.look_at;
            const double x = dot(q, best.u), y = dot(q, best.v), z = dot(q, best.w);
            dist = std::max(dist, std::max(z + std::fabs(x) / th, z + std::fabs(y) / tv));
        }
    dist = std::max(dist * 1.02, 1e-3 * r);
    cam.eye = cam.look_at + best.w * dist;
    return cam;
}

namespace {

// The nearest hit of the ray o + t d (t > 0) with the first `triangles`
// triangles of `m`, in double (Moeller-Trumbore); t = +inf when none, and
// `facing` whether that triangle's winding normal faces back along the ray.
double nearest_hit(const Mesh& m, std::size_t triangles, const Vec3d& o, const Vec3d& d, bool* facing = nullptr) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < triangles; ++t) {
        const Vec3d a = to_d(m.vertices[m.triangles[t][0]]), b = to_d(m.vertices[m.triangles[t][1]]),
                    c = to_d(m.vertices[m.triangles[t][2]]);
        const Vec3d e1 = b - a, e2 = c - a, pv = cross(d, e2);
        const double det = dot(e1, pv);
        if (std::fabs(det) < 1e-300) continue;
        const double inv = 1.0 / det;
        const Vec3d tv = o - a;
        const double u = dot(tv, pv) * inv;
        if (u < 0 || u > 1) continue;
        const Vec3d qv = cross(tv, e1);
        const double v = dot(d, qv) * inv;
        if (v < 0 || u + v > 1) continue;
        const double h = dot(e2, qv) * inv;
        if (h > 1e-9 && h < best) {
            best = h;
            if (facing) *facing = dot(cross(e1, e2), d) < 0;
        }
    }
    return best;
}

Aabb bounds_of(const Mesh& m, std::size_t triangles) {
    Aabb b;
    for (std::size_t t = 0; t < triangles; ++t)
        for (auto i : m.triangles[t]) b.grow(to_d(m.vertices[i]));
    return b;
}

}  // namespace

InteriorTest interior_test(const Mesh& m, std::size_t triangles) {
    InteriorTest r;
    const Aabb b = bounds_of(m, triangles);
    const Vec3d c = b.center();
    // 128 directions spread over the sphere (a Fibonacci lattice).
    constexpr int kRays = 128;
    int inward = 0;
    for (int i = 0; i < kRays; ++i) {
        const double y = 1 - (i + 0.5) * 2.0 / kRays, rho = std::sqrt(std::max(0.0, 1 - y * y));
        const double phi = i * M_PI * (3 - std::sqrt(5.0));
        const Vec3d d{rho * std::cos(phi), y, rho * std::sin(phi)};
        bool facing = false;
        if (std::isfinite(nearest_hit(m, triangles, c, d, &facing)) && facing) ++inward;
    }
    r.inward_fraction = double(inward) / kRays;
    // The volume the winding encloses, about the centre: negative when the
    // surfaces, summed, face inward (walls modelled to be seen from inside).
    // A closed object around the centre can show the rays an inner face (a
    // teapot's lid and body), but its winding encloses a positive volume.
    for (std::size_t t = 0; t < triangles; ++t) {
        const Vec3d a = to_d(m.vertices[m.triangles[t][0]]) - c, bb = to_d(m.vertices[m.triangles[t][1]]) - c,
                    cc = to_d(m.vertices[m.triangles[t][2]]) - c;
        r.volume += dot(a, cross(bb, cc)) / 6;
    }
    r.inside = r.inward_fraction >= 0.9 && r.volume < 0;
    return r;
}

Camera inside_camera(const Mesh& m, std::size_t triangles, double fov_deg) {
    const Aabb b = bounds_of(m, triangles);
    const Vec3d ext = b.extent();
    // At the centre of the floor plan, at 40 % of the height, looking along the
    // horizontal line of sight that runs farthest before it meets a surface.
    Camera cam;
    cam.up = {0, 1, 0};
    cam.fov_deg = fov_deg;
    cam.eye = {b.center().x, b.lo.y + 0.4 * ext.y, b.center().z};
    double far = -1;
    for (int k = 0; k < 16; ++k) {
        const double a = k * M_PI / 8;
        const Vec3d d{std::cos(a), 0, std::sin(a)};
        double t = nearest_hit(m, triangles, cam.eye, d);
        if (!std::isfinite(t)) t = length(ext);
        if (t > far * 1.001) far = t, cam.look_at = cam.eye + d * (0.5 * t);
    }
    return cam;
}

AreaLight inside_light(const Mesh& m, std::size_t triangles, const Vec3d& eye) {
    const Aabb b = bounds_of(m, triangles);
    const Vec3d ext = b.extent();
    // Under the ceiling above the eye (or the top of the box when open), a
    // square a quarter of the smaller floor side, facing down: it reaches the
    // floor below it.
    double up = nearest_hit(m, triangles, eye, {0, 1, 0});
    if (!std::isfinite(up)) up = b.hi.y - eye.y;
    const double side = 0.25 * std::max(std::min(ext.x, ext.z), 1e-6);
    const Vec3d center = eye + Vec3d(0, 0.95 * up, 0);
    AreaLight l;
    l.edge_u = {side, 0, 0};
    l.edge_v = {0, 0, side};  // u x v points down (-y)
    l.corner = center - l.edge_u * 0.5 - l.edge_v * 0.5;
    return l;
}

AreaLight auto_light(const Aabb& b) {
    Vec3d c = b.center();
    double r = std::max(length(b.extent()) * 0.5, 1e-6);
    AreaLight l;
    Vec3d center = c + Vec3d(-0.6 * r, 2.0 * r, 0.9 * r);
    l.edge_u = {0.8 * r, 0, 0};
    l.edge_v = {0, 0, 0.8 * r};  // u x v points down (-y)
    l.corner = center - l.edge_u * 0.5 - l.edge_v * 0.5;
    return l;
}

void add_floor(Mesh& m) {
    Aabb b = m.bounds();
    Vec3d c = b.center();
    double r = std::max(length(b.extent()) * 0.5, 1e-6);
    float y = float(b.lo.y - 1e-3 * r);
    float x0 = float(c.x - 3 * r), x1 = float(c.x + 3 * r), z0 = float(c.z - 3 * r), z1 = float(c.z + 3 * r);
    Material mt;
    mt.name = "floor";
    mt.diffuse = {0.8f, 0.8f, 0.8f};
    m.materials.push_back(mt);
    auto mat = static_cast<std::int32_t>(m.materials.size() - 1);
    auto base = static_cast<std::uint32_t>(m.vertices.size());
    if (m.triangle_object.size() == m.triangles.size())
        m.triangle_object.insert(m.triangle_object.end(), 2, Mesh::kAddedObject);
    m.vertices.push_back({x0, y, z0});
    m.vertices.push_back({x0, y, z1});
    m.vertices.push_back({x1, y, z1});
    m.vertices.push_back({x1, y, z0});
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
    m.triangle_material.push_back(mat);
    m.triangle_material.push_back(mat);
}

Scene scene_from_params(const ParamSet& p, const std::string& mesh_override) {
    Scene s;
    s.name = p.get_string("name");
    std::string mesh = mesh_override.empty() ? p.get_string("mesh") : mesh_override;
    std::optional<Mesh> animated_mesh = animation_still_mesh(p, mesh_override);
    const bool wave = p.get_string("animation.builtin") == "wave";
    const bool builtin = mesh.empty() && !animated_mesh;
    if (animated_mesh) {
        s.mesh = std::move(*animated_mesh);
        if (wave && !p.is_given("name")) s.name = "wave";
    } else if (!mesh_override.empty()) {
        check_mesh_option(mesh_override);
        s.mesh = load_obj(mesh_override);
        if (!p.is_given("name")) {
            std::string base = mesh_override.substr(mesh_override.find_last_of('/') + 1);
            s.name = base.substr(0, base.find_last_of('.'));
        }
    } else if (!mesh.empty()) {
        s.mesh = load_obj(resolve_mesh_path(mesh, p.file_dir()));
    } else {
        s.mesh = builtin_mesh(static_cast<int>(p.get_int("builtin_detail")));
        if (!p.is_given("name")) s.name = "builtin";
    }
    const Aabb object_bounds = s.mesh.bounds();
    const std::size_t object_triangles = s.mesh.triangles.size();
    if (p.get_bool("floor")) add_floor(s.mesh);
    s.diagonal = length(s.mesh.bounds().extent());

    auto eye = p.get_vec3("camera.eye"), at = p.get_vec3("camera.look_at");
    if (eye.has_value() != at.has_value())
        throw InputError(p.origin(eye ? "camera.eye" : "camera.look_at") +
                         ": camera.eye and camera.look_at must be given together");
    double fov = p.get_real("camera.fov_deg");
    if (eye) {
        s.camera.eye = *eye;
        s.camera.look_at = *at;
        s.camera.fov_deg = fov;
        s.camera.up = *p.get_vec3("camera.up");
        // Finite coordinates can still be too far apart for a finite distance.
        const double dist = length(s.camera.eye - s.camera.look_at);
        if (dist <= 0) throw InputError(p.origin("camera.eye") + ": camera.eye equals camera.look_at");
        if (!std::isfinite(dist))
            throw InputError(p.origin("camera.eye") + ": camera.eye and camera.look_at are too far apart");
        const double side = length(cross(s.camera.eye - s.camera.look_at, s.camera.up));
        if (!std::isfinite(side)) throw InputError(p.origin("camera.up") + ": camera.up is too long for the view direction");
        if (side <= 1e-12 * dist)
            throw InputError(p.origin("camera.up") + ": camera.up is parallel to the view direction");
    } else if (builtin) {
        s.camera = {{3.2, 2.6, 5.2}, {0.0, 0.7, -0.4}, {0, 1, 0}, fov};
    } else if (wave) {
        s.camera = {{0.0, 3.4, 5.4}, {0.0, -0.3, 0.2}, {0, 1, 0}, fov};
    } else {
        const std::string mode = p.get_string("camera.auto");
        if (mode == "detect") {
            const InteriorTest it = interior_test(s.mesh, object_triangles);
            s.camera_inside = it.inside;
            char buf[160];
            std::snprintf(buf, sizeof buf, "%s: %.0f %% of the rays from its centre meet a surface facing them, its "
                          "winding faces %s", it.inside ? "inside (the mesh encloses its centre)" : "outside",
                          100 * it.inward_fraction, it.volume < 0 ? "inward" : "outward");
            s.camera_note = buf;
        } else {
            s.camera_inside = mode == "inside";
            s.camera_note = mode + " (camera.auto)";
        }
        if (s.camera_inside) {
            // A view from inside wants a wider angle than the default 40 degrees.
            s.camera = inside_camera(s.mesh, object_triangles, p.is_given("camera.fov_deg") ? fov : 70.0);
        } else {
            const double aspect = double(p.get_int("image.width")) / double(p.get_int("image.height"));
            s.camera = auto_camera(s.mesh, object_triangles, fov, aspect);
        }
        s.camera_auto = true;
    }
    auto lc = p.get_vec3("light.corner"), lu = p.get_vec3("light.edge_u"), lv = p.get_vec3("light.edge_v");
    if (lc || lu || lv) {
        if (!(lc && lu && lv))
            throw InputError("scene: light.corner, light.edge_u and light.edge_v must be given together");
        s.light.corner = *lc;
        s.light.edge_u = *lu;
        s.light.edge_v = *lv;
        const double area = length(cross(*lu, *lv));
        if (area <= 0) throw InputError(p.origin("light.edge_u") + ": light edges are parallel or zero");
        if (!std::isfinite(area) || !all_finite(*lc + *lu + *lv))
            throw InputError(p.origin("light.edge_u") + ": light corner and edges are too large");
    } else if (builtin) {
        s.light.corner = {-1.5, 4.0, -0.5};
        s.light.edge_u = {1.2, 0, 0};
        s.light.edge_v = {0, 0, 1.2};
    } else if (wave) {
        s.light.corner = {-4.0, 2.5, -0.6};
        s.light.edge_u = {1.2, 0, 0};
        s.light.edge_v = {0, 0, 1.2};
    } else {
        s.light = s.camera_inside ? inside_light(s.mesh, object_triangles, s.camera.eye) : auto_light(object_bounds);
        s.light_auto = true;
    }
    s.light.emission = *p.get_vec3("light.emission");
    s.width = static_cast<int>(p.get_int("image.width"));
    s.height = static_cast<int>(p.get_int("image.height"));
    if (static_cast<long long>(s.width) * s.height > 64LL * 1024 * 1024)
        throw InputError(p.origin("image.width") + ": image of " + std::to_string(s.width) + "x" +
                         std::to_string(s.height) + " pixels exceeds the limit of 64 Mpixel");
    s.group_size = static_cast<int>(p.get_int("groups.size"));
    s.shadow_group_size = static_cast<int>(p.get_int("groups.shadow_size"));
    s.tris_per_sphere = static_cast<int>(p.get_int("spheres.triangles_per_sphere"));
    s.sphere_method = p.get_string("spheres.method");
    s.ambient = p.get_real("shading.ambient");
    s.shadow_offset = p.get_real("shading.shadow_offset");
    s.skip_facing_away = p.get_bool("shading.skip_facing_away");
    Animation a = animation_from_params(p, s);
    if (a.animated()) s.animation = std::make_shared<const Animation>(std::move(a));
    return s;
}

void resolve_scene_params(ParamSet& p, const Scene& s, const std::string& mesh_override) {
    auto vec = [](const Vec3d& v) {
        auto num = [](double d) {
            char buf[40];
            for (int prec = 1; prec <= 17; ++prec) {  // shortest text that reads back to the same double
                std::snprintf(buf, sizeof buf, "%.*g", prec, d);
                if (std::strtod(buf, nullptr) == d) break;
            }
            std::string t = buf;
            if (t.find_first_of(".eEn") == std::string::npos) t += ".0";
            return t;
        };
        return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]";
    };
    if (!mesh_override.empty()) p.set("mesh=\"" + mesh_override + "\"");
    if (!p.is_given("name")) p.set("name=\"" + s.name + "\"");
    p.set("camera.eye=" + vec(s.camera.eye));
    p.set("camera.look_at=" + vec(s.camera.look_at));
    p.set("camera.up=" + vec(s.camera.up));
    p.set("light.corner=" + vec(s.light.corner));
    p.set("light.edge_u=" + vec(s.light.edge_u));
    p.set("light.edge_v=" + vec(s.light.edge_v));
    if (s.animation) resolve_animation_params(p, *s.animation);
}

Scene load_scene(const SceneRequest& req) {
    if (!req.scene_file.empty() && !req.mesh_file.empty())
        throw UsageError("give either --scene or --mesh, not both");
    ParamSet p = scene_params();
    if (!req.scene_file.empty()) p.load_file(find_scene_file(req.scene_file));
    for (const auto& o : req.overrides) p.set(o);
    return scene_from_params(p, req.mesh_file);
}

}  // namespace raplas
