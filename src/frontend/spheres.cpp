#include "raplas/frontend/spheres.hpp"

#include "raplas/util/bytes.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "raplas/util/parallel.hpp"

namespace raplas {

TriangleRec make_triangle_record(const Mesh& mesh, std::size_t i) {
    Vec3d v0 = to_d(mesh.corner(i, 0)), v1 = to_d(mesh.corner(i, 1)), v2 = to_d(mesh.corner(i, 2));
    Vec3d e1 = v1 - v0, e2 = v2 - v0;
    return {to_f(v0), to_f(e1), to_f(e2), to_f(cross(e1, e2)), mesh.corner(i, 1), mesh.corner(i, 2)};
}

double conservative_margin(double unit_roundoff, double extent) {
    // Planes, spheres and rays are float32 records in every format, so their
    // own rounding bounds the error from below even in float64.
    const double u = std::max(unit_roundoff, NumFormat::float32().unit_roundoff());
    return 64.0 * u * extent;
}

namespace {

// Exact smallest sphere of one triangle: the circumsphere, or for an obtuse
// triangle the sphere on its longest edge.
bool triangle_min_sphere(const Vec3d& a, const Vec3d& b, const Vec3d& c, Vec3d& center) {
    Vec3d ab = b - a, ac = c - a;
    Vec3d n = cross(ab, ac);
    double n2 = dot(n, n);
    if (!(n2 > 0)) return false;
    Vec3d bc = c - b;
    if (dot(ab, ac) <= 0) { center = (b + c) * 0.5; return true; }
    if (dot(-ab, bc) <= 0) { center = (a + c) * 0.5; return true; }
    if (dot(-ac, -bc) <= 0) { center = (a + b) * 0.5; return true; }
    center = a + (cross(n, ab) * dot(ac, ac) + cross(ac, n) * dot(ab, ab)) / (2.0 * n2);
    return true;
}

double radius_about(const Vec3d& c, const std::vector<Vec3d>& pts) {
    double r2 = 0;
    for (const auto& p : pts) r2 = std::max(r2, dot(p - c, p - c));
    return std::sqrt(r2);
}

Sphere enclose(const std::vector<Vec3d>& pts, bool tight, double margin) {
    Aabb box;
    for (const auto& p : pts) box.grow(p);
    Vec3d best = box.center();
    double best_r = radius_about(best, pts);
    if (tight) {
        std::vector<Vec3d> cands;
        Vec3d mean;
        for (const auto& p : pts) mean += p;
        cands.push_back(mean / double(pts.size()));
        bool exact = false;
        if (pts.size() == 3) {
            Vec3d c;
            exact = triangle_min_sphere(pts[0], pts[1], pts[2], c);
            if (exact) cands.push_back(c);
        }
        // Badoiu-Clarkson: step toward the farthest point, converges to the
        // minimum sphere (not needed when a lone triangle's is known exactly).
        if (!exact) {
            Vec3d c = best;
            for (int i = 1; i <= 64; ++i) {
                const Vec3d* far = &pts[0];
                double d2 = -1;
                for (const auto& p : pts)
                    if (dot(p - c, p - c) > d2) { d2 = dot(p - c, p - c); far = &p; }
                c = c + (*far - c) / double(i + 1);
            }
            cands.push_back(c);
        }
        for (const auto& cc : cands) {
            double r = radius_about(cc, pts);
            if (r < best_r) { best_r = r; best = cc; }
        }
    }
    Sphere s;
    s.c = to_f(best);
    // radius about the float centre, rounded up, plus the rounding margin
    double r = radius_about(to_d(s.c), pts);
    s.r = std::nextafter(float(r + margin), INFINITY);
    return s;
}

void split(std::vector<std::uint32_t>& idx, std::size_t lo, std::size_t hi, std::size_t k,
           const std::vector<Vec3d>& centroid, std::vector<std::pair<std::size_t, std::size_t>>& leaves) {
    std::size_t n = hi - lo;
    if (n <= k) {
        leaves.emplace_back(lo, hi);
        return;
    }
    Aabb box;
    for (std::size_t i = lo; i < hi; ++i) box.grow(centroid[idx[i]]);
    Vec3d e = box.extent();
    int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    std::size_t half = (n / 2 + k - 1) / k * k;  // leaves stay full
    if (half >= n) half = n - k;
    auto mid = idx.begin() + static_cast<std::ptrdiff_t>(lo + half);
    std::nth_element(idx.begin() + static_cast<std::ptrdiff_t>(lo), mid, idx.begin() + static_cast<std::ptrdiff_t>(hi),
                     [&](std::uint32_t a, std::uint32_t b) {
                         double ca = centroid[a][static_cast<std::size_t>(axis)];
                         double cb = centroid[b][static_cast<std::size_t>(axis)];
                         return ca < cb || (ca == cb && a < b);
                     });
    split(idx, lo, lo + half, k, centroid, leaves);
    split(idx, lo + half, hi, k, centroid, leaves);
}

}  // namespace

SphereSet build_spheres(const Mesh& mesh, int tris_per_sphere, const std::string& method, double margin,
                        unsigned threads) {
    const std::size_t nt = mesh.triangle_count();
    const std::size_t k = static_cast<std::size_t>(std::max(1, tris_per_sphere));
    std::vector<std::uint32_t> idx(nt);
    std::iota(idx.begin(), idx.end(), 0u);
    std::vector<std::pair<std::size_t, std::size_t>> leaves;
    const bool tight = method != "file-order";
    if (tight) {
        std::vector<Vec3d> centroid(nt);
        for (std::size_t i = 0; i < nt; ++i)
            centroid[i] = (to_d(mesh.corner(i, 0)) + to_d(mesh.corner(i, 1)) + to_d(mesh.corner(i, 2))) / 3.0;
        split(idx, 0, nt, k, centroid, leaves);
    } else {
        for (std::size_t lo = 0; lo < nt; lo += k) leaves.emplace_back(lo, std::min(nt, lo + k));
    }
    // Leaves are contiguous and ascending, so leaf j's triangles go to
    // Triangle Memory [lo, hi): every sphere is built on its own.
    const std::size_t ns = leaves.size();
    SphereSet s;
    s.spheres.resize(ns);
    s.first_tri.resize(ns);
    s.tri_count.resize(ns);
    s.triangles.resize(nt);
    s.tri_mesh_index.resize(nt);
    s.tri_sphere.resize(nt);
    parallel_for(ns, threads, [&](std::size_t j) {
        const auto [lo, hi] = leaves[j];
        // within a sphere, triangles keep mesh order
        std::sort(idx.begin() + static_cast<std::ptrdiff_t>(lo), idx.begin() + static_cast<std::ptrdiff_t>(hi));
        thread_local std::vector<Vec3d> pts;
        pts.clear();
        s.first_tri[j] = static_cast<std::uint32_t>(lo);
        s.tri_count[j] = static_cast<std::uint32_t>(hi - lo);
        for (std::size_t i = lo; i < hi; ++i) {
            const std::uint32_t t = idx[i];
            for (int c = 0; c < 3; ++c) pts.push_back(to_d(mesh.corner(t, c)));
            s.triangles[i] = make_triangle_record(mesh, t);
            s.tri_mesh_index[i] = static_cast<std::int32_t>(t);
            s.tri_sphere[i] = static_cast<std::uint32_t>(j);
        }
        s.spheres[j] = enclose(pts, tight, margin);
    });
    return s;
}

SphereSet refit_spheres(const SphereSet& prev, double prev_margin, const Mesh& mesh,
                        const std::vector<std::int32_t>& tri_motion, const std::vector<RigidMotion>& motions,
                        SphereRefit mode, const std::string& method, double margin, unsigned threads) {
    const std::size_t nt = prev.triangles.size(), ns = prev.spheres.size();
    if (mesh.triangle_count() != nt)
        throw std::invalid_argument("refit_spheres: the mesh has " + std::to_string(mesh.triangle_count()) +
                                    " triangles, the spheres " + std::to_string(nt));
    if (!tri_motion.empty() && tri_motion.size() != nt)
        throw std::invalid_argument("refit_spheres: tri_motion needs one entry per triangle");
    const bool tight = method != "file-order";
    SphereSet s;
    s.spheres.resize(ns);
    s.first_tri = prev.first_tri;
    s.tri_count = prev.tri_count;
    s.triangles.resize(nt);
    s.tri_mesh_index = prev.tri_mesh_index;
    s.tri_sphere = prev.tri_sphere;
    // The motion every triangle of sphere j shares, or -1.
    auto shared_motion = [&](std::size_t j) -> std::int32_t {
        if (tri_motion.empty() || mode == SphereRefit::enclose) return -1;
        const std::size_t lo = prev.first_tri[j], hi = lo + prev.tri_count[j];
        const std::int32_t k = tri_motion[static_cast<std::size_t>(prev.tri_mesh_index[lo])];
        if (k < 0 || static_cast<std::size_t>(k) >= motions.size()) return -1;
        for (std::size_t i = lo + 1; i < hi; ++i)
            if (tri_motion[static_cast<std::size_t>(prev.tri_mesh_index[i])] != k) return -1;
        return k;
    };
    parallel_for(ns, threads, [&](std::size_t j) {
        const std::size_t lo = prev.first_tri[j], hi = lo + prev.tri_count[j];
        for (std::size_t i = lo; i < hi; ++i)
            s.triangles[i] = make_triangle_record(mesh, static_cast<std::size_t>(prev.tri_mesh_index[i]));
        thread_local std::vector<Vec3d> pts;
        auto moved_corners = [&] {
            pts.clear();
            for (std::size_t i = lo; i < hi; ++i)
                for (int c = 0; c < 3; ++c) pts.push_back(to_d(mesh.corner(static_cast<std::size_t>(prev.tri_mesh_index[i]), c)));
        };
        const std::int32_t k = shared_motion(j);
        if (k < 0) {
            moved_corners();
            s.spheres[j] = enclose(pts, tight, margin);
            return;
        }
        const RigidMotion& m = motions[static_cast<std::size_t>(k)];
        const Sphere& old = prev.spheres[j];
        if (m.identity() && margin == prev_margin) {
            s.spheres[j] = old;
            return;
        }
        Sphere out;
        out.c = to_f(m.apply(to_d(old.c)));
        if (mode == SphereRefit::transform_radius) {
            moved_corners();
            out.r = std::nextafter(float(radius_about(to_d(out.c), pts) + margin), INFINITY);
        } else {
            // |v' - c'| <= scale (r - prev_margin) + |v' - T v| + |c' - T c|. Each
            // moved point is T computed in double (relative error far below
            // 2^-40 of the magnitudes that enter it) and rounded to float
            // (at most 2^-24 of its length); |T v| <= |c'| + scale r.
            const double sr = std::fabs(m.scale) * double(old.r);
            const double inputs = max_abs(m.pivot) + max_abs(m.translate) +
                                  std::fabs(m.scale) * (max_abs(to_d(old.c)) + max_abs(m.pivot) + double(old.r));
            const double allowance = 0x1p-22 * (length(to_d(out.c)) + sr) + 0x1p-40 * (4 * inputs + margin);
            out.r = std::nextafter(float(std::fabs(m.scale) * (double(old.r) - prev_margin) + allowance + margin), INFINITY);
        }
        s.spheres[j] = out;
    });
    return s;
}

bool same_spheres(const SphereSet& a, const SphereSet& b) {
    return same_bytes(a.spheres, b.spheres) && a.first_tri == b.first_tri && a.tri_count == b.tri_count &&
           same_bytes(a.triangles, b.triangles) && a.tri_mesh_index == b.tri_mesh_index && a.tri_sphere == b.tri_sphere;
}

SphereQuality sphere_quality(const SphereSet& s) {
    SphereQuality q;
    for (const auto& sp : s.spheres) {
        q.sum_radius += sp.r;
        q.sum_volume += 4.0 / 3.0 * M_PI * double(sp.r) * sp.r * sp.r;
    }
    q.mean_tris_per_sphere = s.spheres.empty() ? 0 : double(s.triangles.size()) / double(s.spheres.size());
    return q;
}

}  // namespace raplas
