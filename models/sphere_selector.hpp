// Per-ICC Selector on the Sphere Stream Link: an ICC with a ray group takes
// every sphere (each must be tested against its planes) into its Sphere
// FIFO; an ICC without a group this pass ignores the stream.
#pragma once

#include "fifo.hpp"

namespace raplas::model {

class SphereSelector {
public:
    struct Params {};
    struct Stats {
        std::uint64_t received = 0;
        std::uint64_t blocked_link_cycles = 0;  // cycles this ICC's full Sphere FIFO stopped the broadcast
    };
    explicit SphereSelector(const Params& p = {}) : params_(p) {}

    // (`fifo`: the Sphere FIFO, or the netlist's port on its channel)
    template <class SFifo>
    bool ready(bool active, const SFifo& fifo) const { return !active || !fifo.full(); }
    // `cycles` cycles in which this ICC's full Sphere FIFO stopped the broadcast.
    template <class SFifo>
    void note_blocked(SFifo& fifo, std::uint64_t cycles = 1) {
        stats_.blocked_link_cycles += cycles;
        fifo.note_full(cycles);
    }
    void receive(bool active, std::uint32_t sphere, SphereFifo& fifo) {
        if (!active) return;
        fifo.push(sphere);
    }
    void end_group(std::uint64_t received) { stats_.received += received; }
    const Stats& stats() const { return stats_; }
    const Params& params() const { return params_; }

private:
    Params params_;
    Stats stats_;
};

}  // namespace raplas::model
