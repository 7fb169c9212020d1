#include "raplas/frontend/group_source.hpp"

#include <algorithm>
#include <stdexcept>

#include "raplas/util/cpu_time.hpp"

namespace raplas {

void GroupSource::release(std::size_t end) {
    if (end <= released_) return;
    if (ahead_) {
        ahead_->wait_observed(end);
    } else {
        for (std::size_t i = released_; i < end; ++i) {
            const TraceGroup& g = group(i);
            for (const auto& fn : observers) fn(i, g);
        }
    }
    released_ = end;
    free_below(end);
}

ObserveAhead::ObserveAhead(GroupSource& source) : source_(source) {
    if (source_.observers.empty() || source_.ahead_) return;  // (nothing to run, or already ahead)
    observed_ = source_.released_;
    source_.ahead_ = this;
    thread_ = std::thread([this] { run(); });
}

ObserveAhead::~ObserveAhead() { stop(); }

void ObserveAhead::stop() {
    if (!thread_.joinable()) return;
    stop_ = true;
    source_.wake();
    thread_.join();
    source_.ahead_ = nullptr;
}

void ObserveAhead::run() {
    try {
        for (std::size_t i = observed_; source_.wait_there(i, stop_); ++i) {
            const TraceGroup& g = source_.group(i);
            for (const auto& fn : source_.observers) fn(i, g);
            {
                std::lock_guard<std::mutex> lock(mutex_);
                observed_ = i + 1;
            }
            cv_.notify_all();
        }
    } catch (...) {
        std::lock_guard<std::mutex> lock(mutex_);
        error_ = std::current_exception();
    }
    {
        std::lock_guard<std::mutex> lock(mutex_);
        ended_ = true;
        cpu_s_ = thread_cpu_s();
    }
    cv_.notify_all();
}

void ObserveAhead::wait_observed(std::size_t end) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [&] { return observed_ >= end || ended_; });
    if (error_) std::rethrow_exception(error_);
    if (observed_ < end)
        throw std::logic_error("ObserveAhead: group " + std::to_string(observed_) + " released before it was there");
}

GroupStream::GroupStream(std::size_t window) : window_(std::max<std::size_t>(1, window)), slots_(window_), ready_(window_, 0) {}

void GroupStream::wait_until(std::unique_lock<std::mutex>& lock, const std::function<bool()>& ready) {
    if (!ready()) {
        const ScopeWall timed(frontend_waits_s_);  // (added to with the lock held again)
        cv_.wait(lock, [&] { return ready() || failure_ || cancelled_; });
    }
    if (!failure_ && !cancelled_) return;
    throw Cancelled();
}

bool GroupStream::wait_or_fail(std::unique_lock<std::mutex>& lock, const std::function<bool()>& ready) {
    cv_.wait(lock, [&] { return ready() || failure_; });
    return ready();
}

void GroupStream::set_header(Trace&& header) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        header_ = std::move(header);
        header_.groups.clear();
        have_header_ = true;
    }
    cv_.notify_all();
}

void GroupStream::acquire(std::size_t i) {
    std::unique_lock<std::mutex> lock(mutex_);
    wait_until(lock, [&] { return i < free_point_ + window_; });
    acquired_end_ = std::max(acquired_end_, i + 1);
    peak_held_ = std::max(peak_held_, acquired_end_ - free_point_);
}

void GroupStream::put(std::size_t i, TraceGroup&& g) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (i < free_point_ || i >= free_point_ + window_) throw std::logic_error("GroupStream::put outside the window");
        slots_[i % window_] = std::move(g);
        ready_[i % window_] = 1;
    }
    cv_.notify_all();
}

void GroupStream::set_total(std::uint64_t total) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        total_ = total;
        have_total_ = true;
    }
    cv_.notify_all();
}

void GroupStream::fail(std::exception_ptr e, const std::string& message) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!failure_) failure_ = e, failure_message_ = message;
    }
    cv_.notify_all();
}

std::string GroupStream::failure_message() {
    std::lock_guard<std::mutex> lock(mutex_);
    return failure_message_;
}

void GroupStream::cancel() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        cancelled_ = true;
    }
    cv_.notify_all();
}

std::exception_ptr GroupStream::failure() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return failure_;
}

double GroupStream::frontend_waits_s() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return frontend_waits_s_;
}

std::size_t GroupStream::peak_held() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return peak_held_;
}

const Trace& GroupStream::header() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!wait_or_fail(lock, [&] { return have_header_; })) std::rethrow_exception(failure_);
    return header_;
}

bool GroupStream::total_known() {
    std::lock_guard<std::mutex> lock(mutex_);
    return have_total_;
}

bool GroupStream::wait_total() {
    std::unique_lock<std::mutex> lock(mutex_);
    return wait_or_fail(lock, [&] { return have_total_; });
}

std::uint64_t GroupStream::total_groups() {
    std::lock_guard<std::mutex> lock(mutex_);
    return total_;
}

bool GroupStream::wait_for(std::size_t end) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (end > free_point_ + window_) {
        failure_message_ = "internal: the model needs group " + std::to_string(end - 1) + ", beyond the window of " +
                           std::to_string(window_) + " groups from group " + std::to_string(free_point_);
        return false;
    }
    return wait_or_fail(lock, [&] { return ready_below(end); });
}

bool GroupStream::has(std::size_t end) {
    std::lock_guard<std::mutex> lock(mutex_);
    return end <= free_point_ + window_ && !failure_ && ready_below(end);
}

bool GroupStream::ready_below(std::size_t end) const {
    for (std::size_t i = free_point_; i < end; ++i)
        if (!ready_[i % window_]) return false;
    return true;
}

const TraceGroup& GroupStream::group(std::size_t i) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!holds(i)) throw std::logic_error("GroupStream: group " + std::to_string(i) + " read before it was waited for");
    return slots_[i % window_];
}

bool GroupStream::wait_there(std::size_t i, const std::atomic<bool>& stop) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [&] { return holds(i) || failure_ || cancelled_ || stop; });
    return holds(i);
}

bool GroupStream::holds(std::size_t i) const {
    // (group i's slot holds group i only once the groups a window before it are freed)
    return i >= free_point_ && i < free_point_ + window_ && ready_[i % window_];
}

void GroupStream::wake() {
    { std::lock_guard<std::mutex> lock(mutex_); }  // (a waiter checks `stop` with the lock held)
    cv_.notify_all();
}

void GroupStream::free_below(std::size_t end) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (; free_point_ < end; ++free_point_) {
            slots_[free_point_ % window_] = TraceGroup{};
            ready_[free_point_ % window_] = 0;
        }
    }
    cv_.notify_all();
}

}  // namespace raplas
