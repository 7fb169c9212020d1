#include <cmath>
#include <map>
#include <utility>

#include "raplas/scene/mesh.hpp"

namespace raplas {

namespace {

struct Builder {
    Mesh& m;
    std::int32_t object = 0;
    // The triangles added from now on belong to the object `name`.
    void begin_object(const std::string& name) {
        m.object_names.push_back(name);
        object = static_cast<std::int32_t>(m.object_names.size() - 1);
    }
    std::int32_t add_material(const std::string& name, Vec3f kd) {
        Material mt;
        mt.name = name;
        mt.diffuse = kd;
        m.materials.push_back(mt);
        return static_cast<std::int32_t>(m.materials.size() - 1);
    }
    std::uint32_t vertex(Vec3f p) {
        m.vertices.push_back(p);
        return static_cast<std::uint32_t>(m.vertices.size() - 1);
    }
    void tri(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::int32_t mat) {
        m.triangles.push_back({a, b, c});
        m.triangle_material.push_back(mat);
        m.triangle_object.push_back(object);
    }
    void quad(Vec3f a, Vec3f b, Vec3f c, Vec3f d, std::int32_t mat) {
        auto ia = vertex(a), ib = vertex(b), ic = vertex(c), id = vertex(d);
        tri(ia, ib, ic, mat);
        tri(ia, ic, id, mat);
    }
    void box(Vec3f lo, Vec3f hi, std::int32_t mat) {
        Vec3f p[8];
        for (int i = 0; i < 8; ++i) p[i] = Vec3f(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
        quad(p[0], p[1], p[3], p[2], mat);  // z-
        quad(p[4], p[6], p[7], p[5], mat);  // z+
        quad(p[0], p[4], p[5], p[1], mat);  // y-
        quad(p[2], p[3], p[7], p[6], mat);  // y+
        quad(p[0], p[2], p[6], p[4], mat);  // x-
        quad(p[1], p[5], p[7], p[3], mat);  // x+
    }
    // Icosphere: an icosahedron subdivided `level` times, projected on the sphere.
    void icosphere(Vec3d c, double r, int level, std::int32_t mat) {
        const double t = (1.0 + std::sqrt(5.0)) / 2.0;
        std::vector<Vec3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
        for (auto& p : v) p = normalize(p);
        std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                             {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                             {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                             {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
        for (int l = 0; l < level; ++l) {
            std::map<std::pair<int, int>, int> mid;
            auto midpoint = [&](int a, int b) {
                auto key = std::make_pair(std::min(a, b), std::max(a, b));
                auto it = mid.find(key);
                if (it != mid.end()) return it->second;
                v.push_back(normalize((v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]) * 0.5));
                int id = static_cast<int>(v.size() - 1);
                mid[key] = id;
                return id;
            };
            std::vector<std::array<int, 3>> nf;
            for (auto& tr : f) {
                int a = midpoint(tr[0], tr[1]), b = midpoint(tr[1], tr[2]), cc = midpoint(tr[2], tr[0]);
                nf.push_back({tr[0], a, cc});
                nf.push_back({tr[1], b, a});
                nf.push_back({tr[2], cc, b});
                nf.push_back({a, b, cc});
            }
            f.swap(nf);
        }
        auto base = static_cast<std::uint32_t>(m.vertices.size());
        for (auto& p : v) m.vertices.push_back(to_f(c + p * r));
        for (auto& tr : f)
            tri(base + std::uint32_t(tr[0]), base + std::uint32_t(tr[1]), base + std::uint32_t(tr[2]), mat);
    }
};

}  // namespace

Mesh builtin_mesh(int detail) {
    Mesh m;
    m.source = "<builtin:default>";
    m.materials.push_back(Material{});
    Builder b{m};
    auto floor = b.add_material("floor", {0.80f, 0.78f, 0.72f});
    auto wall = b.add_material("wall", {0.55f, 0.65f, 0.80f});
    auto red = b.add_material("red", {0.85f, 0.25f, 0.20f});
    auto gold = b.add_material("gold", {0.90f, 0.70f, 0.25f});
    auto green = b.add_material("green", {0.30f, 0.75f, 0.35f});
    b.begin_object("floor");
    b.quad({-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, floor);
    b.begin_object("wall");
    b.quad({-3, 0, -3}, {3, 0, -3}, {3, 3, -3}, {-3, 3, -3}, wall);
    b.begin_object("box");
    b.box({0.4f, 0.0f, -1.2f}, {1.4f, 1.6f, -0.2f}, red);
    b.begin_object("big_sphere");
    b.icosphere({-0.9, 0.8, -0.3}, 0.8, detail, gold);
    b.begin_object("small_sphere");
    b.icosphere({0.6, 0.45, 0.9}, 0.45, detail > 0 ? detail - 1 : 0, green);
    return m;
}

Mesh wave_mesh(int detail, double phase) {
    Mesh m;
    m.source = "<builtin:wave>";
    m.materials.push_back(Material{});
    Builder b{m};
    const auto water = b.add_material("wave", {0.25f, 0.45f, 0.80f});
    b.begin_object("wave");
    const int n = 4 << detail;  // cells a side
    const double pi = std::acos(-1.0);
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            const double x = -2.0 + 4.0 * j / n, z = -2.0 + 4.0 * i / n;
            // Crests run across the grid at an angle: two periods along x, one along z.
            const double y = 0.25 * std::sin(pi * x + 0.5 * pi * z - phase);
            b.vertex(to_f(Vec3d(x, y, z)));
        }
    const auto at = [n](int i, int j) { return static_cast<std::uint32_t>(i * (n + 1) + j); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            b.tri(at(i, j), at(i + 1, j), at(i + 1, j + 1), water);
            b.tri(at(i, j), at(i + 1, j + 1), at(i, j + 1), water);
        }
    return m;
}

}  // namespace raplas
