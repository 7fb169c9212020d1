// Minimal deterministic parallel loop: items are independent and each writes
// only its own slot, so the result does not depend on the thread count.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace raplas {

// (asked once: glibc reads /sys/devices/system/cpu/online at each call, and
// the model asks once per pass)
inline unsigned default_threads() {
    static const unsigned n = [] {
        const unsigned k = std::thread::hardware_concurrency();
        return k == 0 ? 1u : k;
    }();
    return n;
}

template <class F>
void parallel_for(std::size_t count, unsigned threads, F&& body) {
    if (threads <= 1 || count <= 1) {
        for (std::size_t i = 0; i < count; ++i) body(i);
        return;
    }
    std::atomic<std::size_t> next{0};
    std::exception_ptr error;
    std::mutex error_mutex;
    auto worker = [&] {
        for (;;) {
            std::size_t i = next.fetch_add(1);
            if (i >= count) return;
            try {
                body(i);
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!error) error = std::current_exception();
                next = count;
                return;
            }
        }
    };
    std::vector<std::thread> pool;
    unsigned n = static_cast<unsigned>(std::min<std::size_t>(threads, count));
    for (unsigned t = 1; t < n; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace raplas
