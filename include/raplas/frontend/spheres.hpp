// Step 1: bounding spheres around spatially coherent groups of at most K
// triangles, and the Sphere/Triangle Memory layout (each sphere's triangles
// contiguous in Triangle Memory).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "raplas/core/intersect.hpp"
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

// Triangle Memory record of mesh triangle i (edges and normal in double,
// stored as float).
TriangleRec make_triangle_record(const Mesh& mesh, std::size_t i);

// Radius margin that keeps the plane-sphere test conservative in a format
// with unit roundoff u, for coordinates (geometry, eye, light) up to `extent`.
// u is taken as at least float32's: the records themselves are float32.
double conservative_margin(double unit_roundoff, double extent);

}  // namespace raplas
