// Accuracy of the intersectors' number formats against a reference format
// (float64), on one scene: every format renders the same frame through the
// RAPLAS front end, and its primary hits, shadow fractions and image are
// compared with the reference's. Wall time is the median of --repeat renders.
// Prints one Markdown table; --json writes every number (tools/accuracy.py
// collects them into docs/ACCURACY.md).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "raplas/frontend/frame.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/atomic_file.hpp"
#include "raplas/util/error.hpp"

namespace raplas {
namespace {

using clock_type = std::chrono::steady_clock;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Linear radiance -> 8-bit sRGB, as the PNG writer does.
int srgb8(float linear) {
    const double x = std::clamp(double(linear), 0.0, 1.0);
    const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return int(std::lround(s * 255.0));
}

struct Run {
    NumFormat format;
    Frame frame;
    std::vector<double> wall_s;
};

Run render(const Scene& scene, const NumFormat& f, int repeat, unsigned threads) {
    Run r;
    r.format = f;
    FrameOptions fo;
    fo.format = f;
    fo.threads = threads;
    for (int i = 0; i < repeat; ++i) {
        const auto t0 = clock_type::now();
        Frame fr = render_frame(scene, fo);
        r.wall_s.push_back(std::chrono::duration<double>(clock_type::now() - t0).count());
        if (i == 0) r.frame = std::move(fr);  // every render of a format is identical
    }
    return r;
}

nlohmann::json compare(const Run& ref, const Run& run) {
    const Frame& a = ref.frame;
    const Frame& b = run.frame;
    const std::size_t n = a.pixel_hit.size();
    auto mesh_tri = [](const Frame& f, std::size_t px) {
        const std::int32_t t = f.pixel_hit[px].tri;
        return t < 0 ? -1 : f.spheres.tri_mesh_index[std::size_t(t)];
    };
    std::size_t mismatched = 0, hit_vs_miss = 0, both_hit = 0, shadow_px = 0, shadow_differs = 0;
    double t_err_max = 0, t_err_sum = 0, vis_err_sum = 0, vis_err_max = 0;
    for (std::size_t px = 0; px < n; ++px) {
        const std::int32_t ta = mesh_tri(a, px), tb = mesh_tri(b, px);
        if (ta != tb) {
            ++mismatched;
            hit_vs_miss += (ta < 0) != (tb < 0);
        } else if (ta >= 0) {
            ++both_hit;
            const double e = std::fabs(b.pixel_hit[px].t - a.pixel_hit[px].t) / std::fabs(a.pixel_hit[px].t);
            t_err_max = std::max(t_err_max, e);
            t_err_sum += e;
        }
        if (a.visibility[px] >= 0 && b.visibility[px] >= 0) {
            ++shadow_px;
            const double e = std::fabs(double(b.visibility[px]) - double(a.visibility[px]));
            vis_err_sum += e;
            vis_err_max = std::max(vis_err_max, e);
            shadow_differs += e > 0;
        }
    }
    double se = 0;
    std::size_t channels_differ = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
        const int d = srgb8(a.rgb[i]) - srgb8(b.rgb[i]);
        se += double(d) * d;
        channels_differ += d != 0;
    }
    const double mse = se / double(a.rgb.size());
    nlohmann::json j;
    j["format"] = run.format.name();
    j["pixels"] = n;
    j["primary_mismatched"] = mismatched;
    j["primary_mismatch_rate"] = double(mismatched) / double(n);
    j["primary_hit_vs_miss"] = hit_vs_miss;
    j["t_rel_error_max"] = t_err_max;
    j["t_rel_error_mean"] = both_hit ? t_err_sum / double(both_hit) : 0.0;
    j["shadow_pixels"] = shadow_px;
    j["shadow_fraction_error_mean"] = shadow_px ? vis_err_sum / double(shadow_px) : 0.0;
    j["shadow_fraction_error_max"] = vis_err_max;
    j["shadow_pixels_differing"] = shadow_differs;
    j["image_mse"] = mse;
    // null when the images are identical (infinite PSNR)
    j["image_psnr_db"] = mse > 0 ? nlohmann::json(10 * std::log10(255.0 * 255.0 / mse)) : nlohmann::json(nullptr);
    j["image_channels_differing"] = channels_differ;
    j["wall_s"] = run.wall_s;
    j["wall_s_median"] = median(run.wall_s);
    const GroupCounts c = [&] {
        GroupCounts g = b.primary_counts;
        g += b.shadow_counts;
        return g;
    }();
    j["plane_sphere_tests"] = c.plane_tests;
    j["sphere_hits"] = c.sphere_hits;
    j["ray_triangle_tests"] = c.rt_tests;
    j["shadow_groups"] = b.shadow_group_count;
    return j;
}

int run_main(int argc, char** argv) {
    CLI::App app{"raplas_accuracy: number formats of the intersectors against a reference format, on one scene"};
    std::string scene_file, json_out, reference = "float64";
    std::vector<std::string> sets, formats;
    int repeat = 3;
    unsigned threads = 1;
    app.add_option("--scene", scene_file, "scene file (default: the built-in scene)");
    app.add_option("--set", sets, "override a scene key (repeatable)");
    app.add_option("--format", formats, "format to measure (repeatable)")->required();
    app.add_option("--reference", reference, "reference format")->capture_default_str();
    app.add_option("--repeat", repeat, "renders per format; wall time is their median")->capture_default_str()
        ->check(CLI::Range(1, 100));
    app.add_option("--threads", threads, "front-end threads per render")->capture_default_str();
    app.add_option("--json", json_out, "write every number as JSON");
    CLI11_PARSE(app, argc, argv);
    try {
        SceneRequest req;
        req.scene_file = scene_file;
        req.overrides = sets;
        const Scene scene = load_scene(req);
        auto parse = [](const std::string& s) {
            try {
                return NumFormat::parse(s);
            } catch (const std::invalid_argument& e) {
                throw InputError(std::string("--format: ") + e.what());
            }
        };
        const Run ref = render(scene, parse(reference), repeat, threads);
        nlohmann::json out;
        out["scene"] = scene.name;
        out["width"] = scene.width;
        out["height"] = scene.height;
        out["triangles"] = scene.mesh.triangle_count();
        out["reference"] = compare(ref, ref);
        out["repeat"] = repeat;
        out["threads"] = threads;
        std::printf("| %s | format | wall s (median of %d) | primary mismatch | shadow error (mean) | PSNR dB |\n",
                    scene.name.c_str(), repeat);
        std::printf("|---|---|---|---|---|---|\n");
        for (const std::string& fs : formats) {
            const Run r = render(scene, parse(fs), repeat, threads);
            nlohmann::json j = compare(ref, r);
            std::printf("| | %s | %.3f | %.5f | %.5f | %s |\n", r.format.name().c_str(), j["wall_s_median"].get<double>(),
                        j["primary_mismatch_rate"].get<double>(), j["shadow_fraction_error_mean"].get<double>(),
                        j["image_psnr_db"].is_null() ? "identical" : std::to_string(j["image_psnr_db"].get<double>()).c_str());
            std::fflush(stdout);
            out["formats"].push_back(j);
        }
        if (!json_out.empty()) write_file_atomically(json_out, out.dump(2) + "\n");
    } catch (const InputError& e) {
        std::cerr << "raplas_accuracy: error: " << e.what() << "\n";
        return 2;
    }
    return 0;
}

}  // namespace
}  // namespace raplas

int main(int argc, char** argv) { return raplas::run_main(argc, argv); }
