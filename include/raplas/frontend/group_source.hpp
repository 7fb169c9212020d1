// Where the timing model takes its ray groups from, one at a time in issue
// order: a whole trace held in memory (TraceSource), or the front end
// producing them while the model runs (GroupStream), with only a bounded
// window of groups in memory (docs/MEMORY.md, "Streaming").
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "raplas/frontend/trace_io.hpp"

namespace raplas {

class GroupSource {
public:
    virtual ~GroupSource() = default;
    // Everything of the trace but its groups (whose vector may be empty):
    // scene facts, Sphere and Triangle Memory, the number of primary groups.
    virtual const Trace& header() = 0;
    // Whether the number of groups is known yet (a stream knows it once the
    // front end has traced every primary group).
    virtual bool total_known() = 0;
    // Waits until the number of groups is known; false when the source
    // stopped first (the front end failed: failure() says why). Never throws:
    // the model waits from inside its SystemC thread.
    virtual bool wait_total() = 0;
    // The number of groups, once known.
    virtual std::uint64_t total_groups() = 0;
    // Waits until every group below `end` is there; false when the source
    // stopped first. Never throws (as wait_total).
    virtual bool wait_for(std::size_t end) = 0;
    // Whether every group below `end` is there now (never waits).
    virtual bool has(std::size_t end) = 0;
    // Group i: waited for, and not yet released. The reference stays valid
    // until the group is released.
    virtual const TraceGroup& group(std::size_t i) = 0;
    // Why the source stopped (empty while it has not).
    virtual std::string failure_message() { return {}; }
    // Groups below `end` will not be read again: each one not yet released
    // is handed to every observer, in issue order, and then may be freed.
    void release(std::size_t end);
    std::size_t released() const { return released_; }
    // Called for every group, in issue order, as it is released (from the
    // thread that releases it), or, while an ObserveAhead runs, from its
    // thread as soon as the group is there: what the reports fold over the
    // whole workload.
    std::vector<std::function<void(std::size_t, const TraceGroup&)>> observers;

protected:
    virtual void free_below(std::size_t end) = 0;
    // For ObserveAhead's thread: waits until group i is there (true), or
    // until `stop` is set or the source stopped first (false).
    virtual bool wait_there(std::size_t i, const std::atomic<bool>& stop) = 0;
    // Wakes every wait_there (its caller has set `stop`).
    virtual void wake() {}

private:
    friend class ObserveAhead;
    std::size_t released_ = 0;
    class ObserveAhead* ahead_ = nullptr;
};

// While it lives, the observers of `source` run on a thread of their own,
// each group handed to them as soon as it is there, in issue order; release()
// then only waits (if need be) until they have seen the groups it frees. The
// figures they fold are the same; the thread that releases the groups (the
// model's) no longer spends its time on them. Destroying it stops the thread:
// give it the scope of the run whose groups it observes.
class ObserveAhead {
public:
    explicit ObserveAhead(GroupSource& source);
    ~ObserveAhead();
    ObserveAhead(const ObserveAhead&) = delete;
    ObserveAhead& operator=(const ObserveAhead&) = delete;
    // Waits until the observers have seen every group below `end`; rethrows
    // an observer's exception.
    void wait_observed(std::size_t end);
    // Stops the thread (as destroying it does).
    void stop();
    // CPU seconds its thread used, once stopped.
    double cpu_s() const { return cpu_s_; }

private:
    void run();
    GroupSource& source_;
    std::atomic<bool> stop_{false};
    std::mutex mutex_;
    std::condition_variable cv_;
    std::size_t observed_ = 0;
    bool ended_ = false;  // the thread has stopped (the source stopped, or an observer threw)
    std::exception_ptr error_;
    double cpu_s_ = 0;
    std::thread thread_;
};

// A trace held whole: nothing waits, nothing is freed.
class TraceSource : public GroupSource {
public:
    explicit TraceSource(const Trace& t) : t_(t) {}
    const Trace& header() override { return t_; }
    bool total_known() override { return true; }
    bool wait_total() override { return true; }
    std::uint64_t total_groups() override { return t_.groups.size(); }
    bool wait_for(std::size_t end) override { return end <= t_.groups.size(); }
    bool wait_there(std::size_t i, const std::atomic<bool>&) override { return i < t_.groups.size(); }
    bool has(std::size_t end) override { return end <= t_.groups.size(); }
    const TraceGroup& group(std::size_t i) override { return t_.groups.at(i); }

protected:
    void free_below(std::size_t) override {}

private:
    const Trace& t_;
};

// The groups of a whole trace in another order: position i is the trace's
// group order[i] (a permutation; the model's workload.group_order). The
// trace's own order is kept for its observers: they are the trace source's.
class PermutedSource : public GroupSource {
public:
    PermutedSource(const Trace& t, std::vector<std::uint32_t> order) : t_(t), order_(std::move(order)) {}
    const Trace& header() override { return t_; }
    bool total_known() override { return true; }
    bool wait_total() override { return true; }
    std::uint64_t total_groups() override { return order_.size(); }
    bool wait_for(std::size_t end) override { return end <= order_.size(); }
    bool wait_there(std::size_t i, const std::atomic<bool>&) override { return i < order_.size(); }
    bool has(std::size_t end) override { return end <= order_.size(); }
    const TraceGroup& group(std::size_t i) override { return t_.groups.at(order_.at(i)); }
    // The trace index of position i.
    std::uint32_t trace_index(std::size_t i) const { return order_.at(i); }

protected:
    void free_below(std::size_t) override {}

private:
    const Trace& t_;
    std::vector<std::uint32_t> order_;
};

// What the reports fold over every group as the model releases them, in
// issue order: the group count, the summed counts and the workload hash.
struct WorkloadTally {
    // fold_hash false: the hash is folded elsewhere (the process that feeds
    // the shards of simulate --jobs, the sweep a point belongs to), and
    // `hasher` is left empty.
    WorkloadTally(const Trace& header, bool pairless, bool fold_hash = true) {
        if (fold_hash) hasher.emplace(header, pairless);
    }
    void add(const TraceGroup& g) {
        ++groups;
        if (g.n == 0) {  // not traced (FrameOptions::groups_read)
            ++untraced;
            return;
        }
        counts += g.counts;
        if (hasher) hasher->add(g);
    }
    // An observer for GroupSource::observers that adds each group here.
    std::function<void(std::size_t, const TraceGroup&)> observer() {
        return [this](std::size_t, const TraceGroup& g) { add(g); };
    }
    std::uint64_t groups = 0;
    std::uint64_t untraced = 0;  // placeholders: in `groups`, not in `counts` or the hash
    GroupCounts counts;
    std::optional<WorkloadHasher> hasher;
};

// Ray groups handed over by the front end's worker threads and taken by the
// model, in issue order. At most `window` groups are between the release
// point and the last one a worker may trace: a worker asks for its group's
// slot (acquire) before tracing it and waits while the group is `window` or
// more past the release point, so the groups traced and not yet released
// never exceed the window.
class GroupStream : public GroupSource {
public:
    explicit GroupStream(std::size_t window);

    // Front end side (any thread).
    void set_header(Trace&& header);  // before any group
    void acquire(std::size_t i);      // waits for group i's slot; throws Cancelled once cancelled
    void put(std::size_t i, TraceGroup&& g);
    void set_total(std::uint64_t total);
    // The front end stopped: header() throws `e`, the model's waits return
    // false with `message`, and waiting workers throw Cancelled.
    void fail(std::exception_ptr e, const std::string& message);

    // Model side.
    const Trace& header() override;  // waits; throws the front end's failure
    bool total_known() override;
    bool wait_total() override;
    std::uint64_t total_groups() override;
    bool wait_for(std::size_t end) override;
    bool has(std::size_t end) override;
    const TraceGroup& group(std::size_t i) override;
    std::string failure_message() override;
    // The model stopped: waiting workers throw Cancelled.
    void cancel();

    struct Cancelled : std::exception {
        const char* what() const noexcept override { return "group stream cancelled"; }
    };
    std::exception_ptr failure() const;
    std::size_t window() const { return window_; }
    // The most groups held at once (traced, or being traced, and not yet released).
    std::size_t peak_held() const;
    // Wall seconds the front end's threads waited for a slot (the model
    // behind), summed over the threads.
    double frontend_waits_s() const;

protected:
    void free_below(std::size_t end) override;
    bool wait_there(std::size_t i, const std::atomic<bool>& stop) override;
    void wake() override;

private:
    // Front end side: returns once ready, throws Cancelled when the stream stopped.
    void wait_until(std::unique_lock<std::mutex>& lock, const std::function<bool()>& ready);
    // Every group from the release point to `end` is there (the lock held).
    bool ready_below(std::size_t end) const;
    // Group i is in its slot, not yet freed (the lock held).
    bool holds(std::size_t i) const;
    // Model side: true once ready, false when the front end failed first.
    bool wait_or_fail(std::unique_lock<std::mutex>& lock, const std::function<bool()>& ready);

    const std::size_t window_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    Trace header_;
    bool have_header_ = false;
    bool have_total_ = false;
    std::uint64_t total_ = 0;
    std::size_t free_point_ = 0;   // groups below it are freed
    std::size_t acquired_end_ = 0;  // one past the highest slot acquired
    std::size_t peak_held_ = 0;
    double frontend_waits_s_ = 0;
    bool cancelled_ = false;
    std::exception_ptr failure_;
    std::string failure_message_;
    std::vector<TraceGroup> slots_;  // group i in slot i % window
    std::vector<char> ready_;
};

}  // namespace raplas
