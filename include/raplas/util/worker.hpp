// A thread kept for a run's background jobs, taken one at a time.
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace raplas {

// run() hands the thread a job and returns; wait() blocks until it is done
// and rethrows what it threw. One thread serves every job of the run, where
// a thread started per job (std::async) would cost a thread's creation each
// time: the timing model loads each next pass ahead, thousands of passes a
// run at one ICC.
class Worker {
public:
    // `on_start` runs once on the thread, before its first job.
    explicit Worker(std::function<void()> on_start = {});
    ~Worker();  // waits for a job still running (its failure is dropped), then ends the thread
    Worker(const Worker&) = delete;
    Worker& operator=(const Worker&) = delete;

    void run(std::function<void()> job);  // at most one job at a time: wait() for the last one first
    void wait();                          // nothing to do when no job was handed over since the last wait

private:
    void loop();
    std::function<void()> on_start_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::function<void()> job_;
    bool queued_ = false;   // job_ is handed over, not yet taken
    bool running_ = false;  // the thread is running a job
    bool pending_ = false;  // a job is handed over and not waited for
    bool stop_ = false;
    std::exception_ptr error_;
    std::thread thread_;
};

}  // namespace raplas
