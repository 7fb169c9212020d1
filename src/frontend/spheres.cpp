#include "raplas/frontend/spheres.hpp"

#include "raplas/util/bytes.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
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

// Badoiu-Clarkson: 64 steps toward the farthest point from `c`, which
// converge to the minimum sphere's centre.
Vec3d badoiu_clarkson(const std::vector<Vec3d>& pts, Vec3d c) {
    for (int i = 1; i <= 64; ++i) {
        const Vec3d* far = &pts[0];
        double d2 = -1;
        for (const auto& p : pts)
            if (dot(p - c, p - c) > d2) { d2 = dot(p - c, p - c); far = &p; }
        c = c + (*far - c) / double(i + 1);
    }
    return c;
}

// badoiu_clarkson for kLanes point sets of m points each at once, set k in
// vector lane k: p[3 kLanes j + kLanes axis + k] is point j of set k,
// c[kLanes axis + k] the start and the result. Each lane does the scalar
// loop's operations in the same order (no FMA; a farther point replaces the
// farthest so far only when strictly farther), so the result is the scalar
// one, bit for bit. Each step waits for the one before it: sixteen lanes,
// four chains of four-lane vectors, keep four steps in flight.
constexpr std::size_t kLanes = 16;
__attribute__((target_clones("avx2", "default"))) void badoiu_clarkson_lanes(const double* p, std::size_t m, double* c) {
    typedef double V __attribute__((vector_size(32)));
    constexpr std::size_t L = kLanes, W = 4, N = L / W;
    // (a macro, not a lambda: a lambda is compiled for the default target,
    // and would pass the vectors through memory)
#define RAPLAS_GET(v, q) std::memcpy(&(v), (q), sizeof(V))
    V cx[N], cy[N], cz[N];
    for (std::size_t u = 0; u < N; ++u) {
        RAPLAS_GET(cx[u], c + W * u);
        RAPLAS_GET(cy[u], c + L + W * u);
        RAPLAS_GET(cz[u], c + 2 * L + W * u);
    }
    for (int i = 1; i <= 64; ++i) {
        V d2[N], fx[N], fy[N], fz[N];
        for (std::size_t u = 0; u < N; ++u) {
            d2[u] = V{} - 1.0;
            RAPLAS_GET(fx[u], p + W * u);
            RAPLAS_GET(fy[u], p + L + W * u);
            RAPLAS_GET(fz[u], p + 2 * L + W * u);
        }
        for (std::size_t j = 0; j < m; ++j) {
            const double* q = p + 3 * L * j;
            for (std::size_t u = 0; u < N; ++u) {
                V x, y, z;
                RAPLAS_GET(x, q + W * u);
                RAPLAS_GET(y, q + L + W * u);
                RAPLAS_GET(z, q + 2 * L + W * u);
                const V dx = x - cx[u], dy = y - cy[u], dz = z - cz[u];
                const V d = (dx * dx + dy * dy) + dz * dz;
                const auto farther = d > d2[u];
                d2[u] = farther ? d : d2[u];
                fx[u] = farther ? x : fx[u];
                fy[u] = farther ? y : fy[u];
                fz[u] = farther ? z : fz[u];
            }
        }
        const V step = V{} + double(i + 1);
        for (std::size_t u = 0; u < N; ++u) {
            cx[u] = cx[u] + (fx[u] - cx[u]) / step;
            cy[u] = cy[u] + (fy[u] - cy[u]) / step;
            cz[u] = cz[u] + (fz[u] - cz[u]) / step;
        }
    }
#undef RAPLAS_GET
    for (std::size_t u = 0; u < N; ++u) {
        std::memcpy(c + W * u, &cx[u], sizeof(V));
        std::memcpy(c + L + W * u, &cy[u], sizeof(V));
        std::memcpy(c + 2 * L + W * u, &cz[u], sizeof(V));
    }
}

Vec3d box_centre(const std::vector<Vec3d>& pts) {
    Aabb box;
    for (const auto& p : pts) box.grow(p);
    return box.center();
}

// The sphere of a leaf's triangle corners. `iterated`, when given, is
// badoiu_clarkson(pts, box centre), computed by the caller.
Sphere enclose(const std::vector<Vec3d>& pts, bool tight, double margin, const Vec3d* iterated = nullptr) {
    Vec3d best = box_centre(pts);
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
        // not needed when a lone triangle's smallest sphere is known exactly
        if (!exact) cands.push_back(iterated ? *iterated : badoiu_clarkson(pts, best));
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

// Median split of idx[lo, hi) along the longest axis of its centroids' box,
// leaves of k. The halves are the k-rounded lower and upper parts of the
// range in the order (centroid on the axis, triangle index), a strict total
// order: they are sets fixed by the input alone, so neither the selection
// algorithm nor the thread count changes a leaf. Each range's keys are
// copied next to their indices before the selection, so that none is looked
// up while it runs. `keys` has one entry per triangle, a range's in its own
// positions, so the two halves of a big range can be split on two threads
// while `threads` allows; it lives only while the spheres are built.
struct SplitKey {
    double c;
    std::uint32_t i;
    bool operator<(const SplitKey& o) const { return c < o.c || (c == o.c && i < o.i); }
};

void split(std::vector<std::uint32_t>& idx, std::vector<SplitKey>& keys, std::size_t lo, std::size_t hi, std::size_t k,
           const std::vector<Vec3d>& centroid, std::vector<std::pair<std::size_t, std::size_t>>& leaves,
           unsigned threads) {
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
    for (std::size_t j = lo; j < hi; ++j) keys[j] = {centroid[idx[j]][static_cast<std::size_t>(axis)], idx[j]};
    const auto first = keys.begin() + static_cast<std::ptrdiff_t>(lo);
    std::nth_element(first, first + static_cast<std::ptrdiff_t>(half), first + static_cast<std::ptrdiff_t>(n));
    for (std::size_t j = lo; j < hi; ++j) idx[j] = keys[j].i;
    if (threads > 1 && n > 8192) {
        std::vector<std::pair<std::size_t, std::size_t>> right;
        const unsigned left_threads = threads / 2;
        parallel_for(2, 2, [&](std::size_t side) {
            if (side == 0) split(idx, keys, lo, lo + half, k, centroid, leaves, left_threads);
            else split(idx, keys, lo + half, hi, k, centroid, right, threads - left_threads);
        });
        leaves.insert(leaves.end(), right.begin(), right.end());
        return;
    }
    split(idx, keys, lo, lo + half, k, centroid, leaves, 1);
    split(idx, keys, lo + half, hi, k, centroid, leaves, 1);
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
        constexpr std::size_t kChunk = 16384;
        parallel_for((nt + kChunk - 1) / kChunk, threads, [&](std::size_t c) {
            for (std::size_t i = c * kChunk; i < std::min(nt, (c + 1) * kChunk); ++i)
                centroid[i] = (to_d(mesh.corner(i, 0)) + to_d(mesh.corner(i, 1)) + to_d(mesh.corner(i, 2))) / 3.0;
        });
        std::vector<SplitKey> keys(nt);
        split(idx, keys, 0, nt, k, centroid, leaves, threads);
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
    // Spheres in blocks of kLanes: those that iterate over as many points run
    // Badoiu-Clarkson together, one per vector lane.
    parallel_for((ns + kLanes - 1) / kLanes, threads, [&](std::size_t block) {
        thread_local std::vector<Vec3d> pts[kLanes];
        const std::size_t j0 = block * kLanes, count = std::min<std::size_t>(kLanes, ns - j0);
        for (std::size_t b = 0; b < count; ++b) {
            const std::size_t j = j0 + b;
            const auto [lo, hi] = leaves[j];
            // within a sphere, triangles keep mesh order
            std::sort(idx.begin() + static_cast<std::ptrdiff_t>(lo), idx.begin() + static_cast<std::ptrdiff_t>(hi));
            pts[b].clear();
            s.first_tri[j] = static_cast<std::uint32_t>(lo);
            s.tri_count[j] = static_cast<std::uint32_t>(hi - lo);
            for (std::size_t i = lo; i < hi; ++i) {
                const std::uint32_t t = idx[i];
                for (int c = 0; c < 3; ++c) pts[b].push_back(to_d(mesh.corner(t, c)));
                s.triangles[i] = make_triangle_record(mesh, t);
                s.tri_mesh_index[i] = static_cast<std::int32_t>(t);
                s.tri_sphere[i] = static_cast<std::uint32_t>(j);
            }
        }
        // (a lone triangle's smallest sphere is mostly known exactly: enclose() decides)
        bool together = tight && count == kLanes && pts[0].size() != 3;
        for (std::size_t b = 1; together && b < kLanes; ++b) together = pts[b].size() == pts[0].size();
        if (!together) {
            for (std::size_t b = 0; b < count; ++b) s.spheres[j0 + b] = enclose(pts[b], tight, margin);
            return;
        }
        constexpr std::size_t L = kLanes;
        const std::size_t m = pts[0].size();
        thread_local std::vector<double> flat;
        flat.resize(3 * L * m);
        for (std::size_t q = 0; q < m; ++q)
            for (std::size_t b = 0; b < L; ++b) {
                flat[3 * L * q + b] = pts[b][q].x;
                flat[3 * L * q + L + b] = pts[b][q].y;
                flat[3 * L * q + 2 * L + b] = pts[b][q].z;
            }
        double c[3 * L];
        for (std::size_t b = 0; b < L; ++b) {
            const Vec3d start = box_centre(pts[b]);
            c[b] = start.x;
            c[L + b] = start.y;
            c[2 * L + b] = start.z;
        }
        badoiu_clarkson_lanes(flat.data(), m, c);
        for (std::size_t b = 0; b < L; ++b) {
            const Vec3d iterated{c[b], c[L + b], c[2 * L + b]};
            s.spheres[j0 + b] = enclose(pts[b], tight, margin, &iterated);
        }
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
