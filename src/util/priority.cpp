#include "raplas/util/priority.hpp"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>

namespace raplas {

void lower_thread_priority(int steps) {
#ifdef SYS_gettid
    const id_t tid = static_cast<id_t>(syscall(SYS_gettid));
    errno = 0;
    const int now = getpriority(PRIO_PROCESS, tid);
    if (now == -1 && errno != 0) return;
    (void)setpriority(PRIO_PROCESS, tid, now + steps);
#else
    (void)steps;
#endif
}

}  // namespace raplas
