// sim.estimate = "fifo_bound": each pass timed in closed form from the trace
// with unbounded Triangle, PlaneID and First-Triangle-ID FIFOs. It rests on
// the same facts as the event mode (event_engine.cpp):
//  1. With a PlaneID FIFO that never fills, no PSI is ever held, so every
//     ICC's sphere side is the shared one: the Decoder's `decided` count at
//     the start of every cycle is the same in every ICC and every pass of a
//     group size N (the Sphere FIFO keeps its configured depth; it is part of
//     that shared side).
//  2. With Triangle FIFOs that never fill, only that count can hold the
//     triangle stream: triangle i is sent in the first cycle after triangle
//     i-1 (and not before link.triangle_lag_cycles) in which every ICC has
//     decided its sphere. These cycles, too, are the same in every pass.
//  3. Behind the Triangle Selector each ICC is a work-conserving queue: a
//     triangle selected in cycle c with m = |rows|·|cols| pairs is popped at
//     the first free issue slot from c+1 on and issues R pairs per cycle; the
//     last result leaves the RTI L cycles after the last pair.
// A pass ends in the cycle after the last record was sent and the last
// result left. A full FIFO or a held PSI can only delay a send or a pop, and
// a later selection never finishes a queue earlier, so the result is a lower
// bound of the exact count, and equal to it when no Triangle FIFO, PlaneID
// FIFO or First-Triangle-ID FIFO fills (tests/bound_fifo.py checks both).
#include <algorithm>

#include "raplas/core/bits.hpp"
#include "top.hpp"

namespace raplas::model {

const Top::BoundSchedule& Top::bound_schedule(std::uint32_t n) {
    for (const auto& b : bound_schedules_)
        if (b.n == n) return b;
    const std::uint32_t S = std::uint32_t(sphere_memory.size());
    const std::uint64_t T = triangle_memory.size();
    // The shared sphere side, stepped as in the event mode with no hits:
    // first_decided[s] is the first cycle at whose start sphere s is decided.
    SphereFifo& rf = *ref_fifo_;
    const Decoder& rd = *ref_decoder_;
    start_shared_side(n);
    std::vector<std::uint64_t> first_decided(S);
    BoundSchedule b;
    b.n = n;
    std::uint32_t sent = 0, known = 0;
    for (std::uint64_t cycle = 0;; ++cycle) {
        for (; known < rd.decided(); ++known) first_decided[known] = cycle;
        if (known == S) break;
        const bool send = sent < S && !rf.full();
        const std::uint32_t s = sent;
        if (send && ++sent == S) b.spheres_sent_by = cycle + 1;
        tick_shared_side(sent < S);
        if (send) rf.push(s);
    }
    b.tri_cycle.resize(T);
    std::uint64_t next = cfg_.triangle_lag_cycles;
    for (std::uint64_t i = 0; i < T; ++i) {
        const std::uint64_t c = std::max(next, first_decided[triangle_memory.sphere_of(std::uint32_t(i))]);
        b.tri_cycle[i] = c;
        next = c + 1;
    }
    bound_schedules_.push_back(std::move(b));
    return bound_schedules_.back();
}

std::uint64_t Top::run_pass_bound(const Host::Pass& p) {
    const std::uint32_t n = groups_.group(p.begin).n;
    const BoundSchedule& b = bound_schedule(n);
    const std::uint32_t pipes = cfg_.icc.rti.pipes, stages = cfg_.icc.rti.stages;
    const std::uint32_t empty_cycles = cfg_.icc.fetcher.empty_cycles;
    const bool keep_pairless = cfg_.icc.decoder.select == TriangleSelect::any;
    std::uint64_t end_cycle = std::max<std::uint64_t>(b.spheres_sent_by, b.tri_cycle.empty() ? 0 : b.tri_cycle.back() + 1);
    // Each ICC's Ray Data Fetcher and RTI as a work-conserving queue: empty at
    // the start of a pass, or (overlapped passes) what the previous pass left.
    std::vector<EventBack>& backs = event_back_;
    if (!cfg_.overlap_passes || backs.size() != iccs.size()) backs.assign(iccs.size(), EventBack{});
    std::uint64_t prev_done = 0;
    for (const EventBack& e : backs) prev_done = std::max(prev_done, e.done);
    std::uint64_t all_done = prev_done;
    for (std::uint32_t gi = p.begin; gi < p.end; ++gi) {
        FetcherQueue& back = backs[gi - p.begin];
        // The spheres the Decoder queues, in stream order; each triangle is
        // selected in the cycle it is sent.
        const TraceGroup& g = groups_.group(gi);
        KeptSpheres kept(g.sphere_hits, keep_pairless ? &g.pairless : nullptr);
        while (kept.next()) {
            const std::uint64_t m = std::uint64_t(bit_count(kept.rows)) * std::uint64_t(bit_count(kept.cols));
            const std::uint32_t first = trace_.first_tri[kept.sphere];
            for (std::uint32_t tri = first; tri < first + trace_.tri_count[kept.sphere]; ++tri)
                back.take(b.tri_cycle[tri], m, pipes, stages, empty_cycles);
        }
        all_done = std::max(all_done, back.done);
    }
    // The pass ends when its streams are done and its work (or, overlapped,
    // the previous pass's) has left the RTIs.
    end_cycle = std::max(end_cycle, (p.drain ? all_done : prev_done) + 1);
    if (cfg_.overlap_passes)
        for (EventBack& e : backs) shift_back(e, end_cycle);
    return end_cycle;
}

}  // namespace raplas::model
