// Host: loads the memories and hands ray groups to the ICCs in passes. A
// pass gives each ICC at most one group; all primary groups are issued
// before any shadow group, because a shadow group's origin is a primary hit
// (docs/MODEL.md, "passes"). With overlapped passes (double-buffered Ray and
// Min-distance Memories) a pass's streams start while the previous pass's
// Ray Data Fetchers and RTIs drain; the last pass of each phase drains.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace raplas::model {

class Host {
public:
    struct Params {
        std::uint32_t iccs = 1;
        std::uint64_t pass_overhead_cycles = 0;  // per pass: loading planes/rays, reading results
        bool overlap_passes = false;
    };
    struct Stats {
        std::uint64_t passes = 0;
        std::uint64_t primary_passes = 0;
        std::uint64_t groups = 0;
    };
    explicit Host(const Params& p) : params_(p) {}

    // Pass p holds group indices [begin, end) of the issue order. `drain`:
    // the pass ends only when every ICC has finished all its work (always
    // without overlap; with it, the last pass of each phase), else once its
    // streams are done and the previous pass's work has drained.
    struct Pass {
        std::uint32_t begin = 0, end = 0;
        bool primary = true;
        bool drain = true;
    };
    static std::vector<Pass> plan(const Params& params, std::uint32_t primary_groups, std::uint32_t total_groups) {
        std::vector<Pass> passes;
        auto add = [&](std::uint32_t from, std::uint32_t to, bool primary) {
            for (std::uint32_t b = from; b < to; b += params.iccs)
                passes.push_back({b, std::min(to, b + params.iccs), primary});
        };
        add(0, primary_groups, true);
        add(primary_groups, total_groups, false);
        for (std::size_t i = 0; i < passes.size(); ++i)
            passes[i].drain = !params.overlap_passes || i + 1 == passes.size() || passes[i + 1].primary != passes[i].primary;
        return passes;
    }
    std::vector<Pass> plan(std::uint32_t primary_groups, std::uint32_t total_groups) {
        std::vector<Pass> passes = plan(params_, primary_groups, total_groups);
        stats_.passes = passes.size();
        stats_.groups = total_groups;
        stats_.primary_passes = 0;
        for (const auto& p : passes) stats_.primary_passes += p.primary;
        return passes;
    }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    Stats stats_;
};

}  // namespace raplas::model
