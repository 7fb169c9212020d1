#include "functional.hpp"

#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "raplas/core/cull.hpp"
#include "raplas/core/row_hits.hpp"

namespace raplas::model {

namespace {

template <class A>
class ComputeFunctional final : public Functional {
public:
    ComputeFunctional(const Trace& t, A a, bool cull, bool pairless, bool pairless_given)
        : a_(a), pairless_(pairless), pairless_given_(pairless && pairless_given) {
        if (cull) tree_ = SphereTree(t.spheres);
        for (const auto& s : t.spheres) spheres_.push_back(load(a_, s));
        tris_.reserve(t.triangles.size());
        for (const auto& tr : t.triangles) tris_.push_back(load(a_, tr));
        mode_ = FunctionalMode::compute;
    }

    class Unit final : public GroupUnit {
    public:
        explicit Unit(const ComputeFunctional& f) : f_(f) {}
        // The Plane-Sphere Intersectors' results for every sphere of the pass,
        // computed in one batch when the group is loaded; the pipeline model
        // releases each at its cycle.
        void load(const TraceGroup& g) override {
            n_ = g.n;
            planes_.clear();
            for (const auto& p : g.planes) planes_.push_back(raplas::load(f_.a_, p));
            rays_.resize(std::size_t(n_) * n_);
            for (std::uint32_t v = 0; v < n_; ++v)
                for (std::uint32_t h = 0; h < n_; ++h) rays_[v * n_ + h] = raplas::load(f_.a_, g.ray(h, v));
            if constexpr (kNative) {  // for rti_row and rti_certain_miss
                directions_by_component(rays_, dx_, dy_, dz_);
                boxes_.build(dx_, dy_, dz_, n_);
            }
            std::vector<SphereRun>* runs = f_.pairless_ && !f_.pairless_given_ ? &runs_ : nullptr;
            if (f_.tree_.empty())
                group_sphere_hits(f_.a_, planes_.data(), n_, g.row_valid, g.col_valid, f_.spheres_, hits_, runs);
            else
                group_sphere_hits_culled(f_.a_, g.planes.data(), planes_.data(), n_, g.row_valid, g.col_valid,
                                         f_.spheres_, f_.tree_, hits_, runs);
            if (f_.pairless_given_) runs_ = g.pairless;
        }
        const std::vector<SphereHitRec>& sphere_hits() const override { return hits_; }
        const std::vector<SphereRun>& pairless() const override { return runs_; }
        bool rti(std::uint32_t ray, std::uint32_t tri, double& t) override {
            return ray_hits_triangle(f_.a_, rays_[ray], f_.tris_[tri], t);
        }
        std::uint64_t rti_row(std::uint32_t v, std::uint64_t cols, std::uint32_t tri, double* t) override {
            std::uint64_t hit = 0;
            if constexpr (kNative) {
                // The group's rays share the origin and (tmin, tmax): the
                // vectorised row test, as the front end's tracer does.
                if (rti_of(f_.a_) == RtiTest::division_free) {
                    using T = typename A::T;
                    T tt[64];
                    std::uint8_t hb[64];
                    const RayA<A>& r0 = rays_[0];
                    const std::size_t base = std::size_t(v) * n_;
                    if (!row_hits(r0.o, r0.tmin, r0.tmax, dx_.data() + base, dy_.data() + base, dz_.data() + base, n_,
                                  f_.tris_[tri], hb, tt))
                        return 0;
                    for (std::uint64_t cm = cols; cm; cm &= cm - 1) {
                        const std::uint32_t h = std::uint32_t(__builtin_ctzll(cm));
                        if (hb[h]) {
                            hit |= std::uint64_t(1) << h;
                            t[h] = static_cast<double>(tt[h]);
                        }
                    }
                    return hit;
                }
            }
            for (std::uint64_t cm = cols; cm; cm &= cm - 1) {
                const std::uint32_t h = std::uint32_t(__builtin_ctzll(cm));
                if (rti(v * n_ + h, tri, t[h])) hit |= std::uint64_t(1) << h;
            }
            return hit;
        }

        void rti_rows(std::uint64_t rows, std::uint64_t cols, std::uint32_t tri, std::uint32_t n, std::uint64_t* hits,
                      double* t) override {
            if constexpr (kNative) {
                // all rows at once, as the front end's tracer tests them
                if (rti_of(f_.a_) == RtiTest::division_free) {
                    const RayA<A>& r0 = rays_[0];
                    tt_.resize(std::size_t(n) * n);
                    rows_hit_triangle(r0.o, r0.tmin, r0.tmax, dx_.data(), dy_.data(), dz_.data(), n, rows, cols,
                                      f_.tris_[tri], hits, tt_.data());
                    for (std::uint64_t rm = rows; rm; rm &= rm - 1) {
                        const std::size_t v = std::size_t(__builtin_ctzll(rm));
                        for (std::uint64_t m = hits[v]; m; m &= m - 1) {
                            const std::size_t i = v * n + std::size_t(__builtin_ctzll(m));
                            t[i] = static_cast<double>(tt_[i]);
                        }
                    }
                    return;
                }
            }
            GroupUnit::rti_rows(rows, cols, tri, n, hits, t);
        }

        bool rti_certain_miss(std::uint64_t rows, std::uint64_t cols, std::uint32_t tri) const override {
            if constexpr (kNative) {
                // (as the tracer: small masks are tested instead)
                if (rti_of(f_.a_) == RtiTest::division_free && boxes_.finite() &&
                    miss_proof_pays<typename A::T>(rows, cols)) {
                    const RayA<A>& r0 = rays_[0];
                    return rays_certainly_miss_triangle_native(r0.o, r0.tmin, r0.tmax, boxes_.of(rows, cols),
                                                               f_.tris_[tri]);
                }
            }
            return false;
        }

    private:
        const ComputeFunctional& f_;
        std::uint32_t n_ = 0;
        std::vector<PlaneA<A>> planes_;
        std::vector<RayA<A>> rays_;
        std::vector<typename A::T> dx_, dy_, dz_, tt_;  // (native formats)
        GroupDirectionBoxes<typename A::T> boxes_;
        std::vector<SphereHitRec> hits_;
        std::vector<SphereRun> runs_;
    };

    std::unique_ptr<GroupUnit> make_unit() const override { return std::make_unique<Unit>(*this); }

private:
    static constexpr bool kNative = std::is_same_v<A, ArithF32> || std::is_same_v<A, ArithF64>;
    A a_;
    bool pairless_;
    bool pairless_given_;  // the pair-less spheres are the trace's (Functional::create)
    SphereSoA<A> spheres_;
    std::vector<TriA<A>> tris_;
    SphereTree tree_;  // empty: every sphere tested
};

class TraceFunctional final : public Functional {
public:
    TraceFunctional() { mode_ = FunctionalMode::trace; }
    class Unit final : public GroupUnit {
    public:
        void load(const TraceGroup& g) override { g_ = &g; }
        const std::vector<SphereHitRec>& sphere_hits() const override { return g_->sphere_hits; }
        const std::vector<SphereRun>& pairless() const override { return g_->pairless; }
        bool rti(std::uint32_t, std::uint32_t, double&) override { return false; }
        std::uint64_t rti_row(std::uint32_t, std::uint64_t, std::uint32_t, double*) override { return 0; }
        bool rti_certain_miss(std::uint64_t, std::uint64_t, std::uint32_t) const override { return false; }

    private:
        const TraceGroup* g_ = nullptr;
    };
    std::unique_ptr<GroupUnit> make_unit() const override { return std::make_unique<Unit>(); }
};

class WrongRtiUnit final : public GroupUnit {
public:
    WrongRtiUnit(std::unique_ptr<GroupUnit> inner, std::shared_ptr<bool> fired)
        : inner_(std::move(inner)), fired_(std::move(fired)) {}
    void load(const TraceGroup& g) override { inner_->load(g); }
    const std::vector<SphereHitRec>& sphere_hits() const override { return inner_->sphere_hits(); }
    const std::vector<SphereRun>& pairless() const override { return inner_->pairless(); }
    bool rti(std::uint32_t ray, std::uint32_t tri, double& t) override {
        if (inner_->rti(ray, tri, t)) return true;
        if (*fired_) return false;
        *fired_ = true;
        t = 0.0;
        return true;
    }
    std::uint64_t rti_row(std::uint32_t v, std::uint64_t cols, std::uint32_t tri, double* t) override {
        std::uint64_t hit = inner_->rti_row(v, cols, tri, t);
        if (*fired_ || hit == cols) return hit;
        const std::uint32_t h = std::uint32_t(__builtin_ctzll(cols & ~hit));  // the first miss, in test order
        *fired_ = true;
        t[h] = 0.0;
        return hit | std::uint64_t(1) << h;
    }
    // Until the wrong answer is given, every test is made, so that it goes to the first miss.
    bool rti_certain_miss(std::uint64_t rows, std::uint64_t cols, std::uint32_t tri) const override {
        return *fired_ && inner_->rti_certain_miss(rows, cols, tri);
    }

private:
    std::unique_ptr<GroupUnit> inner_;
    std::shared_ptr<bool> fired_;
};

}  // namespace

std::unique_ptr<GroupUnit> with_wrong_rti(std::unique_ptr<GroupUnit> inner, std::shared_ptr<bool> fired) {
    return std::make_unique<WrongRtiUnit>(std::move(inner), std::move(fired));
}

std::unique_ptr<Functional> Functional::create(const Trace& t, const NumFormat& format, FunctionalMode mode, bool cull,
                                               bool pairless) {
    if (mode == FunctionalMode::trace) return std::make_unique<TraceFunctional>();
    // The pair-less spheres decide no ray-triangle test and no hit (their
    // triangles get no pair), only timing: a trace made in this format
    // carries exactly the ones these units would find, so they are taken
    // from it rather than found again; without culling (every sphere tested,
    // as the hardware does) they are found again.
    const bool given = cull && t.pairless && t.format == format;
    switch (format.kind) {
        case NumFormat::Kind::f32:
            return std::make_unique<ComputeFunctional<ArithF32>>(t, ArithF32{format.rti}, cull, pairless, given);
        case NumFormat::Kind::f64:
            return std::make_unique<ComputeFunctional<ArithF64>>(t, ArithF64{format.rti}, cull, pairless, given);
        case NumFormat::Kind::custom:
            return std::make_unique<ComputeFunctional<ArithSoft>>(t, ArithSoft{format, true}, cull, pairless, given);
    }
    return nullptr;
}

}  // namespace raplas::model
