#include "pipeline/timing/cache_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace patchsim {
namespace {

// A cache written the plain way: each set a list of (line, last use, fill time, dirty), the
// victim found by scanning for the oldest use (LRU) or the oldest fill (FIFO).
class BruteForceCache {
  public:
    explicit BruteForceCache(const CacheGeometry& g) : g_(g), sets_(g.sets()) {}

    struct Result {
        bool hit;
        std::uint64_t writeback;
    };
    Result access(std::uint64_t line, bool write) {
        ++clock_;
        std::vector<Slot>& set = sets_[line % sets_.size()];
        for (Slot& s : set)
            if (s.line == line) {
                s.lastUse = clock_;
                s.dirty = s.dirty || write;
                return {true, CacheModel::kEmpty};
            }
        std::uint64_t writeback = CacheModel::kEmpty;
        if (set.size() == g_.ways) {
            const auto victim = std::min_element(set.begin(), set.end(), [&](auto& a, auto& b) {
                return g_.replacement == Replacement::Lru ? a.lastUse < b.lastUse
                                                          : a.filled < b.filled;
            });
            if (victim->dirty) writeback = victim->line;
            set.erase(victim);
        }
        set.push_back({line, clock_, clock_, write});
        return {false, writeback};
    }

  private:
    struct Slot {
        std::uint64_t line, lastUse, filled;
        bool dirty;
    };
    CacheGeometry g_;
    std::vector<std::vector<Slot>> sets_;
    std::uint64_t clock_ = 0;
};

void expectSameAsBruteForce(const CacheGeometry& g, std::uint64_t lines, std::uint32_t seed) {
    CacheModel cache(g);
    BruteForceCache reference(g);
    std::mt19937 random(seed);
    std::uniform_int_distribution<std::uint64_t> pick(0, lines - 1);
    std::uint64_t hits = 0, writebacks = 0;
    for (int i = 0; i < 200000; ++i) {
        // Mostly near the last line, sometimes anywhere: a stream with some reuse.
        const std::uint64_t line = pick(random);
        const bool write = random() % 3 == 0;
        const CacheModel::Outcome got = cache.access(line, write);
        const BruteForceCache::Result want = reference.access(line, write);
        ASSERT_EQ(got.hit, want.hit) << "access " << i << " line " << line;
        ASSERT_EQ(got.writeback, want.writeback) << "access " << i << " line " << line;
        hits += want.hit;
        writebacks += want.writeback != CacheModel::kEmpty;
    }
    EXPECT_EQ(cache.stats().hits(), hits);
    EXPECT_EQ(cache.stats().writebacks, writebacks);
    EXPECT_GT(hits, 0u);
    EXPECT_LT(hits, 200000u);
}

TEST(CacheModel, HitsMissesAndWritebacksEqualABruteForceCacheOnRandomStreams) {
    for (Replacement r : {Replacement::Lru, Replacement::Fifo}) {
        expectSameAsBruteForce({4096, 64, 4, r}, 160, 1);    // 16 sets
        expectSameAsBruteForce({4096, 64, 1, r}, 100, 2);    // direct mapped
        expectSameAsBruteForce({4096, 64, 64, r}, 90, 3);    // fully associative
        expectSameAsBruteForce({24576, 128, 3, r}, 500, 4);  // 64 sets of 3 ways
    }
}

TEST(CacheModel, LruKeepsTheRecentlyUsedLineWhereFifoEvictsTheOldestFill) {
    // One set of two ways: fill A, fill B, touch A, fill C.
    for (Replacement r : {Replacement::Lru, Replacement::Fifo}) {
        CacheModel cache({128, 64, 2, r});
        cache.access(10, false);
        cache.access(11, false);
        EXPECT_TRUE(cache.access(10, false).hit);
        cache.access(12, false);
        EXPECT_EQ(cache.access(10, false).hit, r == Replacement::Lru) << replacementName(r);
    }
}

TEST(CacheModel, AFlushWritesEveryDirtyLineOnceAndKeepsThemClean) {
    CacheModel cache({1024, 64, 4, Replacement::Lru});
    for (std::uint64_t line = 0; line < 8; ++line) cache.access(line, line % 2 == 0);
    std::vector<std::uint64_t> written;
    cache.flush([&](std::uint64_t line) { written.push_back(line); });
    std::sort(written.begin(), written.end());
    EXPECT_EQ(written, (std::vector<std::uint64_t>{0, 2, 4, 6}));
    cache.flush([&](std::uint64_t line) { ADD_FAILURE() << "line " << line << " again"; });
    for (std::uint64_t line = 0; line < 8; ++line) EXPECT_TRUE(cache.access(line, false).hit);
}

// A fast clear: an invalidated line is gone, dirty or not, and never written back; the other
// lines keep their order, so the next fill of the set evicts what it would have without the
// cleared line (one set of four ways, LRU: fill 1 to 4, clear 3, fill 5 and 6: 6 evicts 1).
TEST(CacheModel, AnInvalidatedLineIsDroppedUnwrittenAndTheRestKeepTheirOrder) {
    CacheModel cache({256, 64, 4, Replacement::Lru});
    for (std::uint64_t line = 1; line <= 4; ++line) cache.access(line, true);
    cache.invalidate(3);
    cache.invalidate(99);                      // not held: nothing happens
    EXPECT_FALSE(cache.access(5, false).hit);  // fills the freed way: no eviction
    const CacheModel::Outcome sixth = cache.access(6, false);
    EXPECT_FALSE(sixth.hit);
    EXPECT_EQ(sixth.writeback, 1u);  // the least recent of 1, 2, 4, 5
    std::vector<std::uint64_t> written;
    cache.flush([&](std::uint64_t line) { written.push_back(line); });
    std::sort(written.begin(), written.end());
    EXPECT_EQ(written, (std::vector<std::uint64_t>{2, 4}));  // 3 was never written back
    EXPECT_FALSE(cache.access(3, false).hit);
}

}  // namespace
}  // namespace patchsim
