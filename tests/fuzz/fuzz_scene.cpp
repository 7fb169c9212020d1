// fuzz_scene: scene files (ParamSet::load_text on scene_params(), then
// scene_from_params). The mesh and animation.mesh_sequence keys are forced to
// "" before the scene is built, so a built-in mesh is used and no file named by
// the input is ever opened.
// A scene that loads must be one the front end can render, and dump() must
// print TOML that reads back to the same values.
#include <cmath>
#include <string>

#include "fuzz_common.hpp"
#include "raplas/scene/scene.hpp"

namespace {

const char* const kTarget = "fuzz_scene";

bool finite(const raplas::Vec3d& v) { return raplas::all_finite(v); }

void check_scene(const raplas::Scene& s) {
    using raplas::fuzz::fail;
    if (s.mesh.triangles.empty()) fail(kTarget, "scene without triangles");
    if (s.width < 1 || s.height < 1 || s.group_size < 1 || s.shadow_group_size < 1 || s.tris_per_sphere < 1)
        fail(kTarget, "scene sizes out of range");
    const auto& c = s.camera;
    if (!finite(c.eye) || !finite(c.look_at) || !finite(c.up) || !std::isfinite(c.fov_deg))
        fail(kTarget, "non-finite camera");
    const raplas::Vec3d view = c.look_at - c.eye;
    const raplas::Vec3d right = raplas::cross(view, c.up);
    if (!finite(raplas::normalize(view)) || !finite(raplas::normalize(right)))
        fail(kTarget, "camera without a finite view basis");
    const auto& l = s.light;
    if (!finite(l.corner) || !finite(l.edge_u) || !finite(l.edge_v) || !finite(l.emission) || !finite(l.normal()))
        fail(kTarget, "light without a finite position or normal");
    if (!std::isfinite(s.diagonal) || !std::isfinite(s.ambient) || !std::isfinite(s.shadow_offset))
        fail(kTarget, "non-finite scene value");
}


}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
    const std::string text = raplas::fuzz::as_string(data, size);
    raplas::ParamSet p = raplas::scene_params();
    if (!raplas::fuzz::guarded(kTarget, [&] { p.load_text(text, "fuzz.toml"); })) return 0;
    p.set("mesh=\"\"");
    p.set("animation.mesh_sequence=\"\"");
    raplas::fuzz::check_dump(kTarget, p, raplas::scene_params());
    raplas::fuzz::guarded(kTarget, [&] { check_scene(raplas::scene_from_params(p, "")); });
    return 0;
}
