// Triangle Selector: watches the Triangle Stream Link and keeps the
// triangles of spheres its PSIs hit (head of the First-Triangle-ID FIFO),
// with their plane masks, in the Triangle FIFO; discards the rest. It can
// only judge a triangle whose sphere has been decided: until then it holds
// the broadcast (docs/MODEL.md, "triangle stream behind the sphere stream").
#pragma once

#include "decoder.hpp"

namespace raplas::model {

struct TriWork {
    std::uint32_t tri = 0;
    std::uint8_t buf = 0;  // the group's Ray Memory / Min-distance Memory buffer (in tri's padding: 24 bytes)
    std::uint64_t rows = 0, cols = 0;
    TriWork() = default;
    TriWork(std::uint32_t t, std::uint64_t r, std::uint64_t c, std::uint8_t b = 0) : tri(t), buf(b), rows(r), cols(c) {}
};
static_assert(sizeof(TriWork) == 24);

enum class StallPolicy { any_full, needed_full };

class TriangleSelector {
public:
    struct Params {
        StallPolicy policy = StallPolicy::any_full;
        // link.stall_latency (+ _per_icc x ICCs): cycles its hold takes to
        // stop the Triangle Stream Link. The hold rises at depth - latency
        // entries, so that the records already on the link still fit.
        std::uint32_t stall_latency = 0;
        // link.resume_occupancy: once risen, the hold falls only when the
        // FIFO has drained to this occupancy; -1 = as soon as it is below the
        // rising threshold (no hysteresis).
        std::int64_t resume_occupancy = -1;
        // Occupancy at the start of a cycle from which the hold is up, and
        // the one at or below which it falls, for a FIFO of `depth`.
        std::uint64_t hold_at(std::uint32_t depth) const { return std::uint64_t(depth) - stall_latency; }
        std::uint64_t resume_at(std::uint32_t depth) const {
            return resume_occupancy < 0 ? hold_at(depth) - 1 : std::uint64_t(resume_occupancy);
        }
        // Whether the hold of a stopped link is anything but "the FIFO is full" in the same cycle.
        bool plain() const { return stall_latency == 0 && resume_occupancy < 0; }
    };
    struct Stats {
        std::uint64_t selected = 0;
        std::uint64_t discarded = 0;
        std::uint64_t blocked_fifo_full = 0;  // cycles this ICC stopped the broadcast: Triangle FIFO full
        std::uint64_t blocked_undecided = 0;  // ... its sphere not decided yet
        std::uint64_t blocked_alone = 0;      // of blocked_fifo_full, cycles no other ICC's FIFO held the link
    };
    explicit TriangleSelector(const Params& p) : params_(p) {}

    // (The FIFOs are the blocks themselves, or the netlist's ports on their channels.)
    template <class FirstIds>
    static bool wants(std::uint32_t sphere, const FirstIds& first_ids) {
        return !first_ids.empty() && first_ids.front().sphere == sphere;
    }
    // Can this ICC take triangle `tri` of sphere `sphere` this cycle? (Its
    // Triangle FIFO's hold: full, with Params::plain.)
    template <class FirstIds, class TriFifo>
    bool ready(bool active, std::uint32_t sphere, std::uint32_t decided, const FirstIds& first_ids,
               const TriFifo& tri_fifo) const {
        return ready_held(active, sphere, decided, first_ids, tri_fifo.full());
    }
    // The same with the hold given: the FIFO's, as the stall pipeline delivers it.
    template <class FirstIds>
    bool ready_held(bool active, std::uint32_t sphere, std::uint32_t decided, const FirstIds& first_ids,
                    bool held) const {
        if (!active) return true;
        if (decided <= sphere) return false;
        if (!held) return true;
        return params_.policy == StallPolicy::needed_full && !wants(sphere, first_ids);
    }
    // Its Triangle FIFO holds the link (the stall anatomy's wire): it is not
    // ready for the triangle offered although that triangle's sphere is decided.
    static bool fifo_holds(bool ready, std::uint32_t decided, std::uint32_t sphere) { return !ready && decided > sphere; }
    // The hold at the start of a cycle with `occupancy` entries, `before` the
    // hold at the start of the cycle before (false at a pass's first cycle).
    bool hold(std::uint64_t occupancy, std::uint32_t depth, bool before) const {
        return occupancy >= params_.hold_at(depth) || (before && occupancy > params_.resume_at(depth));
    }
    template <class TriFifo>
    void note_blocked(std::uint32_t sphere, std::uint32_t decided, TriFifo& tri_fifo) {
        if (decided <= sphere) ++stats_.blocked_undecided;
        else {
            ++stats_.blocked_fifo_full;
            tri_fifo.note_full();
        }
    }
    template <class PlaneIds, class FirstIds, class TriFifo>
    void receive(bool active, std::uint32_t tri, std::uint32_t sphere, PlaneIds& plane_ids, FirstIds& first_ids,
                 TriFifo& tri_fifo, std::uint8_t buf = 0) {
        if (!active) return;
        if (!wants(sphere, first_ids)) return;  // discarded (counted at the end of the pass)
        const PlaneIdEntry& p = plane_ids.front();
        tri_fifo.push({tri, p.rows, p.cols, buf});
        ++stats_.selected;
        const FirstTriEntry& f = first_ids.front();
        if (tri + 1 == f.first + f.count) {
            plane_ids.pop();
            first_ids.pop();
        }
    }
    void add_blocked_undecided(std::uint64_t cycles) { stats_.blocked_undecided += cycles; }
    // `cycles` of its FIFO-full blocks in which it was the only ICC whose FIFO held the link.
    void note_alone(std::uint64_t cycles = 1) { stats_.blocked_alone += cycles; }
    // Event-driven simulation: triangle `tri` of the head sphere taken; pops
    // the head entry after its last triangle. Returns its plane masks. (The
    // caller counts it: add_selected.)
    static PlaneIdEntry take(std::uint32_t tri, Fifo<PlaneIdEntry>& plane_ids, Fifo<FirstTriEntry>& first_ids) {
        const PlaneIdEntry p = plane_ids.front();
        const FirstTriEntry& f = first_ids.front();
        if (tri + 1 == f.first + f.count) {
            plane_ids.pop();
            first_ids.pop();
            // (the next heads were queued long ago: fetch the next one while
            // the stream moves on, and the cache line after it, which the
            // next few pops reach, well ahead of them)
            plane_ids.prefetch(0);
            first_ids.prefetch(0);
            plane_ids.prefetch(64 / sizeof(PlaneIdEntry));
            first_ids.prefetch(64 / sizeof(FirstTriEntry) + 1);
        }
        return p;
    }
    // Event-driven simulation: `n` triangles taken.
    void add_selected(std::uint64_t n) { stats_.selected += n; }
    void note_blocked_full(Fifo<TriWork>& tri_fifo, std::uint64_t cycles = 1) {
        stats_.blocked_fifo_full += cycles;
        tri_fifo.note_full(cycles);
    }
    // End of a pass in which `received` triangles passed this ICC.
    void end_group(std::uint64_t received, std::uint64_t selected_before) {
        stats_.discarded += received - (stats_.selected - selected_before);
    }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    Stats stats_;
};

}  // namespace raplas::model
