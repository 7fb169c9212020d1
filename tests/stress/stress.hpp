// Shared pieces of the numerical stress suite: the formats under test, closed
// meshes with adjacency, rays aimed at shared edges and vertices, and a
// counter of entries. Every generator is seeded: counts are exact and
// reproducible (the emulated formats are bit-exact, the native ones IEEE).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "raplas/core/intersect.hpp"
#include "raplas/core/numfmt.hpp"
#include "raplas/frontend/spheres.hpp"
#include "raplas/scene/mesh.hpp"

namespace stress {

using namespace raplas;
using Rng = std::mt19937_64;

// Every format of the suite: the two native ones, the 24-bit candidates
// (docs/ACCURACY.md §3) and the paper's choice truncating.
inline const std::vector<std::string>& formats() {
    static const std::vector<std::string> f = {"float64", "float32", "fp1-7-16", "fp1-7-16-rtz", "fp1-8-15", "fp1-6-17"};
    return f;
}

// The same formats with the watertight ray-triangle test.
inline std::vector<std::string> formats_with_watertight() {
    std::vector<std::string> f = formats();
    for (const std::string& x : formats()) f.push_back(x + "-wt");
    return f;
}

// A test's name for a format parameter (gtest names take no '-').
inline std::string param_name(const ::testing::TestParamInfo<std::string>& i) {
    std::string s = i.param;
    std::replace(s.begin(), s.end(), '-', '_');
    return s;
}

inline double uni(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
inline Vec3d rvec(Rng& rng, double lo, double hi) { return {uni(rng, lo, hi), uni(rng, lo, hi), uni(rng, lo, hi)}; }
inline Vec3d random_unit(Rng& rng) {
    for (;;) {
        Vec3d v = rvec(rng, -1, 1);
        const double l = length(v);
        if (l > 0.1 && l < 1) return v / l;
    }
}

// Ray-triangle test of one format on float32 records.
inline bool rti(const NumFormat& f, const Ray& r, const TriangleRec& t, double& tt) {
    return with_arith(f, [&](const auto& a) { return ray_hits_triangle(a, load(a, r), load(a, t), tt); });
}

// ---- closed meshes ----------------------------------------------------------

struct ClosedMesh {
    std::string name;
    Mesh mesh;  // float32 vertices: closed exactly, each edge in two triangles
};

inline std::uint32_t add_vertex(Mesh& m, const Vec3d& v) {
    m.vertices.push_back(to_f(v));
    return static_cast<std::uint32_t>(m.vertices.size() - 1);
}
inline void add_tri(Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    m.triangles.push_back({a, b, c});
    m.triangle_material.push_back(0);
}

// Unit-radius icosphere (convex, outward winding), `level` subdivisions.
inline Mesh icosphere(int level) {
    Mesh m;
    m.materials.push_back(Material{});
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<std::uint32_t, 3>> f = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
        {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (auto& p : v) p = normalize(p);
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(normalize((v[a] + v[b]) * 0.5));
            return mid[key] = static_cast<std::uint32_t>(v.size() - 1);
        };
        std::vector<std::array<std::uint32_t, 3>> g;
        for (auto& tri : f) {
            const std::uint32_t a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
            g.push_back({tri[0], a, c});
            g.push_back({tri[1], b, a});
            g.push_back({tri[2], c, b});
            g.push_back({a, b, c});
        }
        f = g;
    }
    for (auto& p : v) add_vertex(m, p);
    for (auto& tri : f) add_tri(m, tri[0], tri[1], tri[2]);
    return m;
}

// Cube [-1,1]^3, each face a k x k grid of quads split along alternating
// diagonals (coplanar neighbours), outward winding.
inline Mesh cube(int k) {
    Mesh m;
    m.materials.push_back(Material{});
    std::map<std::array<long, 3>, std::uint32_t> index;  // shared vertices across faces
    auto vert = [&](const Vec3d& p) {
        std::array<long, 3> key = {std::lround(p.x * k), std::lround(p.y * k), std::lround(p.z * k)};
        auto it = index.find(key);
        if (it != index.end()) return it->second;
        return index[key] = add_vertex(m, p);
    };
    for (int axis = 0; axis < 3; ++axis) {
        for (int side : {-1, 1}) {
            Vec3d n, u, v;
            n[std::size_t(axis)] = side;
            u[std::size_t((axis + 1) % 3)] = 1;
            v[std::size_t((axis + 2) % 3)] = 1;
            if (side < 0) std::swap(u, v);  // keep u x v = n
            for (int i = 0; i < k; ++i)
                for (int j = 0; j < k; ++j) {
                    auto P = [&](int a, int b) { return vert(n + u * (2.0 * a / k - 1) + v * (2.0 * b / k - 1)); };
                    const std::uint32_t p00 = P(i, j), p10 = P(i + 1, j), p11 = P(i + 1, j + 1), p01 = P(i, j + 1);
                    if ((i + j) % 2) {
                        add_tri(m, p00, p10, p11);
                        add_tri(m, p00, p11, p01);
                    } else {
                        add_tri(m, p00, p10, p01);
                        add_tri(m, p10, p11, p01);
                    }
                }
        }
    }
    return m;
}

// Closed prism over a regular n-gon with fan caps (high-valence centre
// vertices), outward winding.
inline Mesh fan_prism(int n) {
    Mesh m;
    m.materials.push_back(Material{});
    const double pi = std::acos(-1.0);
    std::vector<std::uint32_t> lo, hi;
    for (int i = 0; i < n; ++i) {
        const double a = 2 * pi * i / n;
        lo.push_back(add_vertex(m, {std::cos(a), -1, std::sin(a)}));
        hi.push_back(add_vertex(m, {std::cos(a), 1, std::sin(a)}));
    }
    const std::uint32_t cl = add_vertex(m, {0, -1, 0}), ch = add_vertex(m, {0, 1, 0});
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        add_tri(m, lo[i], hi[i], hi[j]);
        add_tri(m, lo[i], hi[j], lo[j]);
        add_tri(m, ch, hi[j], hi[i]);
        add_tri(m, cl, lo[i], lo[j]);
    }
    return m;
}

// Where and how large the mesh is placed: v -> v * size + offset, rays start
// about `ray_distance` away from their target.
struct Placement {
    std::string name;
    double size, offset, ray_distance;
};

inline const std::vector<Placement>& placements() {
    static const std::vector<Placement> p = {
        {"unit", 1.0, 0.0, 3.0},          // coordinates of order 1
        {"tiny", 1e-6, 0.0, 1.0},         // an object 1e-6 of the scene: rays from 1e6 sizes away
        {"huge", 1e6, 0.0, 3e6},          // coordinates of order 1e6
        {"huge7", 1e7, 0.0, 3e7},         // and 1e7
        {"far", 1.0, 1e4, 3.0},           // 1e4 sizes from the origin
    };
    return p;
}

inline Mesh placed(const Mesh& m, const Placement& p) {
    Mesh out = m;
    out.vertices.clear();
    for (const Vec3f& v : m.vertices) out.vertices.push_back(to_f(to_d(v) * p.size + Vec3d(p.offset, p.offset * 0.5, -p.offset * 0.25)));
    return out;
}

inline std::vector<ClosedMesh> closed_meshes() {
    return {{"icosphere", icosphere(2)}, {"cube", cube(2)}, {"fan_prism", fan_prism(24)}};
}

// ---- rays aimed at shared edges and vertices --------------------------------

struct AimedRay {
    Ray ray;
    bool vertex = false;  // aimed at a shared vertex (else a point of a shared edge)
};

// Outward unit normals of the mesh's triangles, in double from the float32 vertices.
inline std::vector<Vec3d> face_normals(const Mesh& m) {
    std::vector<Vec3d> n;
    for (std::size_t i = 0; i < m.triangle_count(); ++i) {
        const Vec3d a = to_d(m.corner(i, 0)), b = to_d(m.corner(i, 1)), c = to_d(m.corner(i, 2));
        n.push_back(normalize(cross(b - a, c - a)));
    }
    return n;
}

// Rays from outside that enter the mesh exactly through a shared edge point
// or a vertex: the direction faces every triangle around the target (d·n < 0),
// so the ray crosses the surface there once, inward. Origins are float32 and
// directions float32(target - origin): the stored ray passes the target as
// closely as float32 records allow.
inline std::vector<AimedRay> aimed_rays(const Mesh& m, const Placement& pl, int edge_rays, int vertex_rays, Rng& rng) {
    const std::vector<Vec3d> n = face_normals(m);
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> edges;
    std::vector<std::vector<std::size_t>> around(m.vertices.size());
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = m.triangles[t][std::size_t(k)], b = m.triangles[t][std::size_t((k + 1) % 3)];
            edges[std::minmax(a, b)].push_back(t);
            around[a].push_back(t);
        }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edge_list;
    for (const auto& e : edges) edge_list.push_back(e.first);
    auto make = [&](const Vec3d& target, const std::vector<std::size_t>& faces, bool vertex) -> AimedRay {
        Vec3d mean;
        for (std::size_t f : faces) mean += n[f];
        mean = normalize(mean);
        for (;;) {
            const Vec3d d = normalize(-mean + random_unit(rng) * 0.6);
            bool inward = true;
            for (std::size_t f : faces) inward = inward && dot(d, n[f]) < -0.05;
            if (!inward) continue;
            const Vec3f o = to_f(target - d * pl.ray_distance * uni(rng, 0.5, 1.5));
            const Vec3f dd = to_f(target - to_d(o));
            return {Ray{o, dd, 0.0f, FLT_MAX}, vertex};
        }
    };
    std::vector<AimedRay> rays;
    for (int i = 0; i < edge_rays; ++i) {
        const auto& e = edge_list[std::size_t(rng() % edge_list.size())];
        const Vec3d a = to_d(m.vertices[e.first]), b = to_d(m.vertices[e.second]);
        rays.push_back(make(a + (b - a) * uni(rng, 0.02, 0.98), edges[e], false));
    }
    for (int i = 0; i < vertex_rays; ++i) {
        const std::uint32_t v = static_cast<std::uint32_t>(rng() % m.vertices.size());
        rays.push_back(make(to_d(m.vertices[v]), around[v], true));
    }
    return rays;
}

// Entries of one ray into a closed convex mesh: hits on triangles the ray
// meets from outside (D·n < 0). 1 is right; 0 is a leak (the ray passes
// through the surface), 2 or more a double hit.
struct EntryCounts {
    std::uint64_t rays = 0, leaks = 0, doubles = 0;
    EntryCounts& operator+=(const EntryCounts& o) {
        rays += o.rays;
        leaks += o.leaks;
        doubles += o.doubles;
        return *this;
    }
};

template <class HitFn>
EntryCounts count_entries(const std::vector<TriangleRec>& tris, const std::vector<Vec3d>& normals,
                          const std::vector<AimedRay>& rays, HitFn&& hit) {
    EntryCounts c;
    for (const AimedRay& ar : rays) {
        int entries = 0;
        const Vec3d d = to_d(ar.ray.d);
        for (std::size_t t = 0; t < tris.size(); ++t) {
            if (!(dot(d, normals[t]) < 0)) continue;
            double tt;
            entries += hit(ar.ray, tris[t], tt) ? 1 : 0;
        }
        ++c.rays;
        c.leaks += entries == 0;
        c.doubles += entries > 1;
    }
    return c;
}

inline std::vector<TriangleRec> records(const Mesh& m) {
    std::vector<TriangleRec> r;
    for (std::size_t i = 0; i < m.triangle_count(); ++i) r.push_back(make_triangle_record(m, i));
    return r;
}

}  // namespace stress
