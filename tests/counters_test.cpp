#include "core/counters.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "rasterizer/patent/raster_work.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

const Counter testIncrements{"Test/Increments", "increments", "Counted by the counter test only"};
const Counter testLargest{"Test/Largest", "items", "Largest value seen by the counter test",
                          CounterKind::Max};
const RatioCounter testRatio{"Test/Ratio", "Largest per increment", testLargest, testIncrements};

TEST(Counters, ThreadLocalCountsAddUpExactly) {
    CounterRegistry::instance().reset();
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t) {
        threads.emplace_back([t] {
            for (int i = 0; i < 1000; ++i) ++testIncrements;
            testLargest.raiseTo(10 * (t + 1));
            flushThreadCounters();
        });
    }
    for (auto& t : threads) t.join();
    const CounterValues values = CounterRegistry::instance().snapshot();
    EXPECT_EQ(values[testIncrements], 4000);
    EXPECT_EQ(values[testLargest], 40);
    EXPECT_DOUBLE_EQ(values.ratio(testRatio), 0.01);
    EXPECT_EQ(values.byName("Test/Increments"), 4000);
    CounterRegistry::instance().reset();
    EXPECT_EQ(CounterRegistry::instance().snapshot()[testIncrements], 0);
}

TEST(Counters, AnotherProcessesCountsMergeAsSumsAndMaxima) {
    CounterRegistry::instance().reset();
    testIncrements += 5;
    testLargest.raiseTo(7);
    const CounterValues before = CounterRegistry::instance().snapshot();
    testIncrements += 3;
    testLargest.raiseTo(9);
    const CounterValues delta = CounterRegistry::instance().snapshot().since(before);
    EXPECT_EQ(delta[testIncrements], 3);
    EXPECT_EQ(delta[testLargest], 9);
    CounterRegistry::instance().merge(delta);
    const CounterValues after = CounterRegistry::instance().snapshot();
    EXPECT_EQ(after[testIncrements], 11);
    EXPECT_EQ(after[testLargest], 9);
    CounterRegistry::instance().reset();
}

// Each counter is defined in one place: one registration per name.
TEST(Counters, EveryCounterIsRegisteredOnce) {
    std::set<std::string> names;
    for (const CounterInfo& info : CounterRegistry::instance().infos())
        EXPECT_TRUE(names.insert(info.name).second) << info.name << " is registered twice";
}

TEST(Counters, RasterWorkAddsAndFlushesEveryCountOnce) {
    CounterRegistry::instance().reset();
    RasterWork a, b;
    a.raysCast = 3;
    b.raysCast = 4;
    a.peakHierarchyBytes = 100;
    b.peakHierarchyBytes = 60;
    a.add(b);
    EXPECT_EQ(a.raysCast, 7);
    EXPECT_EQ(a.peakHierarchyBytes, 100);  // a Max count keeps the larger
    a.flush();
    a.flush();
    const CounterValues values = CounterRegistry::instance().snapshot();
    EXPECT_EQ(values[rasterCounters().raysCast], 14);
    EXPECT_EQ(values[rasterCounters().peakHierarchyBytes], 100);
    CounterRegistry::instance().reset();
}

TEST(Counters, EveryPipelineCounterIsDocumented) {
    std::ifstream in(test::sourcePath("docs/COUNTERS.md"));
    ASSERT_TRUE(in) << "docs/COUNTERS.md missing";
    std::stringstream text;
    text << in.rdbuf();
    for (const CounterInfo& info : CounterRegistry::instance().infos()) {
        const std::string name = info.name;
        if (name.starts_with("Test/")) continue;
        EXPECT_NE(text.str().find("`" + name + "`"), std::string::npos)
            << name << " is not in docs/COUNTERS.md";
        // Its row, where the page has one, gives the unit the counter registers.
        const std::string row = "| `" + name + "` | ";
        const std::size_t at = text.str().find(row);
        if (at == std::string::npos) continue;
        const std::size_t unit = at + row.size();
        EXPECT_EQ(text.str().substr(unit, text.str().find(" |", unit) - unit), info.unit) << name;
    }
    EXPECT_NE(text.str().find("`" + std::string(sampleTestEfficiency().name) + "`"),
              std::string::npos);
}

}  // namespace
}  // namespace patchsim
