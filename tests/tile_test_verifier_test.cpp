#include "rasterizer/tile_test_verifier.h"

#include <gtest/gtest.h>

namespace patchsim {
namespace {

TEST(TileTestVerifier, BuiltInTestsNeverRejectFalselyAndAreTight) {
    const std::vector<TileTestReport> reports = verifyTileTests(1500, 42);
    ASSERT_GE(reports.size(), 4u);
    for (const TileTestReport& r : reports) {
        EXPECT_EQ(r.cases, 1500) << r.name;
        EXPECT_EQ(r.falseRejects, 0) << r.name;
        // The cases mix overlapping and missing boxes; a test that accepts everything is useless.
        EXPECT_GT(r.trueRejects, 100) << r.name;
    }
}

// A deliberately broken variant: the verifier must catch it.
class AlwaysReject : public TileTestVariant {
  public:
    std::string name() const override { return "always-reject"; }
    bool handlesDefocus() const override { return false; }
    TileTestOutput run(const TileTestInput&) const override { return {false, {}}; }
};

TEST(TileTestVerifier, CatchesATestThatRejectsOverlaps) {
    const std::size_t before = registeredTileTests().size();
    {
        const ScopedTileTest broken(std::make_unique<AlwaysReject>());
        const std::vector<TileTestReport> reports = verifyTileTests(200, 3);
        bool found = false;
        for (const TileTestReport& r : reports) {
            if (r.name != "always-reject") continue;
            found = true;
            EXPECT_GT(r.falseRejects, 0);
        }
        EXPECT_TRUE(found);
    }
    // Gone again: the tests after this one see only the real variants.
    EXPECT_EQ(registeredTileTests().size(), before);
}

}  // namespace
}  // namespace patchsim
