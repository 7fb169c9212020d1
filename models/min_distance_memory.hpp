// Min-distance Memory: per ray of the ICC's group, the nearest triangle id
// and its distance (paper Figure 7: 48 bit x 16). Ties go to the smaller
// triangle id, so the result does not depend on the order of arrival.
#pragma once

#include <vector>

#include "raplas/core/intersect.hpp"

namespace raplas::model {

class MinDistanceMemory {
public:
    struct Params {
        std::uint32_t entry_bytes = 6;  // 24-bit triangle id + 24-bit distance
    };
    struct Stats {
        std::uint64_t updates = 0;
    };
    explicit MinDistanceMemory(const Params& p) : params_(p) {}

    void reset(std::size_t rays) { hits_.assign(rays, Hit{}); }
    void update(std::uint32_t ray, double t, std::uint32_t tri) {
        keep_nearest(hits_[ray], t, std::int32_t(tri));
        ++stats_.updates;
    }
    void set(std::vector<Hit> hits) { hits_ = std::move(hits); }
    // The result of `updates` updates made elsewhere (event-driven simulation).
    void set(std::vector<Hit> hits, std::uint64_t updates) {
        hits_ = std::move(hits);
        stats_.updates += updates;
    }
    const std::vector<Hit>& hits() const { return hits_; }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    std::vector<Hit> hits_;
    Stats stats_;
};

}  // namespace raplas::model
