// What the benchmarks share: the shared scenes' folder, wall time, the
// machine they ran on and number formatting.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "raplas/frontend/frame.hpp"
#include "raplas/frontend/raygroups.hpp"
#include "raplas/util/parallel.hpp"

#ifndef RAPLAS_SHARED_SCENES
#define RAPLAS_SHARED_SCENES "../shared/scenes"
#endif
#ifndef RAPLAS_SOURCE_DIR
#define RAPLAS_SOURCE_DIR "."
#endif

namespace raplas::bench {

using clock_type = std::chrono::steady_clock;

inline double since(clock_type::time_point t0) { return std::chrono::duration<double>(clock_type::now() - t0).count(); }

// The CPU's model name (/proc/cpuinfo), "unknown" when not there.
inline std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("model name", 0) == 0) {
            auto colon = line.find(':');
            if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
        }
    }
    return "unknown";
}

// The 1-minute load average (/proc/loadavg), two decimals.
inline std::string load_average() {
    std::ifstream in("/proc/loadavg");
    double one = -1;
    in >> one;
    if (!in) return "unknown";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", one);
    return buf;
}

// The machine a benchmark ran on, for its --json: threads, CPU and the load
// average before and after the run.
inline nlohmann::json machine_json(const std::string& load_before, const std::string& load_after) {
    return {{"hardware_threads", std::thread::hardware_concurrency()},
            {"cpu", cpu_model()},
            {"load_average_before", load_before},
            {"load_average_after", load_after}};
}

// 1234567 as "1,234,567".
inline std::string fmt_count(std::uint64_t n) {
    std::string s = std::to_string(n);
    for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(std::size_t(i), ",");
    return s;
}

// The shadow rays a frame's front end traced, in its groups' order: one
// group per pixel whose primary ray hits (what render_frame builds), and how
// many of them the front end found occluded.
struct ShadowRays {
    std::vector<Ray> rays;
    std::uint64_t occluded = 0;
};
inline ShadowRays frame_shadow_rays(const Scene& scene, const Frame& f, unsigned threads) {
    std::vector<std::size_t> lit;
    for (std::size_t px = 0; px < f.pixel_hit.size(); ++px)
        if (f.pixel_hit[px].tri >= 0) lit.push_back(px);
    const std::size_t per_group = std::size_t(scene.shadow_group_size) * std::size_t(scene.shadow_group_size);
    ShadowRays s;
    s.rays.resize(lit.size() * per_group);
    parallel_for(lit.size(), threads, [&](std::size_t i) {
        const std::size_t px = lit[i];
        const int x = int(px % std::size_t(scene.width)), y = int(px / std::size_t(scene.width));
        const RayGroup g = shadow_group(scene, shadow_origin(scene, f.spheres, f.pixel_ray[px], f.pixel_hit[px]), x, y);
        for (std::uint32_t v = 0; v < g.n; ++v)
            for (std::uint32_t h = 0; h < g.n; ++h) s.rays[i * per_group + v * g.n + h] = group_ray(g, h, v);
    });
    for (std::size_t px : lit) s.occluded += std::uint64_t(std::llround((1.0 - double(f.visibility[px])) * double(per_group)));
    return s;
}

// Primary rays on which the front end and another tracer (`t`: distance of
// the nearest hit, negative for a miss) disagree: in hit or miss, or in the
// distance by more than 1e-4 relative.
struct PrimaryMismatch {
    std::size_t hit = 0, distance = 0;
};
inline PrimaryMismatch compare_primary(const Frame& f, const std::vector<float>& t) {
    PrimaryMismatch m;
    for (std::size_t px = 0; px < t.size(); ++px) {
        const bool fh = f.pixel_hit[px].tri >= 0, eh = t[px] >= 0;
        if (fh != eh) {
            ++m.hit;
        } else if (fh) {
            const double a = f.pixel_hit[px].t, b = t[px];
            if (std::fabs(a - b) > 1e-4 * std::max(std::fabs(a), std::fabs(b))) ++m.distance;
        }
    }
    return m;
}

}  // namespace raplas::bench
