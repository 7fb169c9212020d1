#include "raplas/frontend/tracer.hpp"

#include <type_traits>
#include <utility>

#include "raplas/core/bits.hpp"
#include "raplas/core/cull.hpp"
#include "raplas/core/row_hits.hpp"
#include "raplas/util/parallel.hpp"

namespace raplas {

struct Tracer::Impl {
    virtual ~Impl() = default;
    virtual void trace(const RayGroup& g, GroupResult& out, bool record, bool per_ray, bool pairless) const = 0;
    virtual Hit brute_force(const Ray& r) const = 0;
};

namespace {

template <class A>
struct ImplT final : Tracer::Impl {
    using T = typename A::T;
    A a;
    const SphereSet& s;
    SphereSoA<A> spheres;
    std::vector<TriA<A>> tris;
    SphereTree tree;  // empty: no culling (every sphere tested)

    ImplT(A arith, const SphereSet& set, bool cull, unsigned threads) : a(arith), s(set) {
        auto loads = [&] {
            for (const auto& sp : set.spheres) spheres.push_back(load(a, sp));
            tris.reserve(set.triangles.size());
            for (const auto& t : set.triangles) tris.push_back(load(a, t));
        };
        if (cull && threads > 1) {  // (independent: the tree reads only the set)
            parallel_for(2, 2, [&](std::size_t side) {
                if (side == 0) tree = SphereTree(set.spheres);
                else loads();
            });
            return;
        }
        if (cull) tree = SphereTree(set.spheres);
        loads();
    }

    void trace(const RayGroup& g, GroupResult& out, bool record, bool per_ray, bool pairless) const override {
        const std::uint32_t n = g.n;
        std::vector<PlaneA<A>> planes;
        planes.reserve(g.planes.size());
        for (const auto& p : g.planes) planes.push_back(load(a, p));
        out.hits.assign(std::size_t(n) * n, Hit{});
        out.counts = GroupCounts{};
        out.sphere_list.clear();
        out.pairless.clear();
        if (per_ray) {
            out.ray_rt_tests.assign(std::size_t(n) * n, 0);
            out.ray_sphere_hits.assign(std::size_t(n) * n, 0);
        }
        const std::uint64_t valid_planes =
            std::uint64_t(bit_count(g.row_valid)) + std::uint64_t(bit_count(g.col_valid));
        out.counts.plane_tests = valid_planes * spheres.size();
        // The list is built in a per-thread scratch vector and, when recorded,
        // copied at its exact size: a frame keeps hundreds of thousands of
        // these lists, and push_back growth would leave up to half of each
        // unused (docs/MEMORY.md).
        thread_local std::vector<SphereHitRec> scratch;
        thread_local std::vector<SphereRun> runs_scratch;
        std::vector<SphereHitRec>& list = scratch;
        list.clear();
        std::vector<SphereRun>* runs = pairless ? &runs_scratch : nullptr;
        if (tree.empty())
            group_sphere_hits(a, planes.data(), n, g.row_valid, g.col_valid, spheres, list, runs);
        else
            group_sphere_hits_culled(a, g.planes.data(), planes.data(), n, g.row_valid, g.col_valid, spheres, tree, list,
                                     runs);
        if (record) out.sphere_list = std::vector<SphereHitRec>(list.begin(), list.end());
        if (runs) {
            for (const SphereRun& r : *runs) out.counts.pairless += r.count;
            if (record) out.pairless = std::vector<SphereRun>(runs->begin(), runs->end());
        }
        out.counts.sphere_hits = list.size();
        if constexpr (kNative) {
            if (!per_ray && rti_of(a) == RtiTest::division_free) {
                triangles_by_row(g, list, out);
                return;
            }
        }
        thread_local std::vector<RayA<A>> rays;
        rays.resize(std::size_t(n) * n);
        for (std::uint32_t v = 0; v < n; ++v)
            for (std::uint32_t h = 0; h < n; ++h) rays[v * n + h] = load(a, group_ray(g, h, v));
        for (const SphereHitRec& hit : list) {
            const std::uint64_t rows = hit.rows, cols = hit.cols;
            const auto [t0, t1] = triangles_tested(hit, out);
            for (std::uint64_t rm = rows; rm; rm &= rm - 1) {
                const std::uint32_t v = static_cast<std::uint32_t>(__builtin_ctzll(rm));
                for (std::uint64_t cm = cols; cm; cm &= cm - 1) {
                    const std::uint32_t h = static_cast<std::uint32_t>(__builtin_ctzll(cm));
                    const std::size_t ri = std::size_t(v) * n + h;
                    const RayA<A>& ray = rays[ri];
                    Hit& best = out.hits[ri];
                    for (std::uint32_t t = t0; t < t1; ++t) {
                        double tt;
                        if (ray_hits_triangle(a, ray, tris[t], tt)) keep_nearest(best, tt, static_cast<std::int32_t>(t));
                    }
                    if (per_ray) {
                        out.ray_rt_tests[ri] += t1 - t0;
                        out.ray_sphere_hits[ri] += 1;
                    }
                }
            }
        }
    }

    // Triangle Memory range [t0, t1) of a hit sphere; adds the group's ray-triangle
    // tests of it (every ray of its row and column masks against each triangle).
    std::pair<std::uint32_t, std::uint32_t> triangles_tested(const SphereHitRec& hit, GroupResult& out) const {
        const std::uint32_t t0 = s.first_tri[hit.sphere], t1 = t0 + s.tri_count[hit.sphere];
        out.counts.rt_tests += std::uint64_t(bit_count(hit.rows)) *
                               std::uint64_t(bit_count(hit.cols)) * (t1 - t0);
        return {t0, t1};
    }

    // Native formats, division-free test: each triangle of a hit sphere against all the rows of
    // the sphere's mask at once (rows_hit_triangle, vectorised, bit-identical to the ray-by-ray
    // test); only the columns of the sphere's mask are kept. Every ray of a group shares the
    // origin and (tmin, tmax).
    static constexpr bool kNative = std::is_same_v<A, ArithF32> || std::is_same_v<A, ArithF64>;

    void triangles_by_row(const RayGroup& g, const std::vector<SphereHitRec>& list, GroupResult& out) const {
        if (list.empty()) return;
        const std::uint32_t n = g.n;
        // The rays' directions by component, as load(a, group_ray(g, h, v))
        // gives them (a native format converts each float as it is); all
        // rays share the origin and (tmin, tmax) of ray 0.
        thread_local std::vector<T> dx, dy, dz, tt;
        dx.resize(std::size_t(n) * n);
        dy.resize(std::size_t(n) * n);
        dz.resize(std::size_t(n) * n);
        for (std::uint32_t v = 0; v < n; ++v)
            for (std::uint32_t h = 0; h < n; ++h) {
                const Ray r = group_ray(g, h, v);
                const std::size_t i = std::size_t(v) * n + h;
                dx[i] = a.cvt(r.d.x);
                dy[i] = a.cvt(r.d.y);
                dz[i] = a.cvt(r.d.z);
            }
        tt.resize(std::size_t(n) * n);
        const RayA<A> r0 = load(a, group_ray(g, 0, 0));
        thread_local GroupDirectionBoxes<T> boxes;
        boxes.build(dx, dy, dz, n);
        std::uint64_t hits[64];
        for (const SphereHitRec& rec : list) {
            const std::uint64_t rows = rec.rows, cols = rec.cols;
            const auto [t0, t1] = triangles_tested(rec, out);
            // triangles no ray of H x V can hit (a proof) are not tested: same answers, less work
            const bool prove = boxes.finite() && miss_proof_pays<T>(rows, cols);
            DirectionBox<T> box;
            if (prove) box = boxes.of(rows, cols);
            for (std::uint32_t t = t0; t < t1; ++t) {
                if (prove && rays_certainly_miss_triangle_native(r0.o, r0.tmin, r0.tmax, box, tris[t])) continue;
                if (!rows_hit_triangle(r0.o, r0.tmin, r0.tmax, dx.data(), dy.data(), dz.data(), n, rows, cols, tris[t],
                                       hits, tt.data()))
                    continue;
                for (std::uint64_t rm = rows; rm; rm &= rm - 1) {
                    const std::size_t v = static_cast<std::size_t>(__builtin_ctzll(rm));
                    const std::size_t base = v * n;
                    for (std::uint64_t cm = hits[v]; cm; cm &= cm - 1) {
                        const std::size_t h = static_cast<std::size_t>(__builtin_ctzll(cm));
                        keep_nearest(out.hits[base + h], static_cast<double>(tt[base + h]), static_cast<std::int32_t>(t));
                    }
                }
            }
        }
    }

    Hit brute_force(const Ray& r) const override {
        RayA<A> ray = load(a, r);
        Hit best;
        for (std::size_t t = 0; t < tris.size(); ++t) {
            double tt;
            if (ray_hits_triangle(a, ray, tris[t], tt)) keep_nearest(best, tt, static_cast<std::int32_t>(t));
        }
        return best;
    }
};

}  // namespace

Tracer::Tracer(const SphereSet& spheres, const NumFormat& format, bool cull, unsigned threads)
    : spheres_(spheres), format_(format) {
    switch (format.kind) {
        case NumFormat::Kind::f32:
            impl_ = std::make_unique<ImplT<ArithF32>>(ArithF32{format.rti}, spheres, cull, threads);
            break;
        case NumFormat::Kind::f64:
            impl_ = std::make_unique<ImplT<ArithF64>>(ArithF64{format.rti}, spheres, cull, threads);
            break;
        case NumFormat::Kind::custom:
            impl_ = std::make_unique<ImplT<ArithSoft>>(ArithSoft{format, true}, spheres, cull, threads);
            break;
    }
}

Tracer::~Tracer() = default;

void Tracer::trace(const RayGroup& g, GroupResult& out, bool record, bool per_ray, bool pairless) const {
    impl_->trace(g, out, record, per_ray, pairless);
}

Hit Tracer::brute_force(const Ray& r) const { return impl_->brute_force(r); }

}  // namespace raplas
