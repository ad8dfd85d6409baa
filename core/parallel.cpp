#include "core/parallel.h"

#include <unistd.h>

namespace patchsim {

WorkerPool& WorkerPool::shared() {
    static WorkerPool* const pool = new WorkerPool;
    return *pool;
}

WorkerPool::WorkerPool() : owner_(long(getpid())) {}

bool WorkerPool::tryRun(std::size_t helpers, const std::function<void(std::size_t)>& share) {
    if (long(getpid()) != owner_) return false;  // a forked child has none of the threads
    bool idle = false;
    if (!busy_.compare_exchange_strong(idle, true, std::memory_order_acquire)) return false;
    struct Release {
        std::atomic<bool>& busy;
        ~Release() { busy.store(false, std::memory_order_release); }
    } release{busy_};
    {
        std::lock_guard lock(state_);
        startHelpersLocked(helpers);
        share_ = &share;
        helpersWanted_ = helpersRunning_ = helpers;
        ++generation_;
    }
    started_.notify_all();
    share(0);
    std::unique_lock lock(state_);
    finished_.wait(lock, [this] { return helpersRunning_ == 0; });
    share_ = nullptr;
    return true;
}

void WorkerPool::startHelpers(std::size_t helpers) {
    if (long(getpid()) != owner_) return;
    std::lock_guard lock(state_);
    startHelpersLocked(helpers);
}

void WorkerPool::startHelpersLocked(std::size_t helpers) {
    while (threads_.size() < helpers) {
        const std::size_t helper = threads_.size() + 1;
        threads_.emplace_back([this, helper] { serve(helper); });
    }
}

// Helper `helper` (1-based) takes part in every loop that wants at least that many helpers.
void WorkerPool::serve(std::size_t helper) {
    std::uint64_t seen = 0;
    std::unique_lock lock(state_);
    for (;;) {
        started_.wait(lock, [&] { return generation_ != seen; });
        seen = generation_;
        if (helper > helpersWanted_) continue;
        const std::function<void(std::size_t)>& share = *share_;
        lock.unlock();
        share(helper);
        flushThreadCounters();
        lock.lock();
        if (--helpersRunning_ == 0) finished_.notify_one();
    }
}

}  // namespace patchsim
