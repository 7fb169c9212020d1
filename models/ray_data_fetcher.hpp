// Ray Data Fetcher: takes triangles from the Triangle FIFO and, for each,
// feeds the Ray-Triangle Intersector one (ray, triangle) pair per pipe per
// cycle for every ray (h, v) with v in the row mask and h in the column
// mask, rows first. A triangle popped in a cycle issues in that same cycle.
// A triangle with no pair (its sphere cut by row planes only or column
// planes only, kept under icc.triangle_select = any) holds the Fetcher for
// `empty_cycles` cycles, counting the one it is popped in, with nothing
// issued; with 0 it is dropped at no cost (docs/MODEL.md §3).
#pragma once

#include <algorithm>

#include "raplas/core/bits.hpp"
#include "fifo.hpp"
#include "ray_triangle_intersector.hpp"
#include "triangle_selector.hpp"

namespace raplas::model {

// The Ray Data Fetcher and RTI of one ICC in closed form, as a
// work-conserving queue (event mode, fifo_bound): a triangle selected in
// cycle c with m pairs is popped at the first free issue slot from c + 1 on
// and issues its pairs `pipes` per cycle, back to back with the triangle
// before; its last result leaves the RTI `rti_stages` cycles after its last
// pair. A triangle with no pair holds the Fetcher `empty_cycles` cycles
// counting its first (0: it takes no slot), as RayDataFetcher::tick does.
struct FetcherQueue {
    std::uint64_t next_cyc = 0;  // the next free issue slot: cycle and pipes used in it
    std::uint32_t next_used = 0;
    bool any = false;            // (false: free from the first cycle on)
    std::uint64_t done = 0;      // the last cycle the back end is busy
    struct Slot {
        std::uint64_t pop;   // the cycle the triangle leaves the Triangle FIFO
        std::uint64_t busy;  // RTI cycles with a pair entering that it adds
    };
    Slot take(std::uint64_t c, std::uint64_t m, std::uint32_t pipes, std::uint32_t rti_stages,
              std::uint32_t empty_cycles) {
        std::uint64_t start = c + 1;
        std::uint32_t used = 0;
        if (any && next_cyc >= start) {
            start = next_cyc;
            used = next_used;
        }
        if (used == pipes) {
            ++start;
            used = 0;
        }
        any = true;
        if (m == 0) {
            if (empty_cycles == 0) {
                next_cyc = start;
                next_used = used;
                done = std::max(done, start);
            } else {  // to the end of its last cycle: the next triangle starts a cycle later
                next_cyc = start + empty_cycles - 1;
                next_used = pipes;
                done = std::max(done, next_cyc);
            }
            return {start, 0};
        }
        const std::uint64_t total = used + m;
        const std::uint64_t end = start + (total - 1) / pipes;
        next_cyc = end;
        next_used = std::uint32_t((total - 1) % pipes + 1);
        done = end + rti_stages;
        return {start, (end - start + 1) - (used > 0 ? 1 : 0)};
    }
};

class RayDataFetcher {
public:
    struct Params {
        std::uint32_t empty_cycles = 1;
    };
    struct Stats {
        std::uint64_t triangles = 0;
        std::uint64_t empty_triangles = 0;  // ... of which with no (ray, triangle) pair
        std::uint64_t starved_cycles = 0;   // pass cycles in which no pair was issued
    };
    explicit RayDataFetcher(const Params& p) : params_(p) {}

    // A new group of N x N rays in buffer `buf`; `keep` (overlapped passes)
    // leaves the previous group's work in progress.
    void start_group(std::uint32_t n, std::uint8_t buf = 0, bool keep = false) {
        n_[buf] = n;
        if (keep) return;
        busy_ = false;
        empty_left_ = 0;
    }
    bool idle() const { return !busy_ && !empty_left_; }
    // Still working on a triangle of buffer `buf`.
    bool holds(std::uint8_t buf) const { return !idle() && cur_.buf == buf; }
    void add_starved(std::uint64_t cycles) { stats_.starved_cycles += cycles; }
    void note_triangle(bool empty) {
        ++stats_.triangles;
        stats_.empty_triangles += empty;
    }
    // Event-driven simulation: n triangles popped, `empty` of them with no pair.
    void note_triangles(std::uint64_t n, std::uint64_t empty) {
        stats_.triangles += n;
        stats_.empty_triangles += empty;
    }

    // One clock cycle: pops triangles from `in` (the Triangle FIFO) and
    // issues pairs to `rti` (can_issue(), issue()): the blocks themselves, or
    // the netlist's views (models/netlist/ray_data_fetcher.hpp).
    template <class In, class Rti>
    void tick(In& in, Rti& rti) {
        if (empty_left_) {  // still on a triangle with no pair
            --empty_left_;
            return;
        }
        while (rti.can_issue()) {
            if (!busy_) {
                if (in.empty()) break;
                cur_ = in.front();
                in.pop();
                const bool empty = !cur_.rows || !cur_.cols;
                note_triangle(empty);
                if (empty) {
                    if (params_.empty_cycles == 0) continue;
                    empty_left_ = params_.empty_cycles - 1;
                    break;
                }
                busy_ = true;
                rows_left_ = cur_.rows;
                cols_left_ = cur_.cols;
            }
            const std::uint32_t v = std::uint32_t(__builtin_ctzll(rows_left_));
            const std::uint32_t h = std::uint32_t(__builtin_ctzll(cols_left_));
            rti.issue({v * n_[cur_.buf] + h, cur_.tri, cur_.buf});
            cols_left_ &= cols_left_ - 1;
            if (!cols_left_) {
                rows_left_ &= rows_left_ - 1;
                cols_left_ = cur_.cols;
                if (!rows_left_) busy_ = false;
            }
        }
    }
    // Cycles of RTI work still held (current triangle only).
    std::uint64_t pending_pairs() const {
        if (!busy_) return 0;
        const std::uint64_t pc = std::uint64_t(bit_count(cur_.cols));
        return (std::uint64_t(bit_count(rows_left_)) - 1) * pc + std::uint64_t(bit_count(cols_left_));
    }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    std::uint32_t n_[2] = {0, 0};  // group size of each buffer
    bool busy_ = false;
    std::uint32_t empty_left_ = 0;  // cycles still held by a triangle with no pair
    TriWork cur_;
    std::uint64_t rows_left_ = 0, cols_left_ = 0;
    Stats stats_;
};

}  // namespace raplas::model
