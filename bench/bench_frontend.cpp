// Wall time of the RAPLAS front end (render_frame, per phase) against Embree 3
// tracing the very same primary and shadow rays, in one run. Prints Markdown
// tables; --json writes every number.
#include <embree3/rtcore.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include "raplas/frontend/frame.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/parallel.hpp"
#include "bench_util.hpp"
#include "embree_rays.hpp"


namespace raplas {
namespace {

namespace fs = std::filesystem;
using bench::clock_type;
using bench::cpu_model;
using bench::fmt_count;
using bench::load_average;
using bench::since;


struct Options {
    std::vector<std::string> scenes{"bunny", "conference"};
    int size = 64;
    int width = 0, height = 0;  // 0: --size
    // Embree alone on the frame's rays: the front end traces the primary
    // rays only (for the shadow rays' origins); shadow rays are made group by
    // group, never all held (big frames).
    bool embree_only = false;
    unsigned threads = 0;
    int repeat = 3;
    int frontend_repeat = 1;
    bool frontend_single = false;
    std::string json;
    std::string shared = RAPLAS_SHARED_SCENES;
    std::string scene_dir = std::string(RAPLAS_SOURCE_DIR) + "/scenes";
};

// Scenes the benchmark knows: mesh, and a camera and light for when the
// project has no scene file of that name.
struct KnownScene {
    std::string name, mesh;
    std::vector<std::string> fallback;  // scene keys; empty = automatic camera and light
};

const std::vector<KnownScene> kKnown = {
    {"bunny", "bunny/bun_zipper.obj", {}},
    {"sportscar", "sportscar/sportsCar_62k.obj", {}},
    // The room is closed: camera and light inside it (units: 0.003 m).
    {"conference",
     "conference/conference.obj",
     {"camera.eye=[1300, 300, -200]", "camera.look_at=[0, 200, -200]", "camera.fov_deg=60",
      "light.corner=[200, 620, -400]", "light.edge_u=[300, 0, 0]", "light.edge_v=[0, 0, 300]"}},
};

// ---- Embree ----------------------------------------------------------------

class EmbreeScene {
public:
    EmbreeScene(const Mesh& mesh, unsigned threads) {
        const std::string cfg = "threads=" + std::to_string(threads);
        device_ = rtcNewDevice(cfg.c_str());
        if (!device_) throw std::runtime_error("rtcNewDevice failed");
        const auto t0 = clock_type::now();
        scene_ = rtcNewScene(device_);
        RTCGeometry geom = new_embree_mesh(device_, mesh);
        rtcCommitGeometry(geom);
        rtcAttachGeometry(scene_, geom);
        rtcReleaseGeometry(geom);
        rtcCommitScene(scene_);
        build_s_ = since(t0);
        if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error("Embree scene build failed");
    }
    ~EmbreeScene() {
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
    }
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    double build_s() const { return build_s_; }

    // Ray parameter of the nearest hit in (0, inf), or -1 for a miss.
    float intersect(const Ray& r) const {
        const RTCRayHit rh = embree_nearest(scene_, r);
        return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? rh.ray.tfar : -1.0f;
    }
    // Anything in (0, r.tmax]?
    bool occluded(const Ray& r) const { return embree_occluded(scene_, r); }

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    double build_s_ = 0;
};

// Wall time of body(i) for i in [0, n) on one thread and on `threads`
// threads (in chunks), each the best of `repeat` runs; the two are
// interleaved so that a passing load affects both alike.
template <class F>
std::pair<double, double> best_times(std::size_t n, unsigned threads, int repeat, F&& body, bool single = true) {
    constexpr std::size_t kChunk = 256;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    auto run = [&](unsigned t) {
        const auto t0 = clock_type::now();
        parallel_for(chunks, t, [&](std::size_t c) {
            const std::size_t end = std::min(n, (c + 1) * kChunk);
            for (std::size_t i = c * kChunk; i < end; ++i) body(i);
        });
        return since(t0);
    };
    double one = std::numeric_limits<double>::infinity(), many = one;
    for (int k = 0; k < std::max(1, repeat); ++k) {
        if (single) one = std::min(one, run(1));
        many = std::min(many, run(threads));
    }
    return {one, many};
}

// ---- one scene ---------------------------------------------------------------

struct Result {
    std::string name, source;
    std::size_t triangles = 0, spheres = 0;
    int tris_per_sphere = 0, width = 0, height = 0, group_size = 0, shadow_group_size = 0;
    unsigned threads = 0;
    int frontend_repeat = 1, embree_repeat = 1;
    double load_s = 0;
    PhaseTimes fe;          // front end, `threads` threads
    PhaseTimes fe_single;   // front end, one thread (when asked)
    bool has_single = false;
    bool embree_only = false;  // front end: primary rays only
    double em_shadow_setup_n = 0;  // embree_only: making the shadow rays alone, `threads` threads
    std::size_t primary_groups = 0, primary_rays = 0, shadow_groups = 0, shadow_rays = 0;
    std::uint64_t fe_plane_tests = 0, fe_rt_tests = 0;
    double shadow_setup_s = 0;
    double em_build_1 = 0, em_build_n = 0;
    double em_primary_1 = 0, em_primary_n = 0;
    double em_shadow_1 = 0, em_shadow_n = 0;
    std::size_t primary_hit_mismatch = 0, primary_t_mismatch = 0;
    std::uint64_t fe_occluded = 0, em_occluded = 0;
};

double total(const PhaseTimes& t) { return t.spheres_s + t.primary_s + t.shadow_s + t.shade_s; }

Scene load_bench_scene(const KnownScene& k, const Options& o, std::string& source) {
    std::vector<std::string> overrides = {"image.width=" + std::to_string(o.width ? o.width : o.size),
                                          "image.height=" + std::to_string(o.height ? o.height : o.size), "groups.size=16",
                                          "groups.shadow_size=16"};
    const fs::path file = fs::path(o.scene_dir) / (k.name + ".toml");
    if (fs::is_regular_file(file)) {
        source = file.lexically_relative(fs::path(RAPLAS_SOURCE_DIR)).string();
        if (source.empty() || source.rfind("..", 0) == 0) source = file.string();
        SceneRequest req;
        req.scene_file = file.string();
        req.overrides = overrides;
        return load_scene(req);
    }
    const std::string mesh = o.shared + "/" + k.mesh;
    source = k.mesh + (k.fallback.empty() ? " (automatic camera and light)" : " (built-in camera and light)");
    ParamSet p = scene_params();
    for (const auto& s : k.fallback) p.set(s);
    for (const auto& s : overrides) p.set(s);
    return scene_from_params(p, mesh);
}

// --embree-only: the front end's primary rays and the shadow groups they
// give, traced by Embree alone (multi-threaded runs only). A shadow group's
// rays are made where they are traced; the time to make them alone is
// measured the same way and taken off.
Result embree_only(const Scene& scene, FrameOptions fo, Result r, const Options& o) {
    struct PrimaryDone {};
    Frame f;
    fo.before_shadow = [&f](const Frame& so_far, std::size_t, const ShadowSample&) {
        f = so_far;
        throw PrimaryDone{};
    };
    std::fprintf(stderr, "%s: front end, primary rays, %u threads...\n", r.name.c_str(), r.threads);
    try {
        render_frame(scene, fo);
        throw std::runtime_error("the front end did not stop before its shadow rays");
    } catch (const PrimaryDone&) {
    }
    r.embree_only = true;
    r.fe.spheres_s = f.times.spheres_s;
    r.fe.primary_s = f.times.primary_s;
    r.spheres = f.spheres.sphere_count();
    r.primary_groups = f.primary.size();
    r.primary_rays = f.pixel_ray.size();
    std::vector<std::size_t> lit;
    for (std::size_t px = 0; px < f.pixel_hit.size(); ++px)  // the pixels render_frame gives a shadow group
        if (f.pixel_hit[px].tri >= 0 &&
            !(scene.skip_facing_away && faces_away_from_light(scene, f.spheres, f.pixel_ray[px], f.pixel_hit[px])))
            lit.push_back(px);
    const std::size_t per_group = std::size_t(scene.shadow_group_size) * std::size_t(scene.shadow_group_size);
    r.shadow_groups = lit.size();
    r.shadow_rays = lit.size() * per_group;

    std::fprintf(stderr, "%s: Embree...\n", r.name.c_str());
    r.em_build_n = std::numeric_limits<double>::infinity();
    for (int i = 1; i < o.repeat; ++i) r.em_build_n = std::min(r.em_build_n, EmbreeScene(scene.mesh, r.threads).build_s());
    const EmbreeScene em(scene.mesh, r.threads);
    r.em_build_n = std::min(r.em_build_n, em.build_s());
    std::vector<float> prim_t(f.pixel_ray.size());
    auto prim = [&](std::size_t i) { prim_t[i] = em.intersect(f.pixel_ray[i]); };
    r.em_primary_n = best_times(prim_t.size(), r.threads, o.repeat, prim, false).second;
    const bench::PrimaryMismatch pm = bench::compare_primary(f, prim_t);
    r.primary_hit_mismatch = pm.hit;
    r.primary_t_mismatch = pm.distance;

    std::vector<std::uint32_t> occluded(lit.size()), made(lit.size());
    auto group = [&](std::size_t i) {
        const std::size_t px = lit[i];
        const int x = int(px % std::size_t(scene.width)), y = int(px / std::size_t(scene.width));
        return shadow_group(scene, shadow_origin(scene, f.spheres, f.pixel_ray[px], f.pixel_hit[px]), x, y);
    };
    auto make_only = [&](std::size_t i) {
        const RayGroup g = group(i);
        std::uint32_t sum = 0;
        for (std::uint32_t v = 0; v < g.n; ++v)
            for (std::uint32_t h = 0; h < g.n; ++h) sum += group_ray(g, h, v).d.x > 0;
        made[i] = sum;
    };
    auto trace = [&](std::size_t i) {
        const RayGroup g = group(i);
        std::uint32_t n = 0;
        for (std::uint32_t v = 0; v < g.n; ++v)
            for (std::uint32_t h = 0; h < g.n; ++h) n += em.occluded(group_ray(g, h, v));
        occluded[i] = n;
    };
    r.em_shadow_setup_n = best_times(lit.size(), r.threads, o.repeat, make_only, false).second;
    const double with_setup = best_times(lit.size(), r.threads, o.repeat, trace, false).second;
    r.em_shadow_n = std::max(0.0, with_setup - r.em_shadow_setup_n);
    for (std::uint32_t c : occluded) r.em_occluded += c;
    return r;
}

Result run_scene(const KnownScene& k, const Options& o, unsigned threads) {
    Result r;
    r.name = k.name;
    r.threads = threads;
    r.frontend_repeat = o.frontend_repeat;
    r.embree_repeat = o.repeat;
    auto t0 = clock_type::now();
    const Scene scene = load_bench_scene(k, o, r.source);
    r.load_s = since(t0);
    r.triangles = scene.mesh.triangle_count();
    r.tris_per_sphere = scene.tris_per_sphere;
    r.width = scene.width;
    r.height = scene.height;
    r.group_size = scene.group_size;
    r.shadow_group_size = scene.shadow_group_size;
    std::fprintf(stderr, "%s: %zu triangles from %s\n", k.name.c_str(), r.triangles, r.source.c_str());

    FrameOptions fo;
    fo.threads = threads;
    if (o.embree_only) return embree_only(scene, fo, r, o);
    std::fprintf(stderr, "%s: front end, %u threads...\n", k.name.c_str(), threads);
    const Frame f = render_frame(scene, fo);
    r.fe = f.times;
    for (int i = 1; i < o.frontend_repeat; ++i) {
        const PhaseTimes t = render_frame(scene, fo).times;
        if (total(t) < total(r.fe)) r.fe = t;
    }
    r.spheres = f.spheres.sphere_count();
    r.primary_groups = f.primary.size();
    r.primary_rays = f.pixel_ray.size();
    r.shadow_groups = f.shadow_group_count;
    r.fe_plane_tests = f.primary_counts.plane_tests + f.shadow_counts.plane_tests;
    r.fe_rt_tests = f.primary_counts.rt_tests + f.shadow_counts.rt_tests;
    if (o.frontend_single && threads != 1) {
        std::fprintf(stderr, "%s: front end, 1 thread...\n", k.name.c_str());
        FrameOptions f1 = fo;
        f1.threads = 1;
        for (int i = 0; i < o.frontend_repeat; ++i) {
            const PhaseTimes t = render_frame(scene, f1).times;
            if (i == 0 || total(t) < total(r.fe_single)) r.fe_single = t;
        }
        r.has_single = true;
    }

    // The shadow rays the front end traced: one group per pixel whose primary ray hits.
    t0 = clock_type::now();
    const bench::ShadowRays sr = bench::frame_shadow_rays(scene, f, threads);
    const std::vector<Ray>& shadow_rays = sr.rays;
    r.shadow_setup_s = since(t0);
    r.shadow_rays = shadow_rays.size();
    r.fe_occluded = sr.occluded;

    std::fprintf(stderr, "%s: Embree...\n", k.name.c_str());
    r.em_build_1 = r.em_build_n = std::numeric_limits<double>::infinity();
    for (int i = 1; i < o.repeat; ++i) {
        r.em_build_1 = std::min(r.em_build_1, EmbreeScene(scene.mesh, 1).build_s());
        r.em_build_n = std::min(r.em_build_n, EmbreeScene(scene.mesh, threads).build_s());
    }
    r.em_build_1 = std::min(r.em_build_1, EmbreeScene(scene.mesh, 1).build_s());
    const EmbreeScene em(scene.mesh, threads);
    r.em_build_n = std::min(r.em_build_n, em.build_s());

    std::vector<float> prim_t(f.pixel_ray.size());
    auto prim = [&](std::size_t i) { prim_t[i] = em.intersect(f.pixel_ray[i]); };
    std::tie(r.em_primary_1, r.em_primary_n) = best_times(prim_t.size(), threads, o.repeat, prim);
    const bench::PrimaryMismatch pm = bench::compare_primary(f, prim_t);
    r.primary_hit_mismatch = pm.hit;
    r.primary_t_mismatch = pm.distance;

    std::vector<unsigned char> occ(shadow_rays.size());
    auto shad = [&](std::size_t i) { occ[i] = em.occluded(shadow_rays[i]) ? 1 : 0; };
    std::tie(r.em_shadow_1, r.em_shadow_n) = best_times(occ.size(), threads, o.repeat, shad);
    for (unsigned char c : occ) r.em_occluded += c;
    return r;
}

// ---- reporting -----------------------------------------------------------------

std::string fmt_time(double s) {
    char buf[32];
    if (s >= 10) std::snprintf(buf, sizeof buf, "%.1f s", s);
    else if (s >= 1) std::snprintf(buf, sizeof buf, "%.2f s", s);
    else if (s >= 0.01) std::snprintf(buf, sizeof buf, "%.0f ms", s * 1e3);
    else if (s >= 0.001) std::snprintf(buf, sizeof buf, "%.1f ms", s * 1e3);
    else std::snprintf(buf, sizeof buf, "%.2f ms", s * 1e3);
    return buf;
}


std::string fmt_rate(double rays, double s) {
    if (!(s > 0)) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", rays / s / 1e6);
    return buf;
}



void print_markdown(const std::vector<Result>& rs, const std::string& command, const std::string& load_before,
                    const std::string& load_after) {
    std::cout << "Command: `" << command << "`  \n";
    std::cout << "Machine: " << std::thread::hardware_concurrency() << " hardware threads, " << cpu_model()
              << "; 1-minute load average " << load_before << " before the run, " << load_after << " after.\n\n";
    for (const Result& r : rs) {
        const unsigned T = r.threads;
        std::cout << "### " << r.name << "\n\n";
        if (r.embree_only) {
            std::cout << r.source << ": " << fmt_count(r.triangles) << " triangles, " << r.width << "x" << r.height
                      << " image, " << fmt_count(r.primary_rays) << " primary rays, " << fmt_count(r.shadow_groups)
                      << " shadow groups of " << r.shadow_group_size << "x" << r.shadow_group_size << " ("
                      << fmt_count(r.shadow_rays) << " rays), " << T << " threads, Embree best of " << r.embree_repeat
                      << " run(s).\n\n| Embree 3 | time |\n|---|---|\n| BVH build | " << fmt_time(r.em_build_n)
                      << " |\n| primary rays | " << fmt_time(r.em_primary_n) << " |\n| shadow rays (occluded?) | "
                      << fmt_time(r.em_shadow_n) << " |\n| **rays** | " << fmt_time(r.em_primary_n + r.em_shadow_n)
                      << " |\n| Mrays/s | " << fmt_rate(double(r.primary_rays + r.shadow_rays), r.em_primary_n + r.em_shadow_n)
                      << " |\n\nMaking the shadow rays alone took " << fmt_time(r.em_shadow_setup_n)
                      << " (taken off). RAPLAS front end, primary rays only: spheres " << fmt_time(r.fe.spheres_s)
                      << ", primary " << fmt_time(r.fe.primary_s) << ". Primary hit/miss differs on "
                      << r.primary_hit_mismatch << " rays; Embree finds " << fmt_count(r.em_occluded)
                      << " shadow rays occluded.\n\n";
            continue;
        }
        std::cout << r.source << ": " << fmt_count(r.triangles) << " triangles, " << fmt_count(r.spheres)
                  << " spheres (K = " << r.tris_per_sphere << "), " << r.width << "x" << r.height << " image, "
                  << r.group_size << "x" << r.group_size << " primary groups (" << r.primary_groups << "), "
                  << r.shadow_group_size << "x" << r.shadow_group_size << " shadow groups (" << fmt_count(r.shadow_groups)
                  << ", " << fmt_count(r.shadow_rays) << " rays). OBJ load " << fmt_time(r.load_s)
                  << ". Times: front end best of " << r.frontend_repeat << " frame(s), Embree best of "
                  << r.embree_repeat << " run(s).\n\n";
        std::cout << "| phase | RAPLAS front end, " << T << " thr";
        if (r.has_single) std::cout << " | RAPLAS front end, 1 thr";
        std::cout << " | Embree 3, 1 thr | Embree 3, " << T << " thr |\n|---|---|";
        if (r.has_single) std::cout << "---|";
        std::cout << "---|---|\n";
        auto row = [&](const std::string& phase, double fe, double fe1, const std::string& e1, const std::string& en) {
            std::cout << "| " << phase << " | " << fmt_time(fe);
            if (r.has_single) std::cout << " | " << fmt_time(fe1);
            std::cout << " | " << e1 << " | " << en << " |\n";
        };
        row("build (bounding spheres / BVH)", r.fe.spheres_s, r.fe_single.spheres_s, fmt_time(r.em_build_1),
            fmt_time(r.em_build_n));
        row("primary rays (" + fmt_count(r.primary_rays) + ")", r.fe.primary_s, r.fe_single.primary_s,
            fmt_time(r.em_primary_1), fmt_time(r.em_primary_n));
        row("shadow rays (" + fmt_count(r.shadow_rays) + ")", r.fe.shadow_s, r.fe_single.shadow_s,
            fmt_time(r.em_shadow_1), fmt_time(r.em_shadow_n));
        row("shading", r.fe.shade_s, r.fe_single.shade_s, "-", "-");
        row("**total**", total(r.fe), total(r.fe_single), fmt_time(r.em_build_1 + r.em_primary_1 + r.em_shadow_1),
            fmt_time(r.em_build_n + r.em_primary_n + r.em_shadow_n));
        const double rays = double(r.primary_rays + r.shadow_rays);
        std::cout << "| Mrays/s (primary + shadow, build excluded) | " << fmt_rate(rays, r.fe.primary_s + r.fe.shadow_s);
        if (r.has_single) std::cout << " | " << fmt_rate(rays, r.fe_single.primary_s + r.fe_single.shadow_s);
        std::cout << " | " << fmt_rate(rays, r.em_primary_1 + r.em_shadow_1) << " | "
                  << fmt_rate(rays, r.em_primary_n + r.em_shadow_n) << " |\n\n";
        std::cout << "Front end work: " << fmt_count(r.fe_plane_tests) << " plane-sphere tests, "
                  << fmt_count(r.fe_rt_tests) << " ray-triangle tests. Shadow ray setup for Embree (not in its times): "
                  << fmt_time(r.shadow_setup_s) << ". Same answers: primary hit/miss differs on "
                  << r.primary_hit_mismatch << " rays, distance (> 1e-4 rel.) on " << r.primary_t_mismatch
                  << "; occluded shadow rays " << fmt_count(r.fe_occluded) << " (front end) vs "
                  << fmt_count(r.em_occluded) << " (Embree).\n\n";
    }
}

nlohmann::json to_json(const std::vector<Result>& rs, const std::string& command, const std::string& load_before,
                       const std::string& load_after) {
    nlohmann::json j;
    j["command"] = command;
    j["machine"] = bench::machine_json(load_before, load_after);
    auto phases = [](const PhaseTimes& t) {
        return nlohmann::json{{"spheres_s", t.spheres_s}, {"primary_s", t.primary_s}, {"shadow_s", t.shadow_s},
                              {"shade_s", t.shade_s}};
    };
    for (const Result& r : rs) {
        nlohmann::json s;
        s["name"] = r.name;
        s["source"] = r.source;
        s["triangles"] = r.triangles;
        s["spheres"] = r.spheres;
        s["triangles_per_sphere"] = r.tris_per_sphere;
        s["image"] = {r.width, r.height};
        s["group_size"] = r.group_size;
        s["shadow_group_size"] = r.shadow_group_size;
        s["threads"] = r.threads;
        s["frontend_repeat"] = r.frontend_repeat;
        s["embree_repeat"] = r.embree_repeat;
        s["load_s"] = r.load_s;
        s["primary_groups"] = r.primary_groups;
        s["primary_rays"] = r.primary_rays;
        s["shadow_groups"] = r.shadow_groups;
        s["shadow_rays"] = r.shadow_rays;
        s["embree_only"] = r.embree_only;
        s["frontend"] = phases(r.fe);
        if (r.has_single) s["frontend_1_thread"] = phases(r.fe_single);
        s["frontend_work"] = {{"plane_sphere_tests", r.fe_plane_tests}, {"ray_triangle_tests", r.fe_rt_tests}};
        s["embree"] = {{"build_1_thread_s", r.em_build_1}, {"build_s", r.em_build_n},
                       {"primary_1_thread_s", r.em_primary_1}, {"primary_s", r.em_primary_n},
                       {"shadow_1_thread_s", r.em_shadow_1}, {"shadow_s", r.em_shadow_n},
                       {"shadow_ray_setup_s", r.embree_only ? r.em_shadow_setup_n : r.shadow_setup_s}};
        s["agreement"] = {{"primary_hit_mismatch", r.primary_hit_mismatch},
                          {"primary_t_mismatch", r.primary_t_mismatch},
                          {"frontend_occluded_shadow_rays", r.fe_occluded},
                          {"embree_occluded_shadow_rays", r.em_occluded}};
        j["scenes"].push_back(s);
    }
    return j;
}

}  // namespace
}  // namespace raplas

int main(int argc, char** argv) {
    using namespace raplas;
    Options o;
    CLI::App app{"RAPLAS front end vs Embree 3: wall time per phase on the same rays"};
    app.add_option("--scene", o.scenes, "scenes to run: bunny, sportscar, conference (repeatable)")->capture_default_str();
    app.add_option("--size", o.size, "image width and height")->capture_default_str()->check(CLI::Range(1, 4096));
    app.add_option("--width", o.width, "image width (default: --size)")->check(CLI::Range(1, 8192));
    app.add_option("--height", o.height, "image height (default: --size)")->check(CLI::Range(1, 8192));
    app.add_flag("--embree-only", o.embree_only,
                 "Embree alone on the frame's primary and shadow rays (the front end traces the primary rays only; "
                 "for big frames)");
    app.add_option("--threads", o.threads, "threads for the front end and the multi-threaded Embree runs (0: all)")
        ->capture_default_str();
    app.add_option("--repeat", o.repeat, "Embree builds and traces: best of this many runs")->capture_default_str()->check(CLI::Range(1, 100));
    app.add_option("--frontend-repeat", o.frontend_repeat, "front end: best (by total) of this many frames")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    app.add_flag("--frontend-single-thread", o.frontend_single, "also time the front end on one thread");
    app.add_option("--json", o.json, "write every number as JSON");
    app.add_option("--shared", o.shared, "shared scenes folder")->capture_default_str();
    app.add_option("--scene-dir", o.scene_dir, "project scene files (NAME.toml used when present)")->capture_default_str();
    CLI11_PARSE(app, argc, argv);

    std::string command;
    for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(i ? argv[i] : "raplas_bench_frontend");

    try {
        // Scene files name meshes relative to the shared scenes folder.
        std::string path = o.shared;
        if (const char* env = std::getenv("RAPLAS_SCENE_PATH")) path += std::string(":") + env;
        setenv("RAPLAS_SCENE_PATH", path.c_str(), 1);

        const std::string load_before = load_average();
        const unsigned threads = o.threads ? o.threads : default_threads();
        std::vector<Result> results;
        for (const auto& name : o.scenes) {
            auto it = std::find_if(kKnown.begin(), kKnown.end(), [&](const KnownScene& k) { return k.name == name; });
            if (it == kKnown.end()) {
                std::cerr << "raplas_bench_frontend: unknown scene '" << name << "' (bunny, sportscar, conference)\n";
                return 2;
            }
            results.push_back(run_scene(*it, o, threads));
        }
        const std::string load_after = load_average();
        print_markdown(results, command, load_before, load_after);
        if (!o.json.empty()) {
            std::ofstream out(o.json);
            out << to_json(results, command, load_before, load_after).dump(2) << "\n";
            if (!out) throw std::runtime_error("cannot write " + o.json);
        }
    } catch (const std::exception& e) {
        std::cerr << "raplas_bench_frontend: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
