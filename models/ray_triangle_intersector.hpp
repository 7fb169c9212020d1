// Ray-Triangle Intersector: R pipes (paper: 1) of L stages (paper: 25). A
// (ray, triangle) pair that enters in cycle c leaves in cycle c + L, where
// its result goes to the Min-distance Memory. It never stalls: the
// Min-distance Memory takes one result per pipe per cycle.
#pragma once

#include <vector>

#include "functional.hpp"
#include "min_distance_memory.hpp"

namespace raplas::model {

struct RtiOp {
    std::uint32_t ray = 0, tri = 0;
};

class RayTriangleIntersector : public sc_core::sc_module {
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
    RayTriangleIntersector(sc_core::sc_module_name n, const Params& p)
        : sc_core::sc_module(n), params_(p), ring_(p.stages) {
        for (auto& s : ring_) s.reserve(p.pipes);
    }

    void start_group() {
        for (auto& s : ring_) s.clear();
        idx_ = 0;
        inflight_ = 0;
    }
    bool empty() const { return inflight_ == 0; }
    std::uint32_t inflight() const { return inflight_; }
    // Start of a cycle: the pairs that entered `stages` cycles ago leave.
    void retire(GroupUnit& unit, MinDistanceMemory& mem) {
        auto& slot = ring_[idx_];
        for (const RtiOp& op : slot) {
            double t;
            if (unit.rti(op.ray, op.tri, t)) {
                ++stats_.hits;
                mem.update(op.ray, t, op.tri);
            }
        }
        inflight_ -= std::uint32_t(slot.size());
        slot.clear();
    }
    bool can_issue() const { return ring_[idx_].size() < params_.pipes; }
    void issue(const RtiOp& op) {
        ring_[idx_].push_back(op);
        ++inflight_;
        ++stats_.tests;
    }
    // End of a cycle.
    void advance() {
        if (!ring_[idx_].empty()) ++stats_.busy_cycles;
        idx_ = idx_ + 1 == params_.stages ? 0 : idx_ + 1;
    }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    std::vector<std::vector<RtiOp>> ring_;
    std::uint32_t idx_ = 0, inflight_ = 0;
    Stats stats_;
};

}  // namespace raplas::model
