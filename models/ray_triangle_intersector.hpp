// Ray-Triangle Intersector: R pipes (paper: 1) of L stages (paper: 25). A
// (ray, triangle) pair that enters in cycle c leaves in cycle c + L, where
// its result goes to the Min-distance Memory. It never stalls: the
// Min-distance Memory takes one result per pipe per cycle.
#pragma once

#include <algorithm>
#include <vector>

#include "functional.hpp"
#include "min_distance_memory.hpp"

namespace raplas::model {

// A (ray, triangle) pair; `buf` names the Ray Memory / Min-distance Memory
// buffer of its group (two when passes overlap, docs/MODEL.md §3).
struct RtiOp {
    std::uint32_t ray = 0, tri = 0;
    std::uint8_t buf = 0;
};

class RayTriangleIntersector {
public:
    struct Params {
        std::uint32_t pipes = 1;
        std::uint32_t stages = 25;
    };
    struct Stats {
        std::uint64_t tests = 0;
        std::uint64_t hits = 0;
        std::uint64_t busy_cycles = 0;  // cycles with at least one pair entering
    };
    explicit RayTriangleIntersector(const Params& p)
        : params_(p), ops_(std::size_t(p.stages) * p.pipes), count_(p.stages, 0) {}

    void start_group() {
        std::fill(count_.begin(), count_.end(), 0u);
        idx_ = 0;
        inflight_ = 0;
        inflight_buf_[0] = inflight_buf_[1] = 0;
    }
    bool empty() const { return inflight_ == 0; }
    std::uint32_t inflight() const { return inflight_; }
    std::uint32_t inflight(std::uint8_t buf) const { return inflight_buf_[buf]; }
    // Start of a cycle: the pairs that entered `stages` cycles ago leave, each
    // to its buffer's group unit and Min-distance Memory.
    void retire(GroupUnit* const units[2], MinDistanceMemory* const mems[2]) {
        retire_with([&](const RtiOp& op, double& t) { return units[op.buf]->rti(op.ray, op.tri, t); },
                    [&](const RtiOp& op, double t) { mems[op.buf]->update(op.ray, t, op.tri); });
    }
    // The same with the test made by test(op, t) (true: a hit at t) and a
    // hit recorded by record(op, t) (the netlist's ports on the Ray Memory
    // and the Min-distance Memory).
    template <class Test, class Record>
    void retire_with(Test&& test, Record&& record) {
        const std::uint32_t n = count_[idx_];
        const RtiOp* slot = &ops_[std::size_t(idx_) * params_.pipes];
        for (std::uint32_t i = 0; i < n; ++i) {
            double t;
            if (test(slot[i], t)) {
                ++stats_.hits;
                record(slot[i], t);
            }
            --inflight_buf_[slot[i].buf];
        }
        inflight_ -= n;
        count_[idx_] = 0;
    }
    void retire(GroupUnit& unit, MinDistanceMemory& mem) {  // one buffer
        GroupUnit* const u[2] = {&unit, &unit};
        MinDistanceMemory* const m[2] = {&mem, &mem};
        retire(u, m);
    }
    // Event-driven simulation: `tests` pairs, `hits` of them hits, entering
    // in `busy` distinct cycles, accounted at once.
    void account(std::uint64_t tests, std::uint64_t hits, std::uint64_t busy) {
        stats_.tests += tests;
        stats_.hits += hits;
        stats_.busy_cycles += busy;
    }
    bool can_issue() const { return !stuck_ && count_[idx_] < params_.pipes; }
    // Fault injection (sim.fault = stuck_rti): takes no pair from now on.
    void set_stuck(bool s) { stuck_ = s; }
    bool stuck() const { return stuck_; }
    void issue(const RtiOp& op) {
        ops_[std::size_t(idx_) * params_.pipes + count_[idx_]++] = op;
        ++inflight_;
        ++inflight_buf_[op.buf];
        ++stats_.tests;
    }
    // End of a cycle.
    void advance() {
        if (count_[idx_]) ++stats_.busy_cycles;
        idx_ = idx_ + 1 == params_.stages ? 0 : idx_ + 1;
    }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    std::vector<RtiOp> ops_;             // stages x pipes slots
    std::vector<std::uint32_t> count_;   // pairs in each stage's slot
    std::uint32_t idx_ = 0, inflight_ = 0;
    std::uint32_t inflight_buf_[2] = {0, 0};
    bool stuck_ = false;
    Stats stats_;
};

}  // namespace raplas::model
