#pragma once
// Runs work items on a fixed number of threads. Idle workers take the next item (dynamic
// scheduling, so uneven items keep every thread busy); each item's result lands in its own slot,
// and every worker's counts reach the registry (the helpers flush when their share is done, the
// calling thread at its next snapshot): results and counters do not depend on the thread count or
// on which worker ran which item.
//
// Representation
// --------------
// The helpers are threads of one process-wide WorkerPool that wait between loops, because a frame
// runs about ten of these loops and starting a thread costs tens of microseconds on a guest (see
// docs/PERFORMANCE.md). The pool runs one loop at a time. A loop that finds it busy (a loop inside
// a loop, or loops started by two threads at once) starts threads of its own for that loop, as
// every loop did before the pool, so no caller ever waits for another caller's loop.

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "core/counters.h"

namespace patchsim {

inline int resolveThreadCount(int requested) {
    if (requested > 0) return requested;
    return std::max(1, int(std::thread::hardware_concurrency()));
}

class WorkerPool {
  public:
    // The process's pool. It is never destroyed: its parked threads must not outlive a pool that
    // static destruction took away, and a parked thread holds nothing that needs releasing.
    static WorkerPool& shared();

    // Runs share(1) .. share(helpers) on the pool's threads, each followed by a flush of that
    // thread's counters, and share(0) on the calling thread; returns when all have returned.
    // Returns false without running anything when the pool is running another loop, or when this
    // process is a fork of the one that started the pool's threads.
    bool tryRun(std::size_t helpers, const std::function<void(std::size_t)>& share);
    // Starts the threads `helpers` helpers need now rather than at the first loop (a thread
    // started while another thread is inside dlopen waits for it; see image_io_module.h).
    void startHelpers(std::size_t helpers);

  private:
    void startHelpersLocked(std::size_t helpers);
    WorkerPool();
    void serve(std::size_t helper);

    std::atomic<bool> busy_{false};  // set by the caller whose loop the pool runs
    std::mutex state_;
    std::condition_variable started_, finished_;
    const std::function<void(std::size_t)>* share_ = nullptr;
    std::size_t helpersWanted_ = 0, helpersRunning_ = 0;
    std::uint64_t generation_ = 0;
    std::vector<std::thread> threads_;
    long owner_;  // the process id that started threads_
};

// body(workerIndex, item) for every item in [0, count). The calling thread is worker 0, as it is
// on one thread. Worker 0's counters stay with the calling thread (its next snapshot flushes
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
    const std::function<void(std::size_t)> share = [&](std::size_t w) {
        try {
            for (std::size_t i = next++; i < count; i = next++) body(int(w), i);
        } catch (...) {
            std::lock_guard lock(failureMutex);
            if (!failure) failure = std::current_exception();
        }
    };
    if (!WorkerPool::shared().tryRun(workers - 1, share)) {
        std::vector<std::thread> own;
        for (std::size_t w = 1; w < workers; ++w) {
            own.emplace_back([&, w] {
                share(w);
                flushThreadCounters();
            });
        }
        share(0);
        for (std::thread& t : own) t.join();
    }
    if (failure) std::rethrow_exception(failure);
}

}  // namespace patchsim
