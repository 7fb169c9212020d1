// CPU time, for the run-time figures reported beside wall time ("wall" in a
// simulation's JSON). Nothing computed depends on them.
#pragma once

#include <time.h>

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

}  // namespace raplas
