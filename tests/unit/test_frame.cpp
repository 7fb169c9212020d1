// Scene-dependent skips of the front end change the work, never the image.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "raplas/frontend/frame.hpp"
#include "raplas/scene/animation.hpp"
#include "raplas/scene/mesh.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/bytes.hpp"
#include "raplas/util/params.hpp"

namespace {

using namespace raplas;

Scene builtin_with(const std::vector<std::string>& sets) {
    ParamSet p = scene_params();
    p.set("image.width=40");
    p.set("image.height=32");
    p.set("groups.shadow_size=4");
    for (const auto& set : sets) p.set(set);
    return scene_from_params(p, "");
}

TEST(FrameSkips, HitPointsFacingAwayFromTheLightGetNoShadowGroupAndTheSameImage) {
    FrameOptions fo;
    fo.threads = 2;
    const std::vector<std::vector<std::string>> lights = {
        {}, {"light.corner=[-3.0, 0.2, 1.0]", "light.edge_u=[0.0, 0.5, 0.0]", "light.edge_v=[0.0, 0.0, 0.5]"}};
    for (const auto& light : lights) {
        Scene all = builtin_with(light), skip = builtin_with(light);
        skip.skip_facing_away = true;
        const Frame a = render_frame(all, fo), b = render_frame(skip, fo);
        std::size_t hits = 0, away = 0;
        for (std::size_t px = 0; px < a.pixel_hit.size(); ++px) {
            if (a.pixel_hit[px].tri < 0) continue;
            ++hits;
            if (faces_away_from_light(skip, b.spheres, b.pixel_ray[px], b.pixel_hit[px])) {
                ++away;
                EXPECT_EQ(b.visibility[px], 0.0f);
            } else {
                EXPECT_EQ(b.visibility[px], a.visibility[px]) << "pixel " << px;
            }
        }
        EXPECT_EQ(a.shadow_group_count, hits);  // one group per hit pixel, none for a miss
        EXPECT_GT(away, 0u) << "the scene has hit points facing away from the light";
        EXPECT_EQ(b.facing_away, away);
        EXPECT_EQ(b.shadow_group_count, hits - away);
        EXPECT_EQ(a.rgb, b.rgb) << "skipping changed the image";
        EXPECT_LT(b.shadow_counts.plane_tests, a.shadow_counts.plane_tests);
    }
}

}  // namespace


TEST(SphereCache, StaticGeometryBuildsItsSpheresOnceAndMovedGeometryAgainBitForBit) {
    // An orbit moves the camera only; the built-in animation also turns the box.
    for (const bool moving : {false, true}) {
        ParamSet p = scene_params();
        p.set("image.width=24");
        p.set("image.height=24");
        if (moving) {
            p.set("animation.builtin=default");
        } else {  // the eye stays within the geometry's extent, so the margin does too
            p.set("animation.frames=8");
            p.set("animation.orbit.radius=1.5");
            p.set("animation.orbit.eye_height=1");
        }
        const Scene base = scene_from_params(p, "");
        SphereCache cache;
        FrameOptions with;
        with.threads = 2;
        with.sphere_cache = &cache;
        FrameOptions without;
        without.threads = 1;
        for (int f = 0; f < 3; ++f) {
            const Scene s = scene_at_frame(base, f);
            const Frame a = render_frame(s, with), b = render_frame(s, without);
            EXPECT_TRUE(raplas::same_spheres(a.spheres, b.spheres)) << "frame " << f << (moving ? ", moving" : ", static");
            EXPECT_TRUE(same_bytes(a.rgb, b.rgb)) << "frame " << f;
        }
        EXPECT_EQ(cache.built, moving ? 3u : 1u);
        EXPECT_EQ(cache.reused, moving ? 0u : 2u);
    }
}
