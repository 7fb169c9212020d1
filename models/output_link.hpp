// Output Link: at the end of a pass each ICC sends its group's Min-distance
// Memory (one entry per ray) back to the host.
#pragma once

#include <cstdint>

namespace raplas::model {

class OutputLink {
public:
    struct Params {
        std::uint32_t entry_bytes = 6;
    };
    struct Stats {
        std::uint64_t groups = 0;
        std::uint64_t records = 0;
        std::uint64_t bytes = 0;
    };
    explicit OutputLink(const Params& p) : params_(p) {}
    void send(std::uint64_t rays) {
        ++stats_.groups;
        stats_.records += rays;
        stats_.bytes += rays * params_.entry_bytes;
    }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    Stats stats_;
};

}  // namespace raplas::model
