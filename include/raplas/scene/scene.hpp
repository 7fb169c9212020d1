// A scene: a mesh plus camera, rectangular area light, image size and the
// RAPLAS grouping parameters. Scene files are TOML validated by ParamSet
// (docs/SCENES.md); anything not given is chosen automatically from the mesh.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "raplas/scene/mesh.hpp"
#include "raplas/util/params.hpp"

namespace raplas {

struct Camera {
    Vec3d eye, look_at, up{0, 1, 0};
    double fov_deg = 40;  // vertical field of view
};

// One-sided rectangle: points corner + a*edge_u + b*edge_v, a,b in [0,1];
// it emits toward edge_u x edge_v.
struct AreaLight {
    Vec3d corner, edge_u, edge_v;
    Vec3d emission{1, 1, 1};
    Vec3d normal() const { return normalize(cross(edge_u, edge_v)); }
    Vec3d center() const { return corner + edge_u * 0.5 + edge_v * 0.5; }
};

struct Animation;  // raplas/scene/animation.hpp

struct Scene {
    std::string name;
    Mesh mesh;
    Camera camera;
    AreaLight light;
    bool camera_auto = false, light_auto = false;
    // Automatic framing from inside the mesh (camera.auto), and what it chose and why.
    bool camera_inside = false;
    std::string camera_note;
    int width = 64, height = 64;
    int group_size = 16;         // N: primary ray groups are N x N pixel tiles
    int shadow_group_size = 16;  // shadow ray groups: an N x N grid on the light
    int tris_per_sphere = 2;     // K: triangles per bounding sphere (at most)
    std::string sphere_method = "median-split";
    double ambient = 0.15;
    double shadow_offset = 1e-4;  // shadow ray origin offset, fraction of the scene's diagonal
    bool skip_facing_away = false;  // no shadow group for hit points facing away from the whole light
    double diagonal = 0;          // of the mesh's bounding box (0: not computed yet)
    // The [animation] keys (scene_at_frame() makes one frame's scene); null
    // for a still scene. This scene is the still one: the keys outside
    // [animation], with frame 0's mesh of a deforming one.
    std::shared_ptr<const Animation> animation;
};

// Every scene key with its default, range and description.
ParamSet scene_params();

// The scene file `--scene NAME` means: NAME itself when it is a file, else
// scenes/NAME[.toml] in the working directory, then in the installed data
// folder or the source tree (raplas/util/data_dir.hpp). InputError when none
// is, listing the shipped scenes and the nearest names.
std::string find_scene_file(const std::string& name);
// InputError when the file given to --mesh is plainly a scene file (a .toml).
void check_mesh_option(const std::string& path);

// Where relative mesh paths are looked up after the scene file's directory:
// the working directory, $RAPLAS_SCENE_PATH (colon-separated),
// ./../shared/scenes, <scene dir>/../../shared/scenes and the source tree's
// ../shared/scenes.
std::vector<std::string> scene_search_path(const std::string& scene_dir);
std::string resolve_mesh_path(const std::string& mesh, const std::string& scene_dir);

struct SceneRequest {
    std::string scene_file;             // TOML scene file or a shipped scene's name, or empty
    std::string mesh_file;              // --mesh OBJ, or empty
    std::vector<std::string> overrides;  // --set key=value on scene keys
};

// Loads the request: no scene and no mesh gives the built-in procedural
// scene. Throws InputError on bad input.
Scene load_scene(const SceneRequest& req);
// Writes what the scene chose by itself into `p` (camera, light, the mesh
// given with --mesh, the name, the animation's resolved values), so that
// p.dump() is a scene file that gives the same scene.
void resolve_scene_params(ParamSet& p, const Scene& s, const std::string& mesh_override);
// Same, from a ParamSet already loaded and overridden.
Scene scene_from_params(const ParamSet& p, const std::string& mesh_override);

// The mesh files a scene's parameters resolve to (the --mesh file, the
// scene's mesh, every file of its mesh sequence), as they are found when the
// scene is loaded; none for the built-in scene. What a result records and
// a run must never write over.
std::vector<std::string> scene_mesh_files(const ParamSet& p, const std::string& mesh_override);

// Automatic framing and lighting from the mesh bounds.
// (Framing uses the bounds of the mesh as loaded, before any floor is added.)
// The camera of a scene that gives none: looking at the centre of the first
// `triangles` triangles of `m` (the mesh without the floor) from above and to
// the side, at the smallest distance that keeps each of their corners in the
// view of `fov_deg` (vertical) and `aspect` (width / height).
Camera auto_camera(const Mesh& m, std::size_t triangles, double fov_deg, double aspect);
AreaLight auto_light(const Aabb& bounds);
// Whether a mesh (its first `triangles` triangles) is an interior: from the
// centre of its bounding box, at least 90 % of 128 rays spread over the
// sphere meet a surface whose winding normal faces them, and the volume its
// winding encloses is negative (its surfaces, summed, face inward: walls
// modelled to be seen from inside; a closed object encloses a positive one).
struct InteriorTest {
    bool inside = false;
    double inward_fraction = 0;
    double volume = 0;  // signed, about the centre
};
InteriorTest interior_test(const Mesh& m, std::size_t triangles);
// The framing of an interior: the eye at the centre of the floor plan, 40 %
// up, looking along the farthest horizontal line of sight; the light under
// the ceiling above the eye, facing down.
Camera inside_camera(const Mesh& m, std::size_t triangles, double fov_deg);
AreaLight inside_light(const Mesh& m, std::size_t triangles, const Vec3d& eye);
// Appends a floor quad just below the mesh (scene key `floor`).
void add_floor(Mesh& m);

}  // namespace raplas
