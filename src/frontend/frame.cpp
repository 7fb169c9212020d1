#include "raplas/frontend/frame.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <mutex>

#include "raplas/frontend/group_source.hpp"
#include "raplas/util/bytes.hpp"
#include "raplas/util/parallel.hpp"

namespace raplas {

namespace {

// Hands FrameOptions::progress the groups finished by the worker threads: a
// call every 1/200 of the phase, one at a time, `done` never going back.
class GroupProgress {
public:
    GroupProgress(const FrameOptions& opt, const char* phase, std::size_t total)
        : fn_(opt.progress), phase_(phase), total_(total), step_(std::max<std::size_t>(1, total / 200)) {
        if (fn_) fn_(phase_, 0, total_);
    }
    void one_done() {
        if (!fn_) return;
        const std::size_t d = done_.fetch_add(1) + 1;
        if (d % step_ != 0 && d != total_) return;
        std::lock_guard<std::mutex> lock(mutex_);
        if (d <= last_) return;
        last_ = d;
        fn_(phase_, d, total_);
    }

private:
    const std::function<void(const char*, std::size_t, std::size_t)>& fn_;
    const char* phase_;
    std::size_t total_, step_;
    std::atomic<std::size_t> done_{0};
    std::mutex mutex_;
    std::size_t last_ = 0;
};
// A streamed group's lists at their exact size (grown by push_back they may
// hold twice that): the window's memory is what docs/MEMORY.md counts.
TraceGroup fitted(TraceGroup g) {
    g.sphere_hits.shrink_to_fit();
    g.pairless.shrink_to_fit();
    g.hits.shrink_to_fit();
    return g;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

double scene_extent(const Scene& scene) {
    double e = 0;
    for (const auto& v : scene.mesh.vertices) e = std::max(e, max_abs(to_d(v)));
    e = std::max(e, max_abs(scene.camera.eye));
    e = std::max(e, max_abs(scene.light.corner));
    e = std::max(e, max_abs(scene.light.corner + scene.light.edge_u + scene.light.edge_v));
    return e;
}

Vec3f shadow_origin(const Scene& scene, const SphereSet& s, const Ray& r, const Hit& h) {
    const TriangleRec& tr = s.triangles[static_cast<std::size_t>(h.tri)];
    Vec3d d = to_d(r.d);
    Vec3d x = to_d(r.o) + d * h.t;
    Vec3d nrm = normalize(to_d(tr.n));
    if (dot(nrm, d) > 0) nrm = -nrm;
    const double diag = scene.diagonal > 0 ? scene.diagonal : length(scene.mesh.bounds().extent());
    return to_f(x + nrm * (scene.shadow_offset * diag));
}

bool faces_away_from_light(const Scene& scene, const SphereSet& s, const Ray& r, const Hit& h) {
    const TriangleRec& tr = s.triangles[static_cast<std::size_t>(h.tri)];
    Vec3d nrm = normalize(to_d(tr.n));
    if (dot(nrm, to_d(r.d)) > 0) nrm = -nrm;  // the side the primary ray came from
    const Vec3d o = to_d(shadow_origin(scene, s, r, h));
    const AreaLight& l = scene.light;
    const Vec3d corners[4] = {l.corner, l.corner + l.edge_u, l.corner + l.edge_v, l.corner + l.edge_u + l.edge_v};
    // Every light sample is a convex combination of the corners. The margin
    // (1e-5 of the farthest corner's distance) keeps the sample directions as
    // traced, rounded to float, strictly behind the surface: the shading's
    // cosine is negative for every one of them.
    double far = 0;
    for (const Vec3d& c : corners) far = std::max(far, length(c - o));
    for (const Vec3d& c : corners)
        if (!(dot(nrm, c - o) < -1e-5 * far)) return false;
    return true;
}

Frame render_frame(const Scene& scene, const FrameOptions& opt) {
    using clock = std::chrono::steady_clock;
    const unsigned threads = opt.threads ? opt.threads : default_threads();
    Frame f;
    f.width = scene.width;
    f.height = scene.height;
    const std::size_t npix = std::size_t(scene.width) * std::size_t(scene.height);

    auto t0 = clock::now();
    f.sphere_margin = conservative_margin(opt.format.unit_roundoff(), scene_extent(scene));
    SphereCache* const cache = opt.sphere_cache;
    const Mesh& m = scene.mesh;
    if (cache && cache->valid && cache->k == scene.tris_per_sphere && cache->method == scene.sphere_method &&
        same_bits(cache->margin, f.sphere_margin) && same_bytes(cache->vertices, m.vertices) &&
        same_bytes(cache->triangles, m.triangles)) {
        f.spheres = cache->spheres;
        ++cache->reused;
    } else {
        f.spheres = build_spheres(m, scene.tris_per_sphere, scene.sphere_method, f.sphere_margin, threads);
        if (cache) {
            cache->vertices = m.vertices;
            cache->triangles = m.triangles;
            cache->k = scene.tris_per_sphere;
            cache->method = scene.sphere_method;
            cache->margin = f.sphere_margin;
            cache->spheres = f.spheres;
            cache->valid = true;
            ++cache->built;
        }
    }
    Tracer tracer(f.spheres, opt.format, opt.cull, threads);
    f.times.spheres_s = seconds_since(t0);

    // Primary groups.
    t0 = clock::now();
    f.primary = primary_groups(scene);
    GroupStream* const stream = opt.stream;
    if (stream) stream->set_header(trace_header(scene, f, opt.format, opt.pairless));
    f.primary_results.resize(stream ? 0 : f.primary.size());
    f.pixel_ray.resize(npix);
    f.pixel_hit.assign(npix, Hit{});
    f.work_rt.assign(npix, 0);
    f.work_spheres.assign(npix, 0);
    std::vector<GroupCounts> primary_counts(f.primary.size());
    std::vector<std::size_t> primary_runs(f.primary.size());
    GroupProgress primary_progress(opt, "primary", f.primary.size());
    parallel_for(f.primary.size(), threads, [&](std::size_t i) {
        if (stream) stream->acquire(i);
        GroupResult local;
        GroupResult& res = stream ? local : f.primary_results[i];
        tracer.trace(f.primary[i], res, opt.record, opt.per_ray, opt.pairless);
        // Each group writes its own pixels.
        const RayGroup& g = f.primary[i];
        for (std::uint32_t v = 0; v < g.n; ++v) {
            for (std::uint32_t h = 0; h < g.n; ++h) {
                if (!g.ray_valid(h, v)) continue;
                std::size_t px = std::size_t(g.py + int(v)) * std::size_t(scene.width) + std::size_t(g.px + int(h));
                f.pixel_ray[px] = group_ray(g, h, v);
                f.pixel_hit[px] = res.hits[v * g.n + h];
                if (opt.per_ray) {
                    f.work_rt[px] += res.ray_rt_tests[v * g.n + h];
                    f.work_spheres[px] += res.ray_sphere_hits[v * g.n + h];
                }
            }
        }
        primary_counts[i] = res.counts;
        primary_runs[i] = res.pairless.size();
        if (stream) stream->put(i, fitted(trace_group(std::move(f.primary[i]), std::move(local), opt.pairless)));
        primary_progress.one_done();
    });
    for (std::size_t i = 0; i < f.primary.size(); ++i) {
        f.primary_counts += primary_counts[i];
        f.primary_pairless_runs += primary_runs[i];
    }
    if (!opt.record) f.primary_results.clear();
    f.times.primary_s = seconds_since(t0);

    // Shadow groups: one per pixel whose primary ray hits, in pixel order
    // (pixels that hit nothing need none), except, when asked, for hit points
    // that face away from the whole light: no sample can light them.
    t0 = clock::now();
    f.visibility.assign(npix, -1.0f);
    std::vector<std::size_t> lit_pixels;
    for (std::size_t px = 0; px < npix; ++px) {
        if (f.pixel_hit[px].tri < 0) continue;
        if (scene.skip_facing_away && faces_away_from_light(scene, f.spheres, f.pixel_ray[px], f.pixel_hit[px])) {
            f.visibility[px] = 0.0f;
            ++f.facing_away;
            continue;
        }
        lit_pixels.push_back(px);
    }
    f.shadow_group_count = lit_pixels.size();
    if (opt.before_shadow) {
        ShadowSample sample;
        if (opt.record && !lit_pixels.empty()) {
            const std::size_t k = std::min<std::size_t>(32, std::max<std::size_t>(1, lit_pixels.size() / 100));
            std::uint64_t hits = 0, runs = 0, pairless = 0;
            for (std::size_t j = 0; j < k; ++j) {
                const std::size_t px = lit_pixels[j * lit_pixels.size() / k];
                const int x = int(px % std::size_t(scene.width)), y = int(px / std::size_t(scene.width));
                GroupResult res;
                tracer.trace(shadow_group(scene, shadow_origin(scene, f.spheres, f.pixel_ray[px], f.pixel_hit[px]), x, y),
                             res, opt.pairless, false, opt.pairless);
                hits += res.counts.sphere_hits;
                runs += res.pairless.size();
                pairless += res.counts.pairless;
            }
            sample.sphere_hits = double(hits) / double(k);
            sample.pairless_runs = double(runs) / double(k);
            sample.pairless_spheres = double(pairless) / double(k);
        }
        opt.before_shadow(f, lit_pixels.size(), sample);
    }
    if (stream) stream->set_total(f.primary.size() + lit_pixels.size());
    std::vector<std::uint8_t> read;
    if (stream && opt.groups_read) read = opt.groups_read(f.primary.size(), f.primary.size() + lit_pixels.size());
    const bool keep_shadow = opt.record && !stream;
    std::vector<RayGroup> shadow(keep_shadow ? lit_pixels.size() : 0);
    std::vector<GroupResult> shadow_res(keep_shadow ? lit_pixels.size() : 0);
    std::vector<GroupCounts> counts(lit_pixels.size());
    std::vector<float> direct(npix, 0.0f);
    const Vec3d light_n = scene.light.normal();
    GroupProgress shadow_progress(opt, "shadow", lit_pixels.size());
    parallel_for(lit_pixels.size(), threads, [&](std::size_t i) {
        if (stream) stream->acquire(f.primary.size() + i);
        if (!read.empty() && !read.at(f.primary.size() + i)) {
            TraceGroup placeholder;
            placeholder.kind = GroupKind::shadow;
            stream->put(f.primary.size() + i, std::move(placeholder));
            shadow_progress.one_done();
            return;
        }
        const std::size_t px = lit_pixels[i];
        const int x = int(px % std::size_t(scene.width)), y = int(px / std::size_t(scene.width));
        RayGroup g = shadow_group(scene, shadow_origin(scene, f.spheres, f.pixel_ray[px], f.pixel_hit[px]), x, y);
        GroupResult res;
        tracer.trace(g, res, opt.record, false, opt.pairless);
        counts[i] = res.counts;
        // shading terms
        const Ray& pr = f.pixel_ray[px];
        const TriangleRec& tr = f.spheres.triangles[static_cast<std::size_t>(f.pixel_hit[px].tri)];
        Vec3d nrm = normalize(to_d(tr.n));
        if (dot(nrm, to_d(pr.d)) > 0) nrm = -nrm;
        std::uint32_t unoccluded = 0;
        double sum_cos = 0;
        for (std::uint32_t v = 0; v < g.n; ++v) {
            for (std::uint32_t h = 0; h < g.n; ++h) {
                if (res.hits[v * g.n + h].tri >= 0) continue;
                ++unoccluded;
                Vec3d w = normalize(to_d(group_ray(g, h, v).d));
                double cs = dot(nrm, w);
                if (cs > 0 && dot(light_n, -w) > 0) sum_cos += cs;
            }
        }
        const double samples = double(g.n) * g.n;
        f.visibility[px] = float(unoccluded / samples);
        direct[px] = float(sum_cos / samples);
        if (opt.per_ray) {
            f.work_rt[px] += res.counts.rt_tests;
            f.work_spheres[px] += res.counts.sphere_hits;
        }
        if (stream) {
            stream->put(f.primary.size() + i, fitted(trace_group(std::move(g), std::move(res), opt.pairless)));
        } else if (keep_shadow) {
            shadow[i] = std::move(g);
            res.hits.shrink_to_fit();
            shadow_res[i] = std::move(res);
        }
        shadow_progress.one_done();
    });
    for (const auto& c : counts) f.shadow_counts += c;
    if (keep_shadow) {
        f.shadow = std::move(shadow);
        f.shadow_results = std::move(shadow_res);
    }
    f.times.shadow_s = seconds_since(t0);

    // Lambert shading.
    t0 = clock::now();
    f.rgb.assign(npix * 3, 0.0f);
    for (std::size_t px = 0; px < npix; ++px) {
        float* out = &f.rgb[px * 3];
        if (f.pixel_hit[px].tri < 0) {
            out[0] = 0.05f; out[1] = 0.05f; out[2] = 0.07f;
            continue;
        }
        std::size_t mesh_tri = static_cast<std::size_t>(f.spheres.tri_mesh_index[static_cast<std::size_t>(f.pixel_hit[px].tri)]);
        const Material& m = scene.mesh.materials[static_cast<std::size_t>(scene.mesh.triangle_material[mesh_tri])];
        for (int c = 0; c < 3; ++c) {
            double kd = m.diffuse[static_cast<std::size_t>(c)];
            double e = m.emission[static_cast<std::size_t>(c)];
            double lit = scene.ambient + (1.0 - scene.ambient) * scene.light.emission[static_cast<std::size_t>(c)] * direct[px];
            out[c] = float(kd * lit + e);
        }
    }
    f.times.shade_s = seconds_since(t0);
    return f;
}

}  // namespace raplas
