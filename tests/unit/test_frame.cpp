// Scene-dependent skips of the front end change the work, never the image.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "raplas/frontend/frame.hpp"
#include "raplas/scene/mesh.hpp"
#include "raplas/scene/scene.hpp"
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
