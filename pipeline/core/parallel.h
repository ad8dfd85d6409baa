#pragma once
// Runs work items on a fixed number of threads. Idle workers take the next item (dynamic
// scheduling, so uneven items keep every thread busy); each item's result lands in its own slot,
// and every worker's counts reach the registry (the started workers flush when they are done,
// the calling thread at its next snapshot): results and counters do not depend on the thread
// count or on which worker ran which item.

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

// body(workerIndex, item) for every item in [0, count). The calling thread is worker 0, as it is
// on one thread: starting a thread costs tens of microseconds on a guest, and a frame runs several
// of these loops. Worker 0's counters stay with the calling thread (its next snapshot flushes
// them); the others flush theirs when they finish.
template <typename Body>
void parallelFor(std::size_t count, int threads, const Body& body) {
    const std::size_t workers = std::min<std::size_t>(std::size_t(resolveThreadCount(threads)),
                                                      std::max<std::size_t>(count, 1));
    if (workers <= 1) {
        for (std::size_t i = 0; i < count; ++i) body(0, i);
        return;
    }
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failureMutex;
    const auto work = [&](std::size_t w) {
        try {
            for (std::size_t i = next++; i < count; i = next++) body(int(w), i);
        } catch (...) {
            std::lock_guard lock(failureMutex);
            if (!failure) failure = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    for (std::size_t w = 1; w < workers; ++w) {
        pool.emplace_back([&, w] {
            work(w);
            flushThreadCounters();
        });
    }
    work(0);
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace patchsim
