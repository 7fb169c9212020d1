// Decoder: turns a PSI result into work. A sphere to be kept goes into the
// PlaneID FIFO (its plane masks, decoded to plane/ray ids through the Decoder
// Table) and the First-Triangle-ID FIFO (its triangle range); both move in
// lockstep. Which spheres are kept is the reading of the paper's Triangle
// Selector (icc.triangle_select, docs/MODEL.md §3): `both` keeps a sphere hit
// by at least one row plane and one column plane (Step 6), `any` every sphere
// at least one valid ray-plane cuts (§4's "if it finds no intersected planes,
// the triangle data are discarded"); a sphere cut by rows only or columns
// only then gives its triangles no (ray, triangle) pair. Every decided
// sphere, kept or not, advances the `decided` count the Triangle Selector
// waits on.
#pragma once

#include <algorithm>
#include <vector>

#include "fifo.hpp"
#include "plane_sphere_intersector.hpp"

namespace raplas::model {

struct PlaneIdEntry {
    std::uint64_t rows = 0, cols = 0;
};
struct FirstTriEntry {
    std::uint32_t sphere = 0, first = 0, count = 0;
};

enum class TriangleSelect { both, any };
// Its name in configs, traces (--triangle-select) and reports.
inline const char* triangle_select_name(TriangleSelect s) { return s == TriangleSelect::any ? "any" : "both"; }

// Does the Decoder queue this PSI result under reading `sel`?
inline bool queued(const PsiResult& r, TriangleSelect sel) {
    return (r.rows && r.cols) || (sel == TriangleSelect::any && r.cut);
}

// The spheres a Decoder keeps for a group, in stream order: the hit spheres
// (with their masks) merged with, under the any-plane reading, the runs of
// pair-less spheres (masks 0). next() moves to the next one; false at the end.
class KeptSpheres {
public:
    KeptSpheres() = default;
    // runs: null under the row-and-column reading
    KeptSpheres(const std::vector<SphereHitRec>& hits, const std::vector<SphereRun>* runs) : hits_(&hits), runs_(runs) {}
    bool next() {
        const std::uint32_t hs = hi_ < hits_->size() ? (*hits_)[hi_].sphere : kNone;
        const std::uint32_t rs = runs_ && ri_ < runs_->size() ? std::max((*runs_)[ri_].first, in_run_) : kNone;
        if (hs == kNone && rs == kNone) return false;
        if (hs < rs) {
            sphere = hs;
            rows = (*hits_)[hi_].rows;
            cols = (*hits_)[hi_].cols;
            ++hi_;
        } else {
            sphere = rs;
            rows = cols = 0;
            in_run_ = rs + 1;
            if (in_run_ >= (*runs_)[ri_].end()) {
                ++ri_;
                in_run_ = 0;
            }
        }
        return true;
    }
    // Moves to just before the first kept sphere from s on: next() gives it.
    void seek(std::uint32_t s) {
        hi_ = std::size_t(first_hit_from(*hits_, s) - hits_->begin());
        in_run_ = 0;
        if (!runs_) return;
        ri_ = std::size_t(first_run_from(*runs_, s) - runs_->begin());
        if (ri_ < runs_->size() && (*runs_)[ri_].first < s) in_run_ = s;
    }
    // After next() gave a sphere of a run of pair-less spheres: how many of
    // that run follow it; skip(n) passes n of them (n <= run_left()).
    std::uint32_t run_left() const { return in_run_ ? (*runs_)[ri_].end() - in_run_ : 0; }
    void skip(std::uint32_t n) {
        in_run_ += n;
        if (in_run_ >= (*runs_)[ri_].end()) {
            ++ri_;
            in_run_ = 0;
        }
    }
    std::uint32_t sphere = 0;
    std::uint64_t rows = 0, cols = 0;

private:
    static constexpr std::uint32_t kNone = ~std::uint32_t(0);
    const std::vector<SphereHitRec>* hits_ = nullptr;
    const std::vector<SphereRun>* runs_ = nullptr;
    std::size_t hi_ = 0, ri_ = 0;
    std::uint32_t in_run_ = 0;  // next sphere of run ri_, when past its first
};

class Decoder {
public:
    struct Params {
        // (the machine configs' default is `any`, docs/MODEL.md §3; a config
        // built in code, as the tests' hand-made traces, starts from `both`)
        TriangleSelect select = TriangleSelect::both;
    };
    struct Stats {
        std::uint64_t decided = 0;
        std::uint64_t sphere_hits = 0;  // spheres queued (kept)
        std::uint64_t pairless = 0;     // ... of which cut by row planes only or column planes only (any)
        std::uint64_t full_cycles = 0;  // a hit could not be queued (FIFOs full)
    };
    explicit Decoder(const Params& p) : params_(p) {}

    void start_group() { decided_ = 0; }
    void end_group() { stats_.decided += decided_; }
    void set_decided(std::uint32_t d) { decided_ = d; }
    void note_hit(bool pairless, std::uint64_t n = 1) {
        stats_.sphere_hits += n;
        stats_.pairless += pairless ? n : 0;
    }
    std::uint32_t decided() const { return decided_; }
    // n cycles of tick() holding (a result to queue, a FIFO full).
    void note_held(std::uint64_t n) { stats_.full_cycles += n; }
    template <class PlaneIds, class FirstIds>
    void note_held(std::uint64_t n, PlaneIds& plane_ids, FirstIds& first_ids) {
        note_held(n);
        if (plane_ids.full()) plane_ids.note_full(n);
        if (first_ids.full()) first_ids.note_full(n);
    }

    // Does the PSI hold this cycle? Its result is to be queued and the
    // PlaneID or First-Triangle-ID FIFO is full (after the Triangle
    // Selector's pop of this cycle): what tick() returns, without its effects.
    template <class Psi, class PlaneIds, class FirstIds>
    bool holds(const Psi& psi, const PlaneIds& plane_ids, const FirstIds& first_ids) const {
        return psi.has_output() && queued(psi.output(), params_.select) && (plane_ids.full() || first_ids.full());
    }
    // One clock cycle: takes the PSI's result, if any, and queues it when it
    // is kept. Returns true when the PSI must hold this cycle. The
    // neighbours are the blocks themselves (event engine) or the netlist's
    // views of its ports (models/netlist/decoder_module.hpp).
    template <class Psi, class PlaneIds, class FirstIds, class SphereInfo>
    bool tick(Psi& psi, PlaneIds& plane_ids, FirstIds& first_ids, const SphereInfo& info) {
        if (!psi.has_output()) return false;
        const PsiResult& r = psi.output();
        if (queued(r, params_.select)) {
            if (plane_ids.full() || first_ids.full()) {
                note_held(1, plane_ids, first_ids);
                return true;
            }
            plane_ids.push({r.rows, r.cols});
            first_ids.push(info.entry(r.sphere));
            note_hit(!(r.rows && r.cols));
        }
        decided_ = r.sphere + 1;
        psi.pop_output();
        return false;
    }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    std::uint32_t decided_ = 0;
    Stats stats_;
};

}  // namespace raplas::model
