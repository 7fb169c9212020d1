// One frame through the RAPLAS front end: bounding spheres, primary ray
// groups, one shadow group per pixel whose primary ray hits, Lambert shading
// with soft shadows (visible fraction of the light's samples).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <functional>
#include <vector>

#include "raplas/frontend/tracer.hpp"

namespace raplas {

struct Frame;
class GroupStream;

// What render_frame measured of a sample of the shadow groups before tracing
// them all (for the memory budget): mean sphere hits, pair-less runs and
// pair-less spheres per group.
struct ShadowSample {
    double sphere_hits = 0, pairless_runs = 0, pairless_spheres = 0;
};

// The bounding spheres of the last frame drawn with this cache and what they
// were built from. build_spheres() is a function of the mesh's vertex and
// index bytes, K, the method and the margin alone (not of the thread count),
// so a frame whose inputs are those bytes again takes a copy of the spheres
// instead of building them: the same Sphere and Triangle Memories, bit for
// bit. A sequence of frames of static geometry (an orbiting camera) builds
// its spheres once; a frame whose geometry or margin changed builds them.
struct SphereCache {
    std::vector<Vec3f> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    int k = 0;
    std::string method;
    double margin = 0;
    SphereSet spheres;
    bool valid = false;
    std::size_t reused = 0, built = 0;  // frames that took the copy, frames that built
};

struct FrameOptions {
    NumFormat format = NumFormat::float32();
    unsigned threads = 0;   // 0: all cores
    bool record = false;    // keep every group and its sphere-hit list (for the trace)
    bool per_ray = false;   // per-pixel work counts (heat map)
    bool cull = true;       // skip spheres a group provably misses (bit-identical results)
    // Also find (and, when recording, keep) each group's spheres cut by row
    // planes only or column planes only, as runs: what a Triangle Selector that
    // keeps every sphere any plane cuts needs (icc.triangle_select = any).
    bool pairless = false;
    // Called once the primary rays are traced and before the shadow rays, with
    // the frame so far, the number of pixels whose primary ray hits (one
    // shadow group each) and, when recording, the mean sphere hits and
    // pair-less runs of a sample of those shadow groups (up to 32, about 1 %,
    // traced twice); may throw to stop (the memory budget,
    // src/app/memory_checks.cpp).
    std::function<void(const Frame&, std::size_t lit_pixels, const ShadowSample& sample)> before_shadow;
    // Called as ray groups are traced, phase "primary" then "shadow": with 0
    // when a phase starts, then at most about 200 times a phase, one call at a
    // time, `done` increasing to `total`. For progress lines; never changes a
    // result.
    std::function<void(const char* phase, std::size_t done, std::size_t total)> progress;
    // With `record`: hand each group, with its records, to this stream as
    // it is traced instead of keeping it in the frame (the frame's group
    // lists stay empty): the trace's header once the spheres and the primary
    // groups are made, then every group in issue order, each traced only
    // once the stream has room for it (raplas/frontend/group_source.hpp).
    GroupStream* stream = nullptr;
    // With `stream`: which groups the stream's reader will read, asked once
    // the group count is known, with (primary groups, all groups); the
    // shadow groups it marks 0 are not traced but handed over as placeholders
    // (TraceGroup::n = 0), and their pixels stay unshaded. Empty: all.
    std::function<std::vector<std::uint8_t>(std::size_t primary, std::size_t total)> groups_read;
    // Frames of one sequence: the spheres of the previous frame, taken when
    // they are provably this frame's too (SphereCache).
    SphereCache* sphere_cache = nullptr;
};

struct PhaseTimes {
    double spheres_s = 0, primary_s = 0, shadow_s = 0, shade_s = 0;
};

struct Frame {
    int width = 0, height = 0;
    SphereSet spheres;
    double sphere_margin = 0;
    std::vector<RayGroup> primary;           // issue order
    std::vector<RayGroup> shadow;            // issue order (pixel order); kept when recording
    std::vector<GroupResult> primary_results;
    std::vector<GroupResult> shadow_results;  // kept when recording
    std::vector<Ray> pixel_ray;              // W*H primary rays as traced
    std::vector<Hit> pixel_hit;              // W*H nearest hits (tri = Triangle Memory index)
    std::vector<float> visibility;           // W*H: unoccluded fraction of light samples (-1: no hit; 0 also
                                             // for hit points facing away from the light when those are skipped)
    std::size_t facing_away = 0;             // hit points given no shadow group (Scene::skip_facing_away)
    std::vector<float> rgb;                  // W*H*3 linear radiance
    std::vector<std::uint64_t> work_rt;      // W*H ray-triangle tests (primary ray + its shadow group)
    std::vector<std::uint64_t> work_spheres;  // W*H sphere hits (same)
    std::uint64_t shadow_group_count = 0;
    GroupCounts primary_counts, shadow_counts;
    std::uint64_t primary_pairless_runs = 0;  // when recording with FrameOptions::pairless
    PhaseTimes times;
};

Frame render_frame(const Scene& scene, const FrameOptions& opt);

// Largest coordinate magnitude of geometry, eye and light: sets the margin.
double scene_extent(const Scene& scene);
// Shadow ray origin for a primary hit: the hit point, offset along the
// normal toward the side the primary ray came from.
Vec3f shadow_origin(const Scene& scene, const SphereSet& s, const Ray& r, const Hit& h);
// The hit point's surface (the side the ray came from) faces away from every
// point of the area light, with a margin: no shadow ray of it can light it.
bool faces_away_from_light(const Scene& scene, const SphereSet& s, const Ray& r, const Hit& h);

}  // namespace raplas
