// The functional half of the intersector models: the core library's
// plane-sphere and ray-triangle tests in the configured number format. The
// timing blocks call these, so timing can never change an answer.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "raplas/frontend/trace_io.hpp"

namespace raplas::model {

// Per-ICC unit: the ray group loaded into the ICC's Plane Memory and Ray Memory.
class GroupUnit {
public:
    virtual ~GroupUnit() = default;
    virtual void load(const TraceGroup& g) = 0;
    // Plane-Sphere Intersectors' results for the loaded group: every sphere
    // cut by a row and a column plane, ascending, with its masks.
    virtual const std::vector<SphereHitRec>& sphere_hits() const = 0;
    // ... and the spheres cut by row planes only or column planes only, as
    // runs (empty unless the functional model was made for them).
    virtual const std::vector<SphereRun>& pairless() const = 0;
    // Ray-Triangle Intersector: true and t when ray (v*N+h) hits the triangle.
    virtual bool rti(std::uint32_t ray, std::uint32_t tri, double& t) = 0;
    // The same test for the rays (v, h) of row v, h in `cols`, against one
    // triangle, in ascending h: the mask of those that hit, t[h] set for each.
    // Answers are rti()'s, bit for bit.
    virtual std::uint64_t rti_row(std::uint32_t v, std::uint64_t cols, std::uint32_t tri, double* t) = 0;
    // True only with a proof that no ray of rows x cols hits the triangle (rti_row would return 0
    // for every row): the caller may skip those tests. False when it cannot tell.
    virtual bool rti_certain_miss(std::uint64_t rows, std::uint64_t cols, std::uint32_t tri) const = 0;

    // rti_row for every row v of `rows` of an n x n group: hits[v] its mask,
    // t[v * n + h] the distance of each hit. A unit may answer all rows at
    // once (the same answers); by default, row by row.
    virtual void rti_rows(std::uint64_t rows, std::uint64_t cols, std::uint32_t tri, std::uint32_t n,
                          std::uint64_t* hits, double* t) {
        for (std::uint64_t rm = rows; rm; rm &= rm - 1) {
            const std::uint32_t v = std::uint32_t(__builtin_ctzll(rm));
            hits[v] = rti_row(v, cols, tri, t + std::size_t(v) * n);
        }
    }

    // The Ray-Triangle Intersector's tests of one selected triangle against
    // the rays of rows x cols (groups of n x n rays), in test order (rows
    // ascending, then columns): hit(ray, t) for each hit; returns their number.
    template <class F>
    std::uint64_t rti_tests(std::uint64_t rows, std::uint64_t cols, std::uint32_t tri, std::uint32_t n, F&& hit) {
        if (!rows || !cols || rti_certain_miss(rows, cols, tri)) return 0;
        std::uint64_t hits = 0;
        std::uint64_t hm[64];
        thread_local std::vector<double> t;
        t.resize(std::size_t(n) * n);
        rti_rows(rows, cols, tri, n, hm, t.data());
        for (std::uint64_t rm = rows; rm; rm &= rm - 1) {
            const std::uint32_t v = std::uint32_t(__builtin_ctzll(rm));
            for (std::uint64_t m = hm[v]; m; m &= m - 1) {
                const std::uint32_t h = std::uint32_t(__builtin_ctzll(m));
                ++hits;
                hit(v * n + h, t[std::size_t(v) * n + h]);
            }
        }
        return hits;
    }
};

// Fault injection (sim.fault = wrong_rti): `inner` with one wrong answer. The
// first ray-triangle test that misses, in this unit or any other sharing
// `fired`, reports a hit at distance 0 instead; every other call is inner's.
std::unique_ptr<GroupUnit> with_wrong_rti(std::unique_ptr<GroupUnit> inner, std::shared_ptr<bool> fired);

enum class FunctionalMode { compute, trace };

// Shared, read-only: the scene's spheres and triangles converted to the format.
class Functional {
public:
    virtual ~Functional() = default;
    virtual std::unique_ptr<GroupUnit> make_unit() const = 0;
    FunctionalMode mode() const { return mode_; }

    // compute: the core library in `format`; trace: masks from the trace
    // (no per-test arithmetic; final hits cannot be checked). pairless: the
    // units also find the pair-less spheres (compute) or take them from the
    // trace (which must carry them).
    static std::unique_ptr<Functional> create(const Trace& t, const NumFormat& format, FunctionalMode mode,
                                              bool cull = true, bool pairless = false);

protected:
    FunctionalMode mode_ = FunctionalMode::compute;
};

}  // namespace raplas::model
