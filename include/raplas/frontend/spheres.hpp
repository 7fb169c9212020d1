// Step 1: bounding spheres around spatially coherent groups of at most K
// triangles, and the Sphere/Triangle Memory layout (each sphere's triangles
// contiguous in Triangle Memory).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "raplas/core/intersect.hpp"
#include "raplas/scene/animation.hpp"
#include "raplas/scene/mesh.hpp"

namespace raplas {

struct SphereSet {
    std::vector<Sphere> spheres;               // Sphere Memory, in stream order
    std::vector<std::uint32_t> first_tri;      // per sphere: first Triangle Memory index
    std::vector<std::uint32_t> tri_count;      // per sphere: its triangles
    std::vector<TriangleRec> triangles;        // Triangle Memory, in stream order
    std::vector<std::int32_t> tri_mesh_index;  // Triangle Memory index -> mesh triangle index
    std::vector<std::uint32_t> tri_sphere;     // Triangle Memory index -> sphere

    std::size_t sphere_count() const { return spheres.size(); }
    std::size_t triangle_count() const { return triangles.size(); }
};

struct SphereQuality {
    double sum_radius = 0;     // a plane's chance to cut a sphere grows with its radius
    double sum_volume = 0;
    double mean_tris_per_sphere = 0;
};

// "median-split": recursive median split of triangle centroids along the
// longest axis (leaf sizes multiples of K), each sphere the smallest of
// several candidate enclosing spheres. "file-order": K consecutive mesh
// triangles per sphere around their bounding-box centre (the naive baseline).
// `margin` is added to every radius so that rounding in the plane test can
// never lose a hit (see conservative_margin()). The spheres are computed on
// `threads` threads, each on its own, so the result does not depend on it.
SphereSet build_spheres(const Mesh& mesh, int tris_per_sphere, const std::string& method, double margin,
                        unsigned threads = 1);
SphereQuality sphere_quality(const SphereSet& s);
// Every array of the two sets byte for byte the same: the same Sphere and
// Triangle Memories.
bool same_spheres(const SphereSet& a, const SphereSet& b);

// How refit_spheres() gets a sphere whose triangles all share one rigid motion.
enum class SphereRefit {
    // Centre moved by the motion (rounded to float), radius scaled by its
    // scale plus an allowance for the rounding of the moved centre and corners:
    // no corner is read.
    transform,
    // Centre moved by the motion, radius recomputed about it from the moved
    // corners (as build_spheres() does about its centre).
    transform_radius,
    // Every sphere fitted again to its moved triangles, as build_spheres()
    // fits one (the motions are not used).
    enclose,
};

// The spheres of `prev` (build_spheres() of an earlier mesh with margin
// `prev_margin`) carried to `mesh`, the same triangles moved: the grouping
// of triangles into spheres and the Sphere and Triangle Memory order are
// prev's (no new median split); the Triangle Memory records are made from
// `mesh`. tri_motion gives, per mesh triangle, an index into `motions` or -1
// for a triangle moved otherwise (empty: every one -1). A sphere whose
// triangles all share a motion k is carried by motions[k] as `mode` says,
// and kept as it is when that motion is the identity and the margin is
// unchanged; any other sphere is fitted again to its moved triangles.
//
// The transform mode encloses the moved triangles, with `margin` to spare,
// when each moved corner is the float rounding of motions[k].apply() of the
// earlier corner (as scene_at_frame() moves an object): then
// |v' - c'| <= scale |v - c| + rounding of v' and c', and the allowance covers
// that rounding. The result is a valid sphere set, but not the one
// build_spheres(mesh) gives: the median split depends on the axes, so a
// rotation changes the grouping and order, and a centre moved and rounded
// differs in its last bits from one fitted to the rounded moved corners.
SphereSet refit_spheres(const SphereSet& prev, double prev_margin, const Mesh& mesh,
                        const std::vector<std::int32_t>& tri_motion, const std::vector<RigidMotion>& motions,
                        SphereRefit mode, const std::string& method, double margin, unsigned threads = 1);

// Triangle Memory record of mesh triangle i (edges and normal in double,
// stored as float).
TriangleRec make_triangle_record(const Mesh& mesh, std::size_t i);

// Radius margin that keeps the plane-sphere test conservative in a format
// with unit roundoff u, for coordinates (geometry, eye, light) up to `extent`.
// u is taken as at least float32's: the records themselves are float32.
double conservative_margin(double unit_roundoff, double extent);

}  // namespace raplas
