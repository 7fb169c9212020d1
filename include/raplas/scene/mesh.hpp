// Triangle mesh as loaded: vertices, triangles in file order after
// triangulation (this order defines the "mesh triangle index"), materials.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "raplas/core/vec.hpp"

namespace raplas {

struct Material {
    std::string name = "default";
    Vec3f diffuse{0.75f, 0.75f, 0.75f};
    Vec3f emission{0.f, 0.f, 0.f};
};

struct Mesh {
    std::vector<Vec3f> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::int32_t> triangle_material;  // index into materials, per triangle
    std::vector<Material> materials;              // never empty: [0] is the default
    // Per triangle, an index into object_names, or kAddedObject for geometry
    // added to the mesh as loaded (the floor); empty when not recorded.
    std::vector<std::int32_t> triangle_object;
    // The OBJ's object and group names (the last `o` or `g` line before a
    // face), in order of first use; "" for faces before any.
    std::vector<std::string> object_names;
    static constexpr std::int32_t kAddedObject = -1;
    std::string source;                           // file path, or "<builtin:NAME>"
    std::vector<std::string> warnings;            // one line each: what was read with a fallback (missing MTL)

    std::size_t triangle_count() const { return triangles.size(); }
    Aabb bounds() const;
    Vec3f corner(std::size_t tri, int k) const { return vertices[triangles[tri][static_cast<std::size_t>(k)]]; }
};

// Loads an OBJ (and its MTL when present): polygons are triangulated by
// tinyobjloader (a quad along its shorter diagonal, larger polygons by ear
// clipping), Kd is the diffuse colour, Ke the emission. Every problem
// (missing/empty file, non-finite coordinate, bad index, face with < 3
// vertices) throws InputError "FILE:LINE: ...".
Mesh load_obj(const std::string& path);
// Same, from OBJ text already read; `name` is used in messages and as
// Mesh::source, `mtl_dir` is where `mtllib` files are looked up ("" = MTL
// files are not read, every triangle gets the default material).
Mesh load_obj_text(const std::string& text, const std::string& name, const std::string& mtl_dir);

// Procedural default scene (no file needed): a floor, a back wall, a box and
// two tessellated spheres (objects "floor", "wall", "box", "big_sphere",
// "small_sphere"). `detail` scales the sphere tessellation.
Mesh builtin_mesh(int detail = 3);
// Procedural deforming mesh: a square grid of 4 * 2^detail cells a side over
// x, z in [-2, 2] (object "wave"), its heights a travelling wave at `phase`
// (radians; one period is 2 pi). Every phase gives the same vertices and
// triangles in the same order.
Mesh wave_mesh(int detail, double phase);

}  // namespace raplas
