// Plane-Sphere Intersectors: P fully pipelined pipes of L stages (paper:
// 32 pipes, 10 stages). A sphere's 2N plane tests are issued over
// ceil(2N/P) cycles; its row/column hit masks leave the last stage
// L cycles after its last batch entered. When the Decoder cannot take a
// result the whole pipe holds (no stage advances, nothing is issued).
#pragma once

#include <algorithm>
#include <vector>

#include "fifo.hpp"
#include "functional.hpp"

namespace raplas::model {

struct PsiResult {
    std::uint32_t sphere = 0;
    std::uint64_t rows = 0, cols = 0;  // of a sphere cut by a row and a column plane; else 0
    bool cut = false;                  // some valid plane cuts it (rows or cols, or a pair-less sphere)
    std::uint64_t ready = 0;  // pipe-local time at which it leaves the last stage
};

class PlaneSphereIntersector {
public:
    struct Params {
        std::uint32_t pipes = 32;
        std::uint32_t stages = 10;
    };
    struct Stats {
        std::uint64_t spheres = 0;        // spheres tested
        std::uint64_t plane_tests = 0;
        std::uint64_t busy_cycles = 0;    // cycles with a batch entering the pipes
        std::uint64_t stall_cycles = 0;   // held because the Decoder's FIFOs were full
        std::uint64_t starved_cycles = 0; // input slot free but the Sphere FIFO empty
    };

    explicit PlaneSphereIntersector(const Params& p) : params_(p) {}

    // `hits`: the group's spheres cut by a row and a column plane, ascending
    // (the functional result of the pipes, see GroupUnit::sphere_hits);
    // `pairless`: those cut by row planes only or column planes only, when
    // known (the Decoder needs them under icc.triangle_select = any).
    void start_group(std::uint32_t planes, const std::vector<SphereHitRec>* hits,
                     const std::vector<SphereRun>* pairless = nullptr) {
        planes_ = planes;
        batches_ = (planes + params_.pipes - 1) / params_.pipes;
        if (batches_ == 0) batches_ = 1;
        ring_.assign(params_.stages + 2, PsiResult{});
        head_ = tail_ = count_ = 0;
        t_ = 0;
        next_issue_ = 0;
        hits_ = hits;
        pairless_ = pairless;
        cursor_ = run_cursor_ = 0;
        next_sphere_ = 0;
        group_spheres_ = 0;
    }
    // End of a pass: figures that follow from the spheres tested.
    void end_group() {
        stats_.spheres += group_spheres_;
        stats_.plane_tests += group_spheres_ * planes_;
        stats_.busy_cycles += group_spheres_ * batches_;  // each sphere occupies the input for its batches
        group_spheres_ = 0;
    }
    bool has_output() const { return count_ != 0 && ring_[head_].ready <= t_; }
    const PsiResult& output() const { return ring_[head_]; }
    void pop_output() {
        head_ = head_ + 1 == ring_.size() ? 0 : head_ + 1;
        --count_;
    }
    bool empty() const { return count_ == 0; }
    // Nothing in flight and free to issue: the state every pipe of the same
    // stream reaches when its input runs dry.
    bool drained() const { return count_ == 0 && t_ >= next_issue_; }
    std::size_t in_flight() const { return count_; }
    std::uint64_t local_time() const { return t_; }
    std::uint32_t batches() const { return batches_; }
    std::uint64_t ready_of_front() const { return ring_[head_].ready; }
    std::uint64_t spheres_this_group() const { return group_spheres_; }
    void add_starved(std::uint64_t cycles) { stats_.starved_cycles += cycles; }
    void add_stalled(std::uint64_t cycles) { stats_.stall_cycles += cycles; }

    // Event-driven simulation: take over the pipe timing of `o` (same
    // stream, never held) and fill in this group's own hit masks.
    void adopt(const PlaneSphereIntersector& o) {
        ring_ = o.ring_;
        head_ = o.head_;
        tail_ = o.tail_;
        count_ = o.count_;
        t_ = o.t_;
        next_issue_ = o.next_issue_;
        group_spheres_ = o.group_spheres_;
        // (the cursors start at the first sphere in flight, or the next to come)
        const std::uint32_t from = count_ ? ring_[head_].sphere : o.next_sphere_;
        next_sphere_ = o.next_sphere_;
        cursor_ = std::size_t(first_hit_from(*hits_, from) - hits_->begin());
        run_cursor_ = pairless_ ? std::size_t(first_run_from(*pairless_, from) - pairless_->begin()) : 0;
        for (std::size_t i = 0, j = head_; i < count_; ++i, j = j + 1 == ring_.size() ? 0 : j + 1) fill(ring_[j]);
    }
    // Steady streaming (one sphere in and one result out per cycle, one batch
    // per sphere, a full pipe): n cycles in which spheres next, next+1, ...
    // enter. Only for a pipe whose results are not looked at (no hits).
    void fast_forward(std::uint64_t n, std::uint32_t next) { stream(n, next, false); }
    // Steady streaming of this pipe's own (event-driven simulation): n
    // cycles, each popping a result the Decoder does not queue and issuing
    // the next sphere (next_sphere_, next_sphere_ + 1, ...) from a Sphere
    // FIFO that does not run dry. Only for one batch per sphere and a full
    // pipe that is free to issue.
    void cruise(std::uint64_t n) { stream(n, next_sphere_, true); }
    // Event-driven simulation: run dry, having issued the group's first
    // `issued` spheres (a pipe of the same stream, never held, once its
    // input has run dry).
    void set_drained(std::uint32_t issued) {
        head_ = tail_ = count_ = 0;
        next_issue_ = std::min(next_issue_, t_);
        next_sphere_ = issued;
        group_spheres_ = issued;
    }
    // Free to issue a sphere this cycle (no later batch of the last one pending).
    bool free_to_issue() const { return t_ >= next_issue_; }
    // n cycles with nothing in flight and nothing to take (event-driven simulation).
    void idle(std::uint64_t n) { t_ += n; }
    // Fault injection (sim.fault = stuck_psi): takes no sphere and advances no stage from now on.
    void set_stuck(bool s) { stuck_ = s; }
    bool stuck() const { return stuck_; }

    // One clock cycle, after the Decoder has looked at the output. `in` is
    // the Sphere FIFO (a SphereFifo, or the netlist's port on its channel).
    template <class In>
    void tick(In& in, bool stalled, bool spheres_pending) {
        if (stuck_) return;
        if (stalled) {
            ++stats_.stall_cycles;
            return;
        }
        if (t_ < next_issue_) {
            // later batches of the current sphere
        } else if (!in.empty()) {
            PsiResult& r = ring_[tail_];
            tail_ = tail_ + 1 == ring_.size() ? 0 : tail_ + 1;
            ++count_;
            r.sphere = in.front();
            next_sphere_ = r.sphere + 1;
            in.pop();
            fill(r);
            r.ready = t_ + batches_ - 1 + params_.stages;
            next_issue_ = t_ + batches_;
            ++group_spheres_;
        } else if (spheres_pending) {
            ++stats_.starved_cycles;
        }
        ++t_;
    }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    // n cycles of steady streaming from sphere `next` on; with `results`
    // the spheres' masks are filled in from the group's lists.
    void stream(std::uint64_t n, std::uint32_t next, bool results) {
        const std::size_t depth = count_;  // results popped and spheres issued one a cycle: it stays
        auto push = [&](std::uint64_t j) {
            PsiResult& r = ring_[tail_];
            tail_ = tail_ + 1 == ring_.size() ? 0 : tail_ + 1;
            ++count_;
            r.sphere = std::uint32_t(next + j);
            if (results) {
                fill(r);
            } else {
                r.rows = r.cols = 0;
                r.cut = false;
            }
            r.ready = t_ + j + params_.stages;
        };
        if (n >= depth) {
            head_ = tail_ = count_ = 0;
            for (std::uint64_t j = n - depth; j < n; ++j) push(j);
        } else {
            for (std::uint64_t j = 0; j < n; ++j) {
                pop_output();
                push(j);
            }
        }
        t_ += n;
        next_issue_ = t_;
        next_sphere_ = std::uint32_t(next + n);
        group_spheres_ += n;
    }
    // The result for r.sphere from the group's lists (spheres arrive in
    // ascending order, so the cursors only move forward).
    void fill(PsiResult& r) {
        const auto& list = *hits_;
        while (cursor_ < list.size() && list[cursor_].sphere < r.sphere) ++cursor_;
        r.rows = r.cols = 0;
        r.cut = false;
        if (cursor_ < list.size() && list[cursor_].sphere == r.sphere) {
            r.rows = list[cursor_].rows;
            r.cols = list[cursor_].cols;
            r.cut = true;
            return;
        }
        if (!pairless_) return;
        const auto& runs = *pairless_;
        while (run_cursor_ < runs.size() && runs[run_cursor_].end() <= r.sphere) ++run_cursor_;
        r.cut = run_cursor_ < runs.size() && runs[run_cursor_].first <= r.sphere;
    }

    Params params_;
    std::uint32_t planes_ = 0, batches_ = 1;
    std::vector<PsiResult> ring_;  // in flight, oldest at head_
    std::size_t head_ = 0, tail_ = 0, count_ = 0;
    std::uint64_t t_ = 0, next_issue_ = 0;
    const std::vector<SphereHitRec>* hits_ = nullptr;
    const std::vector<SphereRun>* pairless_ = nullptr;
    std::size_t cursor_ = 0, run_cursor_ = 0;
    std::uint32_t next_sphere_ = 0;  // the sphere after the last one issued
    std::uint64_t group_spheres_ = 0;
    bool stuck_ = false;
    Stats stats_;
};

}  // namespace raplas::model
