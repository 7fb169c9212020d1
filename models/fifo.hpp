// A hardware FIFO of fixed depth. A push in cycle c is visible to the reader
// from cycle c+1; "full" is judged on the occupancy at the start of a cycle
// (no same-cycle pass-through of a pop), the conservative reading of §3.1.
#pragma once

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace raplas::model {

struct FifoParams {
    std::uint32_t depth = 1000;
};

struct FifoStats {
    std::uint64_t pushes = 0;
    std::uint64_t max_occupancy = 0;
    std::uint64_t full_cycles = 0;  // cycles in which a push was refused because it was full
};

template <class T>
class Fifo {
public:
    using Params = FifoParams;
    using Stats = FifoStats;
    using value_type = T;

    Fifo(const std::string& name, const Params& p) : params_(p), buf_(p.depth) {
        if (p.depth == 0) throw std::invalid_argument(name + ": depth must be >= 1");
    }

    bool empty() const { return count_ == 0; }
    bool full() const { return count_ == params_.depth; }
    std::uint32_t size() const { return count_; }
    std::uint32_t depth() const { return params_.depth; }
    const T& front() const { return buf_[head_]; }
    T& front() { return buf_[head_]; }
    // The entry `i` places behind the front (i < size()).
    const T& at(std::uint32_t i) const {
        std::uint32_t j = head_ + i;
        if (j >= params_.depth) j -= params_.depth;
        return buf_[j];
    }
    void push(const T& v) {
        std::uint32_t i = head_ + count_;  // < 2 depth: no division
        if (i >= params_.depth) i -= params_.depth;
        buf_[i] = v;
        ++count_;
        ++stats_.pushes;
        if (count_ > stats_.max_occupancy) stats_.max_occupancy = count_;
    }
    void pop() {
        head_ = head_ + 1 == params_.depth ? 0 : head_ + 1;
        --count_;
    }
    // Event-driven simulation: stores an entry whose push was recorded
    // already (record_push), while it was kept elsewhere.
    void place(const T& v) {
        std::uint32_t i = head_ + count_;
        if (i >= params_.depth) i -= params_.depth;
        buf_[i] = v;
        ++count_;
    }
    // Asks the cache for the entry `ahead` places behind the front (read soon).
    void prefetch(std::uint32_t ahead) const {
        std::uint32_t i = head_ + ahead;
        if (i >= params_.depth) i -= params_.depth;
        if (i < params_.depth) __builtin_prefetch(&buf_[i]);
    }
    void clear() {
        head_ = 0;
        count_ = 0;
    }
    // The storage as a RAM of depth() entries, slot a (a < depth()), for a
    // FIFO controller of its own: the RTL Triangle FIFO (sim.rtl), which
    // keeps the pointers and the occupancy; this FIFO's are then unused.
    T& ram(std::uint32_t a) { return buf_[a]; }
    const T& ram(std::uint32_t a) const { return buf_[a]; }
    void note_full(std::uint64_t cycles = 1) { stats_.full_cycles += cycles; }
    // Event-driven simulation keeps the contents elsewhere and records here:
    // `n` pushes, the largest occupancy they left being `occupancy`.
    void record_push(std::uint32_t occupancy, std::uint64_t n) {
        stats_.pushes += n;
        if (occupancy > stats_.max_occupancy) stats_.max_occupancy = occupancy;
    }
    const Stats& stats() const { return stats_; }
    const Params& params() const { return params_; }
    // The most entries it may hold without being full or passing its largest
    // occupancy so far (event-driven simulation: runs whose pushes and pops
    // are counted, not ordered, stay within it).
    std::uint64_t quiet_limit() const { return quiet_limit(stats_.max_occupancy, params_.depth); }
    // The same for a FIFO of `depth` whose largest occupancy so far is `max_occupancy`.
    static std::uint64_t quiet_limit(std::uint64_t max_occupancy, std::uint32_t depth) {
        return std::min<std::uint64_t>(max_occupancy, std::uint64_t(depth) - 1);
    }

private:
    Params params_;
    std::vector<T> buf_;
    std::uint32_t head_ = 0, count_ = 0;
    Stats stats_;
};

// The Sphere FIFO: every sphere of the stream enters it in order, so it
// always holds a run of consecutive sphere ids; it is kept as (first, count).
class SphereFifo {
public:
    using Params = FifoParams;
    using Stats = FifoStats;
    using value_type = std::uint32_t;
    SphereFifo(const std::string& name, const Params& p) : params_(p) {
        if (p.depth == 0) throw std::invalid_argument(name + ": depth must be >= 1");
    }
    bool empty() const { return count_ == 0; }
    bool full() const { return count_ == params_.depth; }
    std::uint32_t size() const { return count_; }
    std::uint32_t depth() const { return params_.depth; }
    std::uint32_t front() const { return first_; }
    // The sphere `i` places behind the front (i < size()).
    std::uint32_t at(std::uint32_t i) const { return first_ + i; }
    void push(std::uint32_t sphere) {
        if (count_ == 0) first_ = sphere;
        ++count_;
        ++stats_.pushes;
        if (count_ > stats_.max_occupancy) stats_.max_occupancy = count_;
    }
    void pop() {
        ++first_;
        --count_;
    }
    // Event-driven simulation: `popped` spheres taken from the front and
    // `pushed` received behind them, in a run of cycles in which it never ran
    // dry nor grew past its occupancy at the start.
    void cruise(std::uint32_t popped, std::uint32_t pushed) {
        first_ += popped;
        count_ = count_ - popped + pushed;
        stats_.pushes += pushed;
    }
    // Event-driven simulation: it held `occupancy` entries at some point of such a run.
    void note_occupancy(std::uint32_t occupancy) {
        if (occupancy > stats_.max_occupancy) stats_.max_occupancy = occupancy;
    }
    // Event-driven simulation: spheres first, first+1, ... (n of them)
    // pushed one per cycle with no pop between them.
    void push_run(std::uint32_t first, std::uint32_t n) {
        if (n == 0) return;
        if (count_ == 0) first_ = first;
        count_ += n;
        stats_.pushes += n;
        if (count_ > stats_.max_occupancy) stats_.max_occupancy = count_;
    }
    void clear() { count_ = 0; }
    void note_full() { ++stats_.full_cycles; }
    void note_full(std::uint64_t cycles) { stats_.full_cycles += cycles; }
    // Event-driven simulation: take over the contents of an identical FIFO,
    // with `pushes` pushes and `max_occupancy` seen by it.
    void adopt(const SphereFifo& o, std::uint64_t pushes, std::uint64_t max_occupancy) {
        first_ = o.first_;
        count_ = o.count_;
        stats_.pushes += pushes;
        if (max_occupancy > stats_.max_occupancy) stats_.max_occupancy = max_occupancy;
    }
    // n pushes and n pops in steady streaming.
    void advance(std::uint32_t n) {
        first_ += n;
        stats_.pushes += n;
    }
    const Stats& stats() const { return stats_; }
    const Params& params() const { return params_; }

private:
    Params params_;
    std::uint32_t first_ = 0, count_ = 0;
    Stats stats_;
};

}  // namespace raplas::model
