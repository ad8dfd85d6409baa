#pragma once
// Runs work items on a fixed number of threads. Idle workers take the next item (dynamic
// scheduling, so uneven items keep every thread busy); each item's result lands in its own slot,
// and every worker flushes its counters when it is done: results and counters do not depend on
// the thread count or on which worker ran which item.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "pipeline/core/counters.h"

namespace patchsim {

inline int resolveThreadCount(int requested) {
    if (requested > 0) return requested;
    return std::max(1, int(std::thread::hardware_concurrency()));
}

// body(workerIndex, item) for every item in [0, count).
template <typename Body>
void parallelFor(std::size_t count, int threads, const Body& body) {
    const std::size_t workers = std::min<std::size_t>(std::size_t(resolveThreadCount(threads)),
                                                      std::max<std::size_t>(count, 1));
    if (workers <= 1) {
        for (std::size_t i = 0; i < count; ++i) body(0, i);
        return;
    }
    std::vector<std::thread> pool;
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failureMutex;
    for (std::size_t w = 0; w < workers; ++w) {
        pool.emplace_back([&, w] {
            try {
                for (std::size_t i = next++; i < count; i = next++) body(int(w), i);
            } catch (...) {
                std::lock_guard lock(failureMutex);
                if (!failure) failure = std::current_exception();
            }
            flushThreadCounters();
        });
    }
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace patchsim
