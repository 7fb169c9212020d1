#include "raplas/util/worker.hpp"

#include <stdexcept>
#include <utility>

namespace raplas {

Worker::Worker(std::function<void()> on_start) : on_start_(std::move(on_start)) {}

Worker::~Worker() {
    {
        std::unique_lock<std::mutex> lock(mutex_);
        cv_.wait(lock, [&] { return !queued_ && !running_; });
        stop_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void Worker::run(std::function<void()> job) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (pending_) throw std::logic_error("Worker::run: the last job was not waited for");
        job_ = std::move(job);
        queued_ = pending_ = true;
        error_ = nullptr;
    }
    if (!thread_.joinable()) thread_ = std::thread([this] { loop(); });
    cv_.notify_all();
}

void Worker::wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!pending_) return;
    cv_.wait(lock, [&] { return !queued_ && !running_; });
    pending_ = false;
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void Worker::loop() {
    if (on_start_) on_start_();
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        cv_.wait(lock, [&] { return queued_ || stop_; });
        if (!queued_) return;
        std::function<void()> job = std::move(job_);
        job_ = nullptr;
        queued_ = false;
        running_ = true;
        lock.unlock();
        std::exception_ptr error;
        try {
            job();
        } catch (...) {
            error = std::current_exception();
        }
        job = nullptr;  // (what it holds goes on this thread, before the wait returns)
        lock.lock();
        running_ = false;
        error_ = error;
        cv_.notify_all();
    }
}

}  // namespace raplas
