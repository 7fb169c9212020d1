#include "raplas/frontend/tracer.hpp"

#include "raplas/core/cull.hpp"

namespace raplas {

struct Tracer::Impl {
    virtual ~Impl() = default;
    virtual void trace(const RayGroup& g, GroupResult& out, bool record, bool per_ray) const = 0;
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

    ImplT(A arith, const SphereSet& set, bool cull) : a(arith), s(set) {
        if (cull) tree = SphereTree(set.spheres);
        for (const auto& sp : set.spheres) spheres.push_back(load(a, sp));
        tris.reserve(set.triangles.size());
        for (const auto& t : set.triangles) tris.push_back(load(a, t));
    }

    void trace(const RayGroup& g, GroupResult& out, bool record, bool per_ray) const override {
        const std::uint32_t n = g.n;
        std::vector<PlaneA<A>> planes;
        planes.reserve(g.planes.size());
        for (const auto& p : g.planes) planes.push_back(load(a, p));
        std::vector<RayA<A>> rays(std::size_t(n) * n);
        for (std::uint32_t v = 0; v < n; ++v)
            for (std::uint32_t h = 0; h < n; ++h) rays[v * n + h] = load(a, group_ray(g, h, v));
        out.hits.assign(std::size_t(n) * n, Hit{});
        out.counts = GroupCounts{};
        out.sphere_list.clear();
        if (per_ray) {
            out.ray_rt_tests.assign(std::size_t(n) * n, 0);
            out.ray_sphere_hits.assign(std::size_t(n) * n, 0);
        }
        const std::uint64_t valid_planes =
            std::uint64_t(__builtin_popcountll(g.row_valid)) + std::uint64_t(__builtin_popcountll(g.col_valid));
        out.counts.plane_tests = valid_planes * spheres.size();
        std::vector<SphereHitRec> local;
        std::vector<SphereHitRec>& list = record ? out.sphere_list : local;
        if (tree.empty())
            group_sphere_hits(a, planes.data(), n, g.row_valid, g.col_valid, spheres, list);
        else
            group_sphere_hits_culled(a, g.planes.data(), planes.data(), n, g.row_valid, g.col_valid, spheres, tree, list);
        out.counts.sphere_hits = list.size();
        for (const SphereHitRec& hit : list) {
            const std::uint32_t si = hit.sphere;
            const std::uint64_t rows = hit.rows, cols = hit.cols;
            const std::uint32_t t0 = s.first_tri[si], t1 = t0 + s.tri_count[si];
            out.counts.rt_tests += std::uint64_t(__builtin_popcountll(rows)) *
                                   std::uint64_t(__builtin_popcountll(cols)) * (t1 - t0);
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

Tracer::Tracer(const SphereSet& spheres, const NumFormat& format, bool cull) : spheres_(spheres), format_(format) {
    switch (format.kind) {
        case NumFormat::Kind::f32: impl_ = std::make_unique<ImplT<ArithF32>>(ArithF32{format.rti}, spheres, cull); break;
        case NumFormat::Kind::f64: impl_ = std::make_unique<ImplT<ArithF64>>(ArithF64{format.rti}, spheres, cull); break;
        case NumFormat::Kind::custom:
            impl_ = std::make_unique<ImplT<ArithSoft>>(ArithSoft{format, true}, spheres, cull);
            break;
    }
}

Tracer::~Tracer() = default;

void Tracer::trace(const RayGroup& g, GroupResult& out, bool record, bool per_ray) const {
    impl_->trace(g, out, record, per_ray);
}

Hit Tracer::brute_force(const Ray& r) const { return impl_->brute_force(r); }

}  // namespace raplas
