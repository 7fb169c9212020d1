// The RAPLAS front end against Embree 3: every primary ray of a frame and a
// sample of its shadow rays are traced again by Embree over the same mesh, and
// the answers (hit or miss, distance along the ray, occlusion) must agree.
#include <embree3/rtcore.h>

#include "embree_rays.hpp"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "raplas/frontend/frame.hpp"
#include "raplas/scene/scene.hpp"
#include "shared_scenes.hpp"

#ifndef RAPLAS_SOURCE_DIR
#define RAPLAS_SOURCE_DIR "."
#endif

namespace raplas {
namespace {

namespace fs = std::filesystem;

constexpr double kPrimaryAgreement = 0.9999;
constexpr double kShadowAgreement = 0.999;
constexpr double kRelTolerance = 1e-4;
constexpr std::size_t kMaxShadowGroups = 1024;  // sample size per frame
constexpr std::size_t kMaxSceneFileTriangles = 100000;

const std::string kShared = RAPLAS_SHARED_SCENES;

// Embree scene over a mesh, triangles in mesh order (primID = mesh triangle index).
class EmbreeScene {
public:
    explicit EmbreeScene(const Mesh& mesh) {
        device_ = rtcNewDevice(nullptr);
        if (!device_) throw std::runtime_error("rtcNewDevice failed");
        scene_ = rtcNewScene(device_);
        rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
        RTCGeometry geom = new_embree_mesh(device_, mesh);
        rtcCommitGeometry(geom);
        rtcAttachGeometry(scene_, geom);
        rtcReleaseGeometry(geom);
        rtcCommitScene(scene_);
        if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error("Embree scene build failed");
    }
    ~EmbreeScene() {
        if (scene_) rtcReleaseScene(scene_);
        if (device_) rtcReleaseDevice(device_);
    }
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    bool backface_culling() const {
        return rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED) != 0;
    }

    struct Result {
        bool hit = false;
        float t = 0;
        unsigned prim = 0;
    };

    // Nearest hit along o + t*d, t in (0, tfar].
    Result intersect(const Ray& r, float tfar = std::numeric_limits<float>::infinity()) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRayHit rh;
        set_embree_ray(rh.ray, r, tfar);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene_, &ctx, &rh);
        Result res;
        if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
            res.hit = true;
            res.t = rh.ray.tfar;
            res.prim = rh.hit.primID;
        }
        return res;
    }

    // Any hit along o + t*d, t in (0, r.tmax].
    bool occluded(const Ray& r) const { return embree_occluded(scene_, r); }

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
};

struct PrimaryStats {
    std::size_t rays = 0, both_hit = 0, both_miss = 0, only_raplas = 0, only_embree = 0, t_differs = 0;
    std::size_t same_triangle = 0;
    double max_rel_dt = 0;  // over rays both hit
    std::vector<std::string> examples;

    std::size_t disagreements() const { return only_raplas + only_embree + t_differs; }
    double agreement() const { return rays ? 1.0 - double(disagreements()) / double(rays) : 0.0; }
};

// A shadow ray whose only occluder lies within kRelTolerance of either end of
// the ray (t in units of the distance to the light sample) is a tie: the
// origin sits on a surface (a concave corner) or the occluder touches the
// light, and which side of 0 the rounded distance falls on is arbitrary.
struct ShadowStats {
    std::size_t groups = 0, rays = 0, both_occluded = 0, both_free = 0, only_raplas = 0, only_embree = 0;
    std::size_t ties = 0;
    std::size_t visibility_mismatch = 0;  // sampled pixels whose frame.visibility disagrees with the group's hits
    std::vector<std::string> examples;

    std::size_t disagreements() const { return only_raplas + only_embree; }
    double agreement() const { return rays ? 1.0 - double(disagreements()) / double(rays) : 0.0; }
};

double rel_diff(double a, double b) {
    const double m = std::max(std::fabs(a), std::fabs(b));
    return m > 0 ? std::fabs(a - b) / m : 0.0;
}

PrimaryStats compare_primary(const Frame& f, const EmbreeScene& ref) {
    PrimaryStats s;
    for (std::size_t px = 0; px < f.pixel_ray.size(); ++px) {
        const Ray& r = f.pixel_ray[px];
        const Hit& h = f.pixel_hit[px];
        const EmbreeScene::Result e = ref.intersect(r);
        ++s.rays;
        const bool rh = h.tri >= 0;
        std::string problem;
        if (rh && e.hit) {
            ++s.both_hit;
            const double d = rel_diff(h.t, e.t);
            s.max_rel_dt = std::max(s.max_rel_dt, d);
            const auto mesh_tri = f.spheres.tri_mesh_index[static_cast<std::size_t>(h.tri)];
            if (mesh_tri == static_cast<std::int32_t>(e.prim)) ++s.same_triangle;
            if (d > kRelTolerance) {
                ++s.t_differs;
                problem = "t differs";
            }
        } else if (!rh && !e.hit) {
            ++s.both_miss;
        } else if (rh) {
            ++s.only_raplas;
            problem = "only RAPLAS hits";
        } else {
            ++s.only_embree;
            problem = "only Embree hits";
        }
        if (!problem.empty() && s.examples.size() < 5) {
            std::ostringstream os;
            os.precision(9);
            os << "pixel (" << px % std::size_t(f.width) << ", " << px / std::size_t(f.width) << "): " << problem
               << "; RAPLAS tri " << (rh ? f.spheres.tri_mesh_index[static_cast<std::size_t>(h.tri)] : -1)
               << " t " << h.t << ", Embree tri " << (e.hit ? static_cast<long>(e.prim) : -1L) << " t " << e.t;
            s.examples.push_back(os.str());
        }
    }
    return s;
}

// Compares every ray of a sample of the frame's recorded shadow groups.
ShadowStats compare_shadow(const Frame& f, const EmbreeScene& ref) {
    ShadowStats s;
    const std::size_t n = f.shadow.size();
    const std::size_t stride = std::max<std::size_t>(1, (n + kMaxShadowGroups - 1) / kMaxShadowGroups);
    for (std::size_t i = 0; i < n; i += stride) {
        const RayGroup& g = f.shadow[i];
        const GroupResult& res = f.shadow_results[i];
        ++s.groups;
        std::size_t free_rays = 0;
        for (std::uint32_t v = 0; v < g.n; ++v) {
            for (std::uint32_t h = 0; h < g.n; ++h) {
                const Ray r = group_ray(g, h, v);
                const Hit& rh = res.hits[std::size_t(v) * g.n + h];
                const bool ro = rh.tri >= 0;
                const bool eo = ref.occluded(r);
                ++s.rays;
                if (!ro) ++free_rays;
                if (ro == eo) {
                    ++(ro ? s.both_occluded : s.both_free);
                    continue;
                }
                const double t = ro ? rh.t : double(ref.intersect(r, r.tmax).t);
                if (t < kRelTolerance || t > double(r.tmax) - kRelTolerance) {
                    ++s.ties;
                    continue;
                }
                ++(ro ? s.only_raplas : s.only_embree);
                if (s.examples.size() < 5) {
                    std::ostringstream os;
                    os.precision(9);
                    os << "shadow group of pixel (" << g.px << ", " << g.py << ") ray (" << h << ", " << v
                       << "): RAPLAS " << (ro ? "occluded" : "free") << ", Embree " << (eo ? "occluded" : "free")
                       << ", occluder at t " << t;
                    s.examples.push_back(os.str());
                }
            }
        }
        const std::size_t px = std::size_t(g.py) * std::size_t(f.width) + std::size_t(g.px);
        const float vis = float(double(free_rays) / (double(g.n) * g.n));
        if (f.visibility[px] != vis) ++s.visibility_mismatch;
    }
    return s;
}

struct Case {
    std::string name;
    std::string mesh;  // relative to the shared scenes folder
    int width = 128, height = 128;
    std::vector<std::string> overrides;
};

std::ostream& operator<<(std::ostream& os, const Case& c) { return os << c.name; }

std::string percent(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4f %%", 100.0 * x);
    return buf;
}

// Renders the scene with the front end, traces the same rays with Embree,
// prints the agreement and checks it against the thresholds.
void check_scene(const Scene& scene, const std::string& label) {
    FrameOptions fo;
    fo.record = true;
    const Frame f = render_frame(scene, fo);
    const EmbreeScene ref(scene.mesh);
    ASSERT_FALSE(ref.backface_culling()) << "Embree was built with back-face culling; RAPLAS tests both sides";

    const PrimaryStats p = compare_primary(f, ref);
    const ShadowStats s = compare_shadow(f, ref);

    std::printf("[ agreement ] %s (%zu triangles, %dx%d)\n", label.c_str(), scene.mesh.triangle_count(), f.width,
                f.height);
    std::printf("              primary: %s of %zu rays (hit/hit %zu, miss/miss %zu, only RAPLAS %zu, only Embree %zu, "
                "t differs %zu; same triangle %.3f %%; max rel dt %.2e)\n",
                percent(p.agreement()).c_str(), p.rays, p.both_hit, p.both_miss, p.only_raplas, p.only_embree,
                p.t_differs, p.both_hit ? 100.0 * double(p.same_triangle) / double(p.both_hit) : 0.0, p.max_rel_dt);
    std::printf("              shadow:  %s of %zu rays in %zu of %zu groups (occluded/occluded %zu, free/free %zu, "
                "only RAPLAS %zu, only Embree %zu, ties at t~0 or t~1 %zu)\n",
                percent(s.agreement()).c_str(), s.rays, s.groups, f.shadow.size(), s.both_occluded, s.both_free,
                s.only_raplas, s.only_embree, s.ties);
    for (const auto& e : p.examples) std::printf("              %s\n", e.c_str());
    for (const auto& e : s.examples) std::printf("              %s\n", e.c_str());
    ::testing::Test::RecordProperty("primary_agreement", percent(p.agreement()));
    ::testing::Test::RecordProperty("shadow_agreement", percent(s.agreement()));

    ASSERT_EQ(p.rays, std::size_t(scene.width) * std::size_t(scene.height));
    // The comparison means something only if the frame has hits and misses.
    EXPECT_GT(p.both_hit, p.rays / 20) << "too few primary hits: the camera does not see the mesh";
    EXPECT_GE(p.agreement(), kPrimaryAgreement) << p.disagreements() << " primary rays disagree";
    EXPECT_EQ(f.shadow.size(), f.shadow_group_count);
    EXPECT_GT(s.rays, 10000u);
    EXPECT_GE(s.agreement(), kShadowAgreement) << s.disagreements() << " shadow rays disagree";
    EXPECT_LE(s.ties, s.rays / 100) << "too many shadow rays with an occluder at the ends of the ray";
    EXPECT_EQ(s.visibility_mismatch, 0u) << "frame.visibility differs from the recorded shadow hits";
}

Scene make_scene(const Case& c) {
    ParamSet p = scene_params();
    p.set("image.width=" + std::to_string(c.width));
    p.set("image.height=" + std::to_string(c.height));
    for (const auto& o : c.overrides) p.set(o);
    return scene_from_params(p, kShared + "/" + c.mesh);
}

class EmbreeAgreement : public ::testing::TestWithParam<Case> {};

TEST_P(EmbreeAgreement, PrimaryAndShadowRays) {
    const Case& c = GetParam();
    RAPLAS_NEED_SHARED(kShared + "/" + c.mesh);
    const Scene scene = make_scene(c);
    check_scene(scene, c.name + " [" + c.mesh + "]");
}

const std::vector<Case> kCases = {
    {"bunny_res4", "bunny/bun_zipper_res4.obj", 128, 128, {}},
    // A floor gives the shadow rays something to be blocked by.
    {"bunny_res4_floor", "bunny/bun_zipper_res4.obj", 128, 128, {"floor=true"}},
    {"bunny", "bunny/bun_zipper.obj", 128, 128, {}},
    {"teapot", "teapot/teapot.obj", 128, 128, {}},
    {"cornell_auto", "cornell/cornell_box.obj", 128, 128, {}},
    // Looking into the open side, area light just under the ceiling's light quad.
    {"cornell_inside",
     "cornell/cornell_box.obj",
     128,
     128,
     {"camera.eye=[278, 273, -800]", "camera.look_at=[278, 273, 0]", "light.corner=[213, 547, 227]",
      "light.edge_u=[130, 0, 0]", "light.edge_v=[0, 0, 105]"}},
    // Image not a multiple of the group size: partial tiles.
    {"cornell_original_inside",
     "cornell/CornellBox-Original.obj",
     200,
     150,
     {"camera.eye=[0, 1, 3.5]", "camera.look_at=[0, 1, 0]", "light.corner=[-0.24, 1.97, -0.22]",
      "light.edge_u=[0.47, 0, 0]", "light.edge_v=[0, 0, 0.38]"}},
};

INSTANTIATE_TEST_SUITE_P(SharedScenes, EmbreeAgreement, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

// Every scene file of the project, at the file's own image size (at most
// 128 x 128; 64 x 64 above kMaxSceneFileTriangles triangles, to keep the
// test fast: the conference).
std::vector<std::string> scene_files() {
    std::vector<std::string> names;
    const fs::path dir = fs::path(RAPLAS_SOURCE_DIR) / "scenes";
    if (fs::is_directory(dir))
        for (const auto& e : fs::directory_iterator(dir))
            if (e.path().extension() == ".toml") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

class EmbreeAgreementSceneFile : public ::testing::TestWithParam<std::string> {};

TEST_P(EmbreeAgreementSceneFile, PrimaryAndShadowRays) {
    const std::string file = (fs::path(RAPLAS_SOURCE_DIR) / "scenes" / (GetParam() + ".toml")).string();
    ParamSet p = scene_params();
    p.load_file(file);
    RAPLAS_NEED_SHARED(kShared + "/" + p.get_string("mesh"));
    SceneRequest req;
    req.scene_file = file;
    Scene scene = load_scene(req);
    const int side = scene.mesh.triangle_count() > kMaxSceneFileTriangles ? 64 : 128;
    if (scene.width * scene.height > side * side) {
        req.overrides = {"image.width=" + std::to_string(side), "image.height=" + std::to_string(side)};
        scene = load_scene(req);
    }
    check_scene(scene, GetParam() + ".toml");
}

INSTANTIATE_TEST_SUITE_P(ShippedScenes, EmbreeAgreementSceneFile, ::testing::ValuesIn(scene_files()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace raplas
