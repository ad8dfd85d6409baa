#include "pipeline/core/counters.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "tests/test_paths.h"

PATCHSIM_COUNTER("Test/Increments", "increments", "Counted by the counter test only",
                 testIncrements);
PATCHSIM_COUNTER_MAX("Test/Largest", "items", "Largest value seen by the counter test",
                     testLargest);

namespace patchsim {
namespace {

TEST(Counters, ThreadLocalCountsAddUpExactly) {
    CounterRegistry::instance().reset();
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t) {
        threads.emplace_back([t] {
            for (int i = 0; i < 1000; ++i) ++testIncrements;
            testLargest = std::max<std::int64_t>(testLargest, 10 * (t + 1));
            flushThreadCounters();
        });
    }
    for (auto& t : threads) t.join();
    const CounterValues values = CounterRegistry::instance().snapshot();
    EXPECT_EQ(values.at("Test/Increments"), 4000);
    EXPECT_EQ(values.at("Test/Largest"), 40);
    CounterRegistry::instance().reset();
    EXPECT_EQ(CounterRegistry::instance().snapshot().at("Test/Increments"), 0);
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
    }
}

}  // namespace
}  // namespace patchsim
