// CPU and wait times, for the run-time figures reported beside wall time
// ("wall" in a simulation's JSON). Nothing computed depends on them.
#pragma once

#include <time.h>

#include <chrono>

namespace raplas {

// CPU seconds used so far by the calling thread, and by the whole process.
inline double thread_cpu_s() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
inline double process_cpu_s() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Adds the wall seconds of its scope to `total` (a wait, timed).
class ScopeWall {
public:
    explicit ScopeWall(double& total) : total_(total), t0_(std::chrono::steady_clock::now()) {}
    ~ScopeWall() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
    ScopeWall(const ScopeWall&) = delete;
    ScopeWall& operator=(const ScopeWall&) = delete;

private:
    double& total_;
    std::chrono::steady_clock::time_point t0_;
};

}  // namespace raplas
