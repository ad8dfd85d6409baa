#include "core/parallel.h"

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace patchsim {
namespace {

const Counter testParallelItems{"Test/Parallel items", "items",
                                "Counted by the parallelFor test only"};

// Every item once, its result in its own slot, on any thread count; the pool's threads serve loop
// after loop.
TEST(ParallelFor, EveryItemRunsOnceInItsSlotOnAnyThreadCount) {
    for (int threads : {1, 2, 3, 8}) {
        for (int loop = 0; loop < 20; ++loop) {
            std::vector<int> runs(1000, 0);
            parallelFor(runs.size(), threads, [&](int, std::size_t i) { ++runs[i]; });
            for (std::size_t i = 0; i < runs.size(); ++i)
                ASSERT_EQ(runs[i], 1) << "item " << i << ", " << threads << " threads";
        }
    }
}

// The pool's helpers wait between loops instead of ending: the second loop's helpers are the
// threads of the first.
TEST(ParallelFor, TheHelpersOfOneLoopServeTheNext) {
    const auto helperIds = [] {
        std::vector<std::thread::id> ids(3);
        std::set<std::thread::id> seen;
        // Items that wait for each other, so that all three workers take one.
        std::atomic<int> arrived{0};
        parallelFor(3, 3, [&](int w, std::size_t) {
            ids[std::size_t(w)] = std::this_thread::get_id();
            ++arrived;
            while (arrived.load() < 3) std::this_thread::yield();
        });
        return ids;
    };
    const std::vector<std::thread::id> first = helperIds(), second = helperIds();
    EXPECT_EQ(first[0], std::this_thread::get_id());
    EXPECT_EQ(first, second);
    EXPECT_EQ(std::set<std::thread::id>(first.begin(), first.end()).size(), 3u);
}

// What the helpers count reaches the registry when the loop returns, loop after loop.
TEST(ParallelFor, TheHelpersCountsReachTheRegistryWhenTheLoopReturns) {
    CounterRegistry::instance().reset();
    for (int loop = 1; loop <= 5; ++loop) {
        parallelFor(400, 2, [](int, std::size_t) { ++testParallelItems; });
        EXPECT_EQ(CounterRegistry::instance().snapshot()[testParallelItems], 400 * loop);
    }
    CounterRegistry::instance().reset();
}

// A loop inside a loop, and loops started by two threads at once, find the pool busy and start
// threads of their own: each finishes, with every item run once.
TEST(ParallelFor, LoopsInsideLoopsAndSideBySideAllFinish) {
    std::vector<std::atomic<int>> runs(64 * 16);
    parallelFor(64, 2, [&](int, std::size_t outer) {
        parallelFor(16, 2, [&](int, std::size_t inner) { ++runs[outer * 16 + inner]; });
    });
    for (const auto& r : runs) ASSERT_EQ(r.load(), 1);

    std::vector<int> left(5000, 0), right(5000, 0);
    std::thread other(
        [&] { parallelFor(right.size(), 2, [&](int, std::size_t i) { ++right[i]; }); });
    parallelFor(left.size(), 2, [&](int, std::size_t i) { ++left[i]; });
    other.join();
    for (std::size_t i = 0; i < left.size(); ++i) ASSERT_EQ(left[i] + right[i], 2);
}

// An item's exception reaches the caller, and the pool serves the next loop.
TEST(ParallelFor, AnItemsExceptionReachesTheCallerAndThePoolGoesOn) {
    EXPECT_THROW(parallelFor(100, 2,
                             [](int, std::size_t i) {
                                 if (i == 57) throw std::runtime_error("item 57");
                             }),
                 std::runtime_error);
    std::vector<int> runs(100, 0);
    parallelFor(runs.size(), 2, [&](int, std::size_t i) { ++runs[i]; });
    for (int r : runs) ASSERT_EQ(r, 1);
}

}  // namespace
}  // namespace patchsim
