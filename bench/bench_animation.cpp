// Per-frame host cost of animated scenes: for each frame, the time to rebuild
// the bounding spheres (and the sphere tree used for culling) of the moved
// geometry, the paths that carry frame 0's spheres to the frame instead
// (refit_spheres(): moved by the rigid motion, or fitted again in frame 0's
// grouping), Embree 3 building a new BVH and refitting one
// (RTC_BUILD_QUALITY_REFIT) for the same frame, and both tracers' time for
// the frame's primary and shadow rays. Each carried sphere set is compared
// with the full rebuild: bit-identity, centre and radius differences, and
// whether it still encloses its moved triangles. Prints Markdown tables;
// --json writes every number.
#include <embree3/rtcore.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "raplas/core/cull.hpp"
#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/spheres.hpp"
#include "raplas/frontend/tracer.hpp"
#include "raplas/scene/animation.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/bytes.hpp"
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


const std::vector<std::string> kScenes = {"conference_orbit", "bunny_turn", "wave"};

struct Options {
    std::vector<std::string> scenes = kScenes;
    int width = 64, height = 64;
    int frames = 8;
    unsigned threads = 2;
    int repeat = 3;
    int shadow_size = 0;  // 0: the scene file's
    bool hit_check = true;
    std::string json, images;
    std::string shared = RAPLAS_SHARED_SCENES;
    std::string scene_dir = std::string(RAPLAS_SOURCE_DIR) + "/scenes";
};

// Best (smallest) wall time of `repeat` runs of body(); the last run's result is kept by body.
template <class F>
double best_of(int repeat, F&& body) {
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < std::max(1, repeat); ++k) {
        const auto t0 = clock_type::now();
        body();
        best = std::min(best, since(t0));
    }
    return best;
}

// ---- the animation's rigid motions ----------------------------------------------
// motion_at() (raplas/scene/animation.hpp) is what scene_at_frame() applies;
// the benchmark checks, frame by frame, that it moves every corner to the
// very bits scene_at_frame() gives.

// Each mesh triangle's motion at a frame, for refit_spheres(): motions[0] is
// the identity (the floor, and triangles no track moves); a triangle moved by
// its object's track and the whole mesh's ("*") is given -1 (moved otherwise:
// fitted again), as is every triangle of a deforming mesh.
struct FrameMotions {
    bool rigid = false;  // no deformation: every triangle moves rigidly (or not at all)
    std::vector<std::int32_t> tri_motion;
    std::vector<RigidMotion> motions;
};

FrameMotions frame_motions(const Scene& base, const Animation& a, int frame) {
    FrameMotions fm;
    if (a.deform != Deform::none) return fm;
    fm.rigid = true;
    const Mesh& m = base.mesh;
    fm.motions.push_back(RigidMotion{});
    std::map<std::int32_t, std::int32_t> track_of;  // object -> motion index
    std::int32_t whole = -1;
    for (const ObjectTrack& t : a.objects) {
        fm.motions.push_back(motion_at(t, frame));
        const auto k = static_cast<std::int32_t>(fm.motions.size() - 1);
        if (t.object < 0) whole = k;
        else track_of[t.object] = k;
    }
    const bool named = m.triangle_object.size() == m.triangles.size();
    fm.tri_motion.assign(m.triangles.size(), 0);
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const std::int32_t obj = named ? m.triangle_object[t] : 0;
        if (named && obj == Mesh::kAddedObject) continue;  // the floor never moves
        const auto it = named ? track_of.find(obj) : track_of.end();
        const std::int32_t own = it == track_of.end() ? -1 : it->second;
        if (own >= 0 && whole >= 0) fm.tri_motion[t] = -1;
        else if (own >= 0) fm.tri_motion[t] = own;
        else if (whole >= 0) fm.tri_motion[t] = whole;
    }
    return fm;
}

// Corners of `moved` that are not the float rounding of their motion applied
// to `still`'s (rigid triangles only).
std::size_t motion_mismatches(const Mesh& still, const Mesh& moved, const FrameMotions& fm) {
    std::size_t bad = 0;
    for (std::size_t t = 0; t < fm.tri_motion.size(); ++t) {
        const std::int32_t k = fm.tri_motion[t];
        if (k < 0) continue;
        for (int c = 0; c < 3; ++c) {
            const Vec3f want = to_f(fm.motions[static_cast<std::size_t>(k)].apply(to_d(still.corner(t, c))));
            const Vec3f got = moved.corner(t, c);
            if (!same_bits(want, got)) ++bad;
        }
    }
    return bad;
}

// ---- sphere sets compared -----------------------------------------------------

bool same_mesh(const Mesh& a, const Mesh& b) {
    return a.triangles == b.triangles && same_bytes(a.vertices, b.vertices);
}

// A carried sphere set against the rebuild of the same frame.
struct Comparison {
    bool computed = false;
    bool identical = false;          // every array byte for byte
    bool same_order = false;         // same grouping, same Sphere and Triangle Memory order
    std::size_t matched = 0;         // spheres whose triangles are exactly one rebuilt sphere's
    std::size_t centre_equal = 0;    // of the matched: centre bits equal
    std::size_t radius_equal = 0;    // of the matched: radius bits equal
    double max_centre_diff = 0;      // of the matched: largest |c - c_rebuild|
    double max_centre_diff_rel = 0;  // ... over the rebuilt radius
    double max_radius_diff = 0;      // of the matched: largest |r - r_rebuild|
    double max_radius_diff_rel = 0;  // ... over the rebuilt radius
    double sum_radius_ratio = 0;     // sum of radii over the rebuild's
    std::size_t not_enclosing = 0;   // spheres some moved corner is outside of (with the margin)
    double min_slack = 0;            // smallest r - margin - |v - c| over every sphere and corner
    double min_slack_rel = 0;        // ... over that sphere's radius
    bool hits_checked = false;
    std::size_t hit_diff = 0;        // primary rays whose nearest hit differs from the rebuild's
};

// Smallest r - margin - |v - c| of a sphere set over the corners of `mesh`.
void enclosure(const SphereSet& s, const Mesh& mesh, double margin, std::size_t& failing, double& min_slack,
               double& min_slack_rel) {
    failing = 0;
    min_slack = std::numeric_limits<double>::infinity();
    min_slack_rel = min_slack;
    for (std::size_t j = 0; j < s.spheres.size(); ++j) {
        const Vec3d c = to_d(s.spheres[j].c);
        const double r = s.spheres[j].r;
        double far = 0;
        for (std::size_t i = s.first_tri[j]; i < s.first_tri[j] + s.tri_count[j]; ++i)
            for (int k = 0; k < 3; ++k)
                far = std::max(far, length(to_d(mesh.corner(static_cast<std::size_t>(s.tri_mesh_index[i]), k)) - c));
        const double slack = r - margin - far;
        if (slack < 0) ++failing;
        min_slack = std::min(min_slack, slack);
        if (r > 0) min_slack_rel = std::min(min_slack_rel, slack / r);
    }
}

Comparison compare(const SphereSet& s, const SphereSet& rebuilt, const Mesh& mesh, double margin) {
    Comparison c;
    c.computed = true;
    c.identical = same_spheres(s, rebuilt);
    c.same_order = s.first_tri == rebuilt.first_tri && s.tri_count == rebuilt.tri_count &&
                   s.tri_mesh_index == rebuilt.tri_mesh_index;
    std::vector<std::size_t> pos(rebuilt.tri_mesh_index.size());
    for (std::size_t i = 0; i < pos.size(); ++i) pos[static_cast<std::size_t>(rebuilt.tri_mesh_index[i])] = i;
    double sum = 0, sum_rebuilt = 0;
    for (const auto& sp : rebuilt.spheres) sum_rebuilt += sp.r;
    for (std::size_t j = 0; j < s.spheres.size(); ++j) {
        sum += s.spheres[j].r;
        const std::size_t lo = s.first_tri[j], n = s.tri_count[j];
        const std::size_t k = rebuilt.tri_sphere[pos[static_cast<std::size_t>(s.tri_mesh_index[lo])]];
        if (rebuilt.tri_count[k] != n) continue;
        bool same = true;
        for (std::size_t i = 0; i < n && same; ++i)
            same = rebuilt.tri_mesh_index[rebuilt.first_tri[k] + i] == s.tri_mesh_index[lo + i];
        if (!same) continue;
        ++c.matched;
        const Sphere& a = s.spheres[j];
        const Sphere& b = rebuilt.spheres[k];
        if (same_bits(a.c, b.c)) ++c.centre_equal;
        if (same_bits(a.r, b.r)) ++c.radius_equal;
        const double dc = length(to_d(a.c) - to_d(b.c)), dr = std::fabs(double(a.r) - double(b.r));
        c.max_centre_diff = std::max(c.max_centre_diff, dc);
        c.max_radius_diff = std::max(c.max_radius_diff, dr);
        if (b.r > 0) {
            c.max_centre_diff_rel = std::max(c.max_centre_diff_rel, dc / b.r);
            c.max_radius_diff_rel = std::max(c.max_radius_diff_rel, dr / b.r);
        }
    }
    c.sum_radius_ratio = sum_rebuilt > 0 ? sum / sum_rebuilt : 1;
    enclosure(s, mesh, margin, c.not_enclosing, c.min_slack, c.min_slack_rel);
    return c;
}

// Primary rays whose nearest hit (mesh triangle and distance) differs between two sphere sets.
std::size_t primary_hit_differences(const Scene& scene, const SphereSet& a, const SphereSet& b, unsigned threads) {
    const std::vector<RayGroup> groups = primary_groups(scene);
    const Tracer ta(a, NumFormat::float32()), tb(b, NumFormat::float32());
    std::vector<std::size_t> diff(groups.size());
    parallel_for(groups.size(), threads, [&](std::size_t i) {
        GroupResult ra, rb;
        ta.trace(groups[i], ra, false, false);
        tb.trace(groups[i], rb, false, false);
        for (std::size_t r = 0; r < ra.hits.size(); ++r) {
            const Hit& x = ra.hits[r];
            const Hit& y = rb.hits[r];
            const std::int32_t mx = x.tri < 0 ? -1 : a.tri_mesh_index[static_cast<std::size_t>(x.tri)];
            const std::int32_t my = y.tri < 0 ? -1 : b.tri_mesh_index[static_cast<std::size_t>(y.tri)];
            if (mx != my || (mx >= 0 && !same_bits(x.t, y.t))) ++diff[i];
        }
    });
    std::size_t n = 0;
    for (std::size_t d : diff) n += d;
    return n;
}

// ---- Embree --------------------------------------------------------------------

class EmbreeDevice {
public:
    explicit EmbreeDevice(unsigned threads) {
        const std::string cfg = "threads=" + std::to_string(threads);
        device_ = rtcNewDevice(cfg.c_str());
        if (!device_) throw std::runtime_error("rtcNewDevice failed");
    }
    ~EmbreeDevice() { rtcReleaseDevice(device_); }
    EmbreeDevice(const EmbreeDevice&) = delete;
    EmbreeDevice& operator=(const EmbreeDevice&) = delete;
    RTCDevice get() const { return device_; }
    void check(const char* what) const {
        if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what + " failed");
    }

private:
    RTCDevice device_ = nullptr;
};

// One triangle geometry in its own scene; `fill_s` is the time to copy the
// mesh into Embree's buffers, `commit_s` that of rtcCommitScene (the BVH build).
class EmbreeMesh {
public:
    EmbreeMesh(const EmbreeDevice& dev, const Mesh& mesh, RTCBuildQuality quality) : dev_(dev) {
        auto t0 = clock_type::now();
        scene_ = rtcNewScene(dev.get());
        geom_ = new_embree_mesh(dev.get(), mesh, &vertices_);
        vertex_count_ = mesh.vertices.size();
        if (quality == RTC_BUILD_QUALITY_REFIT) {
            // Embree honours a geometry's build quality only in a scene of
            // quality LOW (a two-level structure, one BVH per geometry).
            rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_LOW);
            rtcSetGeometryBuildQuality(geom_, quality);
        }
        triangles_ = mesh.triangles;
        rtcCommitGeometry(geom_);
        rtcAttachGeometry(scene_, geom_);
        fill_s_ = since(t0);
        t0 = clock_type::now();
        rtcCommitScene(scene_);
        commit_s_ = since(t0);
        dev.check("scene build");
    }
    ~EmbreeMesh() {
        rtcReleaseGeometry(geom_);
        rtcReleaseScene(scene_);
    }
    EmbreeMesh(const EmbreeMesh&) = delete;
    EmbreeMesh& operator=(const EmbreeMesh&) = delete;

    double fill_s() const { return fill_s_; }
    double commit_s() const { return commit_s_; }
    // Same vertex count and triangles: the vertex buffer can be updated in place.
    bool same_topology(const Mesh& m) const { return m.vertices.size() == vertex_count_ && m.triangles == triangles_; }

    // New vertex positions, then rtcUpdateGeometryBuffer + rtcCommitGeometry +
    // rtcCommitScene: a refit for a geometry of RTC_BUILD_QUALITY_REFIT.
    // Returns the time of the three calls; `fill_s` gets the copy's.
    double update(const Mesh& m, double& fill_s) {
        auto t0 = clock_type::now();
        fill_embree_vertices(vertices_, m);
        fill_s = since(t0);
        t0 = clock_type::now();
        rtcUpdateGeometryBuffer(geom_, RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(geom_);
        rtcCommitScene(scene_);
        const double s = since(t0);
        dev_.check("refit");
        return s;
    }

    // Ray parameter of the nearest hit in (0, inf), or -1 for a miss.
    float intersect(const Ray& r) const {
        const RTCRayHit rh = embree_nearest(scene_, r);
        return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? rh.ray.tfar : -1.0f;
    }
    // Anything in (0, r.tmax]?
    bool occluded(const Ray& r) const { return embree_occluded(scene_, r); }

private:

    const EmbreeDevice& dev_;
    RTCScene scene_ = nullptr;
    RTCGeometry geom_ = nullptr;
    float* vertices_ = nullptr;
    std::size_t vertex_count_ = 0;
    std::vector<std::array<std::uint32_t, 3>> triangles_;
    double fill_s_ = 0, commit_s_ = 0;
};

// Wall time of body(i) for i in [0, n) on `threads` threads (chunks of 256), best of `repeat`.
template <class F>
double best_parallel(std::size_t n, unsigned threads, int repeat, F&& body) {
    constexpr std::size_t kChunk = 256;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    return best_of(repeat, [&] {
        parallel_for(chunks, threads, [&](std::size_t c) {
            const std::size_t end = std::min(n, (c + 1) * kChunk);
            for (std::size_t i = c * kChunk; i < end; ++i) body(i);
        });
    });
}

struct EmbreeRays {
    double primary_s = 0, shadow_s = 0;
    std::vector<float> primary_t;
    std::uint64_t occluded = 0;
};

EmbreeRays trace_embree(const EmbreeMesh& em, const std::vector<Ray>& primary, const std::vector<Ray>& shadow,
                        unsigned threads, int repeat) {
    EmbreeRays r;
    r.primary_t.resize(primary.size());
    r.primary_s = best_parallel(primary.size(), threads, repeat, [&](std::size_t i) { r.primary_t[i] = em.intersect(primary[i]); });
    std::vector<unsigned char> occ(shadow.size());
    r.shadow_s = best_parallel(shadow.size(), threads, repeat, [&](std::size_t i) { occ[i] = em.occluded(shadow[i]) ? 1 : 0; });
    for (unsigned char c : occ) r.occluded += c;
    return r;
}

// ---- one scene -------------------------------------------------------------------

const char* const kPaths[] = {"transform", "transform_radius", "refit", "reuse"};
constexpr int kPathCount = 4;

struct FrameResult {
    int frame = 0;
    double scene_s = 0;  // scene_at_frame(): the frame's camera, light and moved mesh
    double margin = 0;
    bool margin_same = false, mesh_same = false;  // as frame 0's (the still scene's)
    std::size_t motion_mismatch = 0;              // corners the benchmark's motion does not reproduce
    double rebuild_s = 0, tree_s = 0;
    std::size_t spheres = 0;
    // transform, transform_radius, refit (fit again in frame 0's grouping), reuse (frame 0's set as it is)
    double path_s[kPathCount] = {0, 0, 0, 0};
    bool path_run[kPathCount] = {false, false, false, false};
    Comparison cmp[kPathCount];
    // Embree
    bool refit_ok = false;
    double em_fill_s = 0, em_build_s = 0, em_refit_fill_s = 0, em_refit_s = 0;
    double em_primary_s = 0, em_shadow_s = 0, em_refit_primary_s = 0, em_refit_shadow_s = 0;
    // front end
    PhaseTimes fe;
    std::size_t primary_rays = 0, shadow_groups = 0, shadow_rays = 0;
    std::uint64_t plane_tests = 0, rt_tests = 0;
    double shadow_setup_s = 0;
    std::size_t primary_hit_mismatch = 0, primary_t_mismatch = 0, refit_primary_diff = 0;
    std::uint64_t fe_occluded = 0, em_occluded = 0, em_refit_occluded = 0;
};

struct SceneResult {
    std::string name, source, kind;
    std::size_t triangles = 0, vertices = 0;
    int tris_per_sphere = 0, width = 0, height = 0, group_size = 0, shadow_group_size = 0, total_frames = 0;
    unsigned threads = 0;
    int repeat = 0;
    double load_s = 0, still_spheres_s = 0, em_refit_initial_s = 0;
    std::vector<FrameResult> frames;
};

void write_ppm(const std::string& path, int w, int h, const std::vector<float>& rgb) {
    std::ofstream out(path, std::ios::binary);
    out << "P6\n" << w << " " << h << "\n255\n";
    for (float v : rgb) {
        const double x = std::clamp(double(v), 0.0, 1.0);
        const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
        out.put(static_cast<char>(std::lround(s * 255.0)));
    }
    if (!out) throw std::runtime_error("cannot write " + path);
}

SceneResult run_scene(const std::string& name, const Options& o) {
    SceneResult R;
    R.name = name;
    R.threads = o.threads;
    R.repeat = o.repeat;
    const unsigned T = o.threads;
    const fs::path file = fs::path(o.scene_dir) / (name + ".toml");
    if (!fs::is_regular_file(file)) throw std::runtime_error("no scene file " + file.string());
    R.source = file.lexically_relative(fs::path(RAPLAS_SOURCE_DIR)).string();
    if (R.source.empty() || R.source.rfind("..", 0) == 0) R.source = file.string();
    SceneRequest req;
    req.scene_file = file.string();
    req.overrides = {"image.width=" + std::to_string(o.width), "image.height=" + std::to_string(o.height)};
    if (o.shadow_size > 0) req.overrides.push_back("groups.shadow_size=" + std::to_string(o.shadow_size));
    auto t0 = clock_type::now();
    const Scene base = load_scene(req);
    R.load_s = since(t0);
    if (!base.animation) throw std::runtime_error(file.string() + " is not animated");
    const Animation& anim = *base.animation;
    R.total_frames = anim.frames;
    R.triangles = base.mesh.triangle_count();
    R.vertices = base.mesh.vertices.size();
    R.tris_per_sphere = base.tris_per_sphere;
    R.width = base.width;
    R.height = base.height;
    R.group_size = base.group_size;
    R.shadow_group_size = base.shadow_group_size;
    R.kind = anim.deform != Deform::none ? "deforming mesh" : !anim.objects.empty() ? "rigid motion" : "static geometry";
    std::fprintf(stderr, "%s: %zu triangles, %d frames (%s), loaded in %.2f s\n", name.c_str(), R.triangles, anim.frames,
                 R.kind.c_str(), R.load_s);

    // Frame 0's spheres (of the still scene, whose mesh the motions move).
    const double u = NumFormat::float32().unit_roundoff();
    const double still_margin = conservative_margin(u, scene_extent(base));
    SphereSet still;
    R.still_spheres_s = best_of(1, [&] {
        still = build_spheres(base.mesh, base.tris_per_sphere, base.sphere_method, still_margin, T);
    });

    EmbreeDevice dev(T);
    std::optional<EmbreeMesh> refit_mesh;
    refit_mesh.emplace(dev, base.mesh, RTC_BUILD_QUALITY_REFIT);
    R.em_refit_initial_s = refit_mesh->commit_s();

    const int n = std::min(o.frames, anim.frames);
    for (int i = 0; i < n; ++i) {
        FrameResult F;
        F.frame = static_cast<int>(static_cast<long long>(i) * anim.frames / n);
        std::fprintf(stderr, "%s: frame %d (%d of %d)...\n", name.c_str(), F.frame, i + 1, n);
        Scene scene;
        F.scene_s = best_of(1, [&] { scene = scene_at_frame(base, F.frame); });
        F.margin = conservative_margin(u, scene_extent(scene));
        F.margin_same = F.margin == still_margin;
        F.mesh_same = same_mesh(scene.mesh, base.mesh);
        const FrameMotions fm = frame_motions(base, anim, F.frame);
        if (fm.rigid) F.motion_mismatch = motion_mismatches(base.mesh, scene.mesh, fm);

        // Full rebuild, and the sphere tree the tracer culls with.
        SphereSet rebuilt;
        F.rebuild_s = best_of(o.repeat, [&] {
            rebuilt = build_spheres(scene.mesh, scene.tris_per_sphere, scene.sphere_method, F.margin, T);
        });
        F.spheres = rebuilt.sphere_count();
        F.tree_s = best_of(o.repeat, [&] { const SphereTree tree(rebuilt.spheres); (void)tree; });

        // The paths that carry frame 0's spheres.
        const SphereRefit modes[3] = {SphereRefit::transform, SphereRefit::transform_radius, SphereRefit::enclose};
        for (int p = 0; p < kPathCount; ++p) {
            if (p < 2 && !fm.rigid) continue;
            SphereSet carried;
            if (p < 3) {
                F.path_s[p] = best_of(o.repeat, [&] {
                    carried = refit_spheres(still, still_margin, scene.mesh, fm.tri_motion, fm.motions, modes[p],
                                            scene.sphere_method, F.margin, T);
                });
            } else {
                if (!(F.mesh_same && F.margin_same)) continue;
                carried = still;  // nothing to compute
            }
            F.path_run[p] = true;
            F.cmp[p] = compare(carried, rebuilt, scene.mesh, F.margin);
            if (p == 0 && o.hit_check) {
                F.cmp[p].hits_checked = true;
                F.cmp[p].hit_diff = F.cmp[p].identical ? 0 : primary_hit_differences(scene, carried, rebuilt, T);
            }
        }

        // Embree: a new scene (default quality), and the refit scene's vertices updated.
        {
            std::optional<EmbreeMesh> fresh;
            F.em_build_s = std::numeric_limits<double>::infinity();
            for (int k = 0; k < std::max(1, o.repeat); ++k) {
                fresh.reset();
                fresh.emplace(dev, scene.mesh, RTC_BUILD_QUALITY_MEDIUM);
                F.em_build_s = std::min(F.em_build_s, fresh->commit_s());
                F.em_fill_s = fresh->fill_s();
            }
            F.refit_ok = refit_mesh->same_topology(scene.mesh);
            if (F.refit_ok) {
                F.em_refit_s = std::numeric_limits<double>::infinity();
                for (int k = 0; k < std::max(1, o.repeat); ++k)
                    F.em_refit_s = std::min(F.em_refit_s, refit_mesh->update(scene.mesh, F.em_refit_fill_s));
            }

            // The front end renders the frame (its own sphere build included, reported apart).
            std::fprintf(stderr, "%s: frame %d: front end...\n", name.c_str(), F.frame);
            FrameOptions fo;
            fo.threads = T;
            const Frame f = render_frame(scene, fo);
            F.fe = f.times;
            F.primary_rays = f.pixel_ray.size();
            F.shadow_groups = f.shadow_group_count;
            F.plane_tests = f.primary_counts.plane_tests + f.shadow_counts.plane_tests;
            F.rt_tests = f.primary_counts.rt_tests + f.shadow_counts.rt_tests;
            if (!o.images.empty()) {
                char buf[64];
                std::snprintf(buf, sizeof buf, "_%04d.ppm", F.frame);
                write_ppm((fs::path(o.images) / (name + buf)).string(), f.width, f.height, f.rgb);
            }

            // The same primary and shadow rays through Embree.
            t0 = clock_type::now();
            const bench::ShadowRays sr = bench::frame_shadow_rays(scene, f, T);
            const std::vector<Ray>& shadow_rays = sr.rays;
            F.shadow_setup_s = since(t0);
            F.shadow_rays = shadow_rays.size();
            F.fe_occluded = sr.occluded;

            std::fprintf(stderr, "%s: frame %d: Embree rays...\n", name.c_str(), F.frame);
            const EmbreeRays er = trace_embree(*fresh, f.pixel_ray, shadow_rays, T, o.repeat);
            F.em_primary_s = er.primary_s;
            F.em_shadow_s = er.shadow_s;
            F.em_occluded = er.occluded;
            const bench::PrimaryMismatch pm = bench::compare_primary(f, er.primary_t);
            F.primary_hit_mismatch = pm.hit;
            F.primary_t_mismatch = pm.distance;
            if (F.refit_ok) {
                const EmbreeRays rr = trace_embree(*refit_mesh, f.pixel_ray, shadow_rays, T, o.repeat);
                F.em_refit_primary_s = rr.primary_s;
                F.em_refit_shadow_s = rr.shadow_s;
                F.em_refit_occluded = rr.occluded;
                for (std::size_t px = 0; px < rr.primary_t.size(); ++px)
                    if (!same_bits(rr.primary_t[px], er.primary_t[px])) ++F.refit_primary_diff;
            }
        }
        R.frames.push_back(F);
    }
    return R;
}

// ---- reporting --------------------------------------------------------------------

std::string fmt_ms(double s) {
    char buf[32];
    const double ms = s * 1e3;
    if (ms >= 100) std::snprintf(buf, sizeof buf, "%.0f", ms);
    else if (ms >= 10) std::snprintf(buf, sizeof buf, "%.1f", ms);
    else std::snprintf(buf, sizeof buf, "%.2f", ms);
    return buf;
}


std::string fmt_g(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

std::string fmt_ratio(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.7f", x);
    return buf;
}



const char* const kPathTitles[] = {"transform (centre moved, radius scaled + rounding allowance)",
                                   "transform + radius (centre moved, radius from the moved corners)",
                                   "refit (frame 0's grouping, each sphere fitted again)",
                                   "reuse (frame 0's spheres as they are)"};
const char* const kPathShort[] = {"transform", "transform + radius", "refit", "reuse"};

void print_markdown(const std::vector<SceneResult>& rs, const std::string& command, const std::string& load_before,
                    const std::string& load_after) {
    std::cout << "Command: `" << command << "`  \n";
    std::cout << "Machine: " << std::thread::hardware_concurrency() << " hardware threads, " << cpu_model()
              << "; 1-minute load average " << load_before << " before the run, " << load_after << " after.\n\n";
    for (const SceneResult& r : rs) {
        std::cout << "### " << r.name << "\n\n";
        std::cout << r.source << " (" << r.kind << "): " << fmt_count(r.triangles) << " triangles, K = " << r.tris_per_sphere
                  << ", " << r.width << "x" << r.height << " image, " << r.group_size << "x" << r.group_size
                  << " primary and " << r.shadow_group_size << "x" << r.shadow_group_size << " shadow groups; "
                  << r.frames.size() << " of its " << r.total_frames << " frames, " << r.threads
                  << " threads everywhere. Scene load " << fmt_ms(r.load_s) << " ms, frame 0's spheres "
                  << fmt_ms(r.still_spheres_s) << " ms, Embree's refit scene built once in "
                  << fmt_ms(r.em_refit_initial_s) << " ms. Builds and Embree traces: best of " << r.repeat
                  << "; the front end renders each frame once. All times in ms.\n\n";
        std::cout << "| frame | frame scene | spheres rebuild | sphere tree | transform | transform + radius | refit "
                     "| Embree build | Embree refit | RAPLAS rays | Embree rays | Embree rays, refitted BVH |\n"
                     "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for (const FrameResult& f : r.frames) {
            auto path = [&](int p) { return f.path_run[p] ? fmt_ms(f.path_s[p]) : std::string("-"); };
            std::cout << "| " << f.frame << " | " << fmt_ms(f.scene_s) << " | " << fmt_ms(f.rebuild_s) << " | "
                      << fmt_ms(f.tree_s) << " | " << path(0) << " | " << path(1) << " | " << path(2) << " | "
                      << fmt_ms(f.em_build_s) << " | " << (f.refit_ok ? fmt_ms(f.em_refit_s) : "-") << " | "
                      << fmt_ms(f.fe.primary_s + f.fe.shadow_s + f.fe.shade_s) << " | "
                      << fmt_ms(f.em_primary_s + f.em_shadow_s) << " | "
                      << (f.refit_ok ? fmt_ms(f.em_refit_primary_s + f.em_refit_shadow_s) : "-") << " |\n";
        }
        {
            // Means over the frames (a column whose path did not run in some frame: over those it ran in).
            const double nf = double(r.frames.size());
            FrameResult m;
            double path_n[kPathCount] = {0, 0, 0, 0}, refit_n = 0;
            for (const FrameResult& f : r.frames) {
                m.scene_s += f.scene_s / nf;
                m.rebuild_s += f.rebuild_s / nf;
                m.tree_s += f.tree_s / nf;
                for (int p = 0; p < kPathCount; ++p)
                    if (f.path_run[p]) m.path_s[p] += f.path_s[p], path_n[p] += 1;
                m.em_build_s += f.em_build_s / nf;
                if (f.refit_ok) {
                    m.em_refit_s += f.em_refit_s;
                    m.em_refit_primary_s += f.em_refit_primary_s + f.em_refit_shadow_s;
                    refit_n += 1;
                }
                m.fe.primary_s += (f.fe.primary_s + f.fe.shadow_s + f.fe.shade_s) / nf;
                m.em_primary_s += (f.em_primary_s + f.em_shadow_s) / nf;
            }
            auto path = [&](int p) { return path_n[p] > 0 ? fmt_ms(m.path_s[p] / path_n[p]) : std::string("-"); };
            std::cout << "| **mean** | " << fmt_ms(m.scene_s) << " | " << fmt_ms(m.rebuild_s) << " | " << fmt_ms(m.tree_s)
                      << " | " << path(0) << " | " << path(1) << " | " << path(2) << " | " << fmt_ms(m.em_build_s) << " | "
                      << (refit_n > 0 ? fmt_ms(m.em_refit_s / refit_n) : "-") << " | " << fmt_ms(m.fe.primary_s) << " | "
                      << fmt_ms(m.em_primary_s) << " | " << (refit_n > 0 ? fmt_ms(m.em_refit_primary_s / refit_n) : "-")
                      << " |\n";
        }
        std::cout << "\nFrame scene: scene_at_frame() (camera, light, moved mesh). Spheres rebuild: build_spheres(), "
                     "what render_frame() does every frame; sphere tree: the culling tree over them (SphereTree), "
                     "also rebuilt every frame. Transform, transform + radius, refit: refit_spheres() from frame 0's "
                     "spheres (\"-\": no rigid motion to carry). Embree build: rtcCommitScene of a new scene "
                     "(default quality; copying the mesh into its buffers is not included: build_fill_s in the JSON); Embree refit: rtcUpdateGeometryBuffer + rtcCommitGeometry + rtcCommitScene of "
                     "an RTC_BUILD_QUALITY_REFIT geometry in a scene of RTC_BUILD_QUALITY_LOW, which Embree needs to honour it "
                     "(\"-\": topology changed). RAPLAS rays: render_frame()'s "
                     "primary + shadow + shading phases; Embree rays: the same primary and shadow rays.\n\n";
        std::cout << "| frame | primary rays | shadow groups | shadow rays | plane-sphere tests | ray-triangle tests "
                     "| RAPLAS primary / shadow / shading | Embree primary / shadow | hit/miss differ | distance differs "
                     "| occluded (RAPLAS / Embree / refitted) |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for (const FrameResult& f : r.frames)
            std::cout << "| " << f.frame << " | " << fmt_count(f.primary_rays) << " | " << fmt_count(f.shadow_groups)
                      << " | " << fmt_count(f.shadow_rays) << " | " << fmt_count(f.plane_tests) << " | "
                      << fmt_count(f.rt_tests) << " | " << fmt_ms(f.fe.primary_s) << " / " << fmt_ms(f.fe.shadow_s)
                      << " / " << fmt_ms(f.fe.shade_s) << " | " << fmt_ms(f.em_primary_s) << " / "
                      << fmt_ms(f.em_shadow_s) << " | " << f.primary_hit_mismatch << " | " << f.primary_t_mismatch
                      << " | " << fmt_count(f.fe_occluded) << " / " << fmt_count(f.em_occluded) << " / "
                      << (f.refit_ok ? fmt_count(f.em_refit_occluded) : "-") << " |\n";
        std::cout << "\n";

        std::cout << "Carried spheres against the full rebuild of the same frame (matched: spheres holding exactly "
                     "the triangles of one rebuilt sphere; slack: r - margin - |corner - centre|, smallest over all "
                     "spheres, over the radius; primary hits: rays whose nearest triangle or distance differs when "
                     "traced with the carried set):\n\n";
        std::cout << "| frame | path | bit-identical | same grouping and order | matched | centres equal | radii equal "
                     "| max centre diff (abs / rel) | max radius diff (abs / rel) | not enclosing | min slack (rel) "
                     "| sum of radii / rebuild | primary hits differ |\n"
                     "|---:|---|---|---|---:|---:|---:|---|---|---:|---:|---:|---:|\n";
        for (const FrameResult& f : r.frames) {
            for (int p = 0; p < kPathCount; ++p) {
                if (!f.path_run[p]) continue;
                const Comparison& c = f.cmp[p];
                std::cout << "| " << f.frame << " | " << kPathShort[p] << " | " << (c.identical ? "yes" : "no") << " | "
                          << (c.same_order ? "yes" : "no") << " | " << fmt_count(c.matched) << " | "
                          << fmt_count(c.centre_equal) << " | " << fmt_count(c.radius_equal) << " | "
                          << fmt_g(c.max_centre_diff) << " / " << fmt_g(c.max_centre_diff_rel) << " | "
                          << fmt_g(c.max_radius_diff) << " / " << fmt_g(c.max_radius_diff_rel) << " | "
                          << c.not_enclosing << " | " << fmt_g(c.min_slack_rel) << " | " << fmt_ratio(c.sum_radius_ratio)
                          << " | " << (c.hits_checked ? fmt_count(c.hit_diff) : "-") << " |\n";
            }
        }
        std::cout << "\n";
        bool any_mismatch = false, margins_same = true, meshes_same = true;
        for (const FrameResult& f : r.frames) {
            any_mismatch = any_mismatch || f.motion_mismatch;
            margins_same = margins_same && f.margin_same;
            meshes_same = meshes_same && f.mesh_same;
        }
        if (r.kind == "rigid motion") {
            int moved = 0, identical_frames = 0;
            double dc = 0, dcr = 0, dr = 0, drr = 0;
            std::size_t not_enclosing = 0, hit_diff = 0;
            bool hits = false;
            for (const FrameResult& f : r.frames) {
                if (!f.path_run[0] || f.mesh_same) continue;
                const Comparison& c = f.cmp[0];
                ++moved;
                identical_frames += c.identical;
                dc = std::max(dc, c.max_centre_diff);
                dcr = std::max(dcr, c.max_centre_diff_rel);
                dr = std::max(dr, c.max_radius_diff);
                drr = std::max(drr, c.max_radius_diff_rel);
                not_enclosing += c.not_enclosing;
                hits = hits || c.hits_checked;
                hit_diff += c.hit_diff;
            }
            if (moved > 0) {
                std::cout << "Transform path, over the " << moved << (moved == 1 ? " frame" : " frames")
                          << " where the mesh moved: bit-identical to the rebuild in " << identical_frames << "; largest centre difference " << fmt_g(dc) << " ("
                          << fmt_g(dcr) << " of the radius), largest radius difference " << fmt_g(dr) << " (" << fmt_g(drr)
                          << " of the radius); spheres not enclosing their moved triangles: " << not_enclosing;
                if (hits) std::cout << "; primary rays whose nearest hit differs: " << hit_diff;
                std::cout << ".\n\n";
            }
        }
        std::cout << "Sphere margin " << (margins_same ? "the same in every frame" : "changes between frames")
                  << "; mesh " << (meshes_same ? "the same in every frame" : "moves") << ".";
        if (r.kind == "rigid motion")
            std::cout << " The benchmark's rigid motions reproduce scene_at_frame()'s corners "
                      << (any_mismatch ? "NOT bit for bit (see motion_mismatch in the JSON)" : "bit for bit") << ".";
        std::cout << "\n\n";
    }
}

nlohmann::json to_json(const std::vector<SceneResult>& rs, const std::string& command, const std::string& load_before,
                       const std::string& load_after) {
    nlohmann::json j;
    j["command"] = command;
    j["machine"] = bench::machine_json(load_before, load_after);
    j["embree_version"] = RTC_VERSION_STRING;
    for (const SceneResult& r : rs) {
        nlohmann::json s;
        s["name"] = r.name;
        s["source"] = r.source;
        s["kind"] = r.kind;
        s["triangles"] = r.triangles;
        s["vertices"] = r.vertices;
        s["triangles_per_sphere"] = r.tris_per_sphere;
        s["image"] = {r.width, r.height};
        s["group_size"] = r.group_size;
        s["shadow_group_size"] = r.shadow_group_size;
        s["animation_frames"] = r.total_frames;
        s["threads"] = r.threads;
        s["repeat"] = r.repeat;
        s["load_s"] = r.load_s;
        s["frame0_spheres_s"] = r.still_spheres_s;
        s["embree_refit_initial_build_s"] = r.em_refit_initial_s;
        for (const FrameResult& f : r.frames) {
            nlohmann::json x;
            x["frame"] = f.frame;
            x["scene_at_frame_s"] = f.scene_s;
            x["margin"] = f.margin;
            x["margin_same_as_frame0"] = f.margin_same;
            x["mesh_same_as_frame0"] = f.mesh_same;
            x["motion_mismatch"] = f.motion_mismatch;
            x["spheres"] = f.spheres;
            x["spheres_rebuild_s"] = f.rebuild_s;
            x["sphere_tree_s"] = f.tree_s;
            for (int p = 0; p < kPathCount; ++p) {
                if (!f.path_run[p]) continue;
                const Comparison& c = f.cmp[p];
                nlohmann::json y = {{"description", kPathTitles[p]},
                                    {"bit_identical", c.identical},
                                    {"same_grouping_and_order", c.same_order},
                                    {"matched_spheres", c.matched},
                                    {"centres_equal", c.centre_equal},
                                    {"radii_equal", c.radius_equal},
                                    {"max_centre_diff", c.max_centre_diff},
                                    {"max_centre_diff_rel", c.max_centre_diff_rel},
                                    {"max_radius_diff", c.max_radius_diff},
                                    {"max_radius_diff_rel", c.max_radius_diff_rel},
                                    {"spheres_not_enclosing", c.not_enclosing},
                                    {"min_slack", c.min_slack},
                                    {"min_slack_rel", c.min_slack_rel},
                                    {"sum_radius_ratio", c.sum_radius_ratio}};
                if (p < 3) y["time_s"] = f.path_s[p];
                if (c.hits_checked) y["primary_hits_differ"] = c.hit_diff;
                x["paths"][kPaths[p]] = y;
            }
            x["embree"] = {{"build_fill_s", f.em_fill_s},
                           {"build_commit_s", f.em_build_s},
                           {"refit_possible", f.refit_ok},
                           {"refit_fill_s", f.em_refit_fill_s},
                           {"refit_s", f.em_refit_s},
                           {"primary_s", f.em_primary_s},
                           {"shadow_s", f.em_shadow_s},
                           {"refitted_primary_s", f.em_refit_primary_s},
                           {"refitted_shadow_s", f.em_refit_shadow_s},
                           {"shadow_ray_setup_s", f.shadow_setup_s}};
            x["frontend"] = {{"spheres_s", f.fe.spheres_s},
                             {"primary_s", f.fe.primary_s},
                             {"shadow_s", f.fe.shadow_s},
                             {"shade_s", f.fe.shade_s},
                             {"plane_sphere_tests", f.plane_tests},
                             {"ray_triangle_tests", f.rt_tests}};
            x["rays"] = {{"primary", f.primary_rays}, {"shadow_groups", f.shadow_groups}, {"shadow", f.shadow_rays}};
            x["agreement"] = {{"primary_hit_mismatch", f.primary_hit_mismatch},
                              {"primary_t_mismatch", f.primary_t_mismatch},
                              {"frontend_occluded_shadow_rays", f.fe_occluded},
                              {"embree_occluded_shadow_rays", f.em_occluded},
                              {"embree_refitted_occluded_shadow_rays", f.em_refit_occluded},
                              {"embree_refitted_primary_t_differs", f.refit_primary_diff}};
            s["frames"].push_back(x);
        }
        j["scenes"].push_back(s);
    }
    return j;
}

}  // namespace
}  // namespace raplas

int main(int argc, char** argv) {
    using namespace raplas;
    Options o;
    CLI::App app{"Per-frame host cost of animated scenes: sphere rebuild and the transform path against Embree 3's "
                 "BVH build and refit, and both tracers' time for the frame's rays"};
    app.add_option("--scene", o.scenes, "animated scenes to run: conference_orbit, bunny_turn, wave (repeatable)")
        ->capture_default_str();
    app.add_option("--width", o.width, "image width")->capture_default_str()->check(CLI::Range(1, 4096));
    app.add_option("--height", o.height, "image height")->capture_default_str()->check(CLI::Range(1, 4096));
    app.add_option("--frames", o.frames, "frames per scene, spread evenly over its animation (frame i F / N)")
        ->capture_default_str()
        ->check(CLI::Range(1, kMaxFrames));
    app.add_option("--threads", o.threads, "threads for everything timed (sphere builds, front end, Embree)")
        ->capture_default_str()
        ->check(CLI::Range(1, 1024));
    app.add_option("--repeat", o.repeat, "sphere builds, Embree builds and Embree traces: best of this many runs")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    app.add_option("--shadow-size", o.shadow_size, "shadow groups N x N (0: the scene file's)")
        ->capture_default_str()
        ->check(CLI::Range(0, 64));
    app.add_flag("!--no-hit-check", o.hit_check,
                 "skip tracing the primary rays with the transformed spheres (the 'primary hits differ' column)");
    app.add_option("--images", o.images, "write each frame's image to DIR/SCENE_FRAME.ppm");
    app.add_option("--json", o.json, "write every number as JSON");
    app.add_option("--shared", o.shared, "shared scenes folder")->capture_default_str();
    app.add_option("--scene-dir", o.scene_dir, "the animated scene files (NAME.toml)")->capture_default_str();
    CLI11_PARSE(app, argc, argv);

    std::string command;
    for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(i ? argv[i] : "raplas_bench_animation");

    try {
        for (const auto& name : o.scenes)
            if (std::find(kScenes.begin(), kScenes.end(), name) == kScenes.end()) {
                std::cerr << "raplas_bench_animation: unknown scene '" << name << "' (conference_orbit, bunny_turn, wave)\n";
                return 2;
            }
        // Scene files name meshes relative to the shared scenes folder.
        std::string path = o.shared;
        if (const char* env = std::getenv("RAPLAS_SCENE_PATH")) path += std::string(":") + env;
        setenv("RAPLAS_SCENE_PATH", path.c_str(), 1);
        if (!o.images.empty()) fs::create_directories(o.images);

        const std::string load_before = load_average();
        std::vector<SceneResult> results;
        for (const auto& name : o.scenes) results.push_back(run_scene(name, o));
        const std::string load_after = load_average();
        print_markdown(results, command, load_before, load_after);
        if (!o.json.empty()) {
            std::ofstream out(o.json);
            out << to_json(results, command, load_before, load_after).dump(2) << "\n";
            if (!out) throw std::runtime_error("cannot write " + o.json);
        }
    } catch (const std::exception& e) {
        std::cerr << "raplas_bench_animation: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
