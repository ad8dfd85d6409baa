#include "core/samples.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace patchsim {
namespace {

const Effects kAll{true, false, true, false};

TEST(Samples, APureFunctionOfSeedPixelAndIndex) {
    const SampleGenerator a(7, 16, kAll), b(7, 16, kAll), c(8, 16, kAll);
    for (int s = 0; s < 16; ++s) {
        const Sample x = a.sample(3, 5, s), y = b.sample(3, 5, s), z = c.sample(3, 5, s);
        EXPECT_EQ(x.time, y.time);
        EXPECT_EQ(x.pixelOffset, y.pixelOffset);
        EXPECT_EQ(x.lens, y.lens);
        EXPECT_NE(x.time, z.time);
    }
}

// Each dimension is stratified within a pixel: with n samples, one time per [k/n, (k+1)/n), one
// lens u per stratum, and (square n) one position per cell of the sqrt(n) x sqrt(n) grid.
TEST(Samples, EveryDimensionIsStratifiedWithinAPixel) {
    for (int n : {4, 16, 7}) {
        const SampleGenerator g(3, n, kAll);
        for (int pixel = 0; pixel < 20; ++pixel) {
            std::set<int> times, lensU, cells;
            for (int s = 0; s < n; ++s) {
                const Sample smp = g.sample(pixel, 2 * pixel, s);
                ASSERT_GE(smp.time, 0.0f);
                ASSERT_LE(smp.time, 1.0f);
                ASSERT_TRUE(smp.pixelOffset.x >= 0 && smp.pixelOffset.x < 1);
                ASSERT_TRUE(smp.pixelOffset.y >= 0 && smp.pixelOffset.y < 1);
                times.insert(int(smp.time * float(n)));
                lensU.insert(int(smp.lens.x * float(n)));
                const int side = n == 7 ? 7 : int(std::sqrt(double(n)));
                cells.insert(int(smp.pixelOffset.x * float(side)) * 100 +
                             int(smp.pixelOffset.y * float(side)));
            }
            EXPECT_EQ(times.size(), std::size_t(n)) << n;
            EXPECT_EQ(lensU.size(), std::size_t(n)) << n;
            if (n != 7) {
                EXPECT_EQ(cells.size(), std::size_t(n)) << n;
            }
        }
    }
}

TEST(Samples, DimensionsTheSceneDoesNotCallForAreFixed) {
    const SampleGenerator still(1, 8, Effects{});
    for (int s = 0; s < 8; ++s) {
        EXPECT_EQ(still.sample(1, 1, s).time, 0.0f);
        EXPECT_EQ(still.sample(1, 1, s).lens, Vec2(0.5f, 0.5f));
    }
    Effects shading;
    shading.shadingVaries = true;  // a material that changes: times, but no lens
    const SampleGenerator timed(1, 8, shading);
    std::set<float> times;
    for (int s = 0; s < 8; ++s) times.insert(timed.sample(1, 1, s).time);
    EXPECT_EQ(times.size(), 8u);
}

TEST(Samples, GridPatternReachesBothEndsOfTimeAndLens) {
    const SampleGenerator g(1, 9, kAll, SamplePattern::Grid);
    float lo = 1, hi = 0;
    for (int s = 0; s < 9; ++s) {
        lo = std::min(lo, g.sample(0, 0, s).time);
        hi = std::max(hi, g.sample(0, 0, s).time);
        const Vec2 o = g.sample(0, 0, s).pixelOffset;
        EXPECT_EQ(o.x * 3.0f, std::floor(o.x * 3.0f));  // on the stratum corners
    }
    EXPECT_EQ(lo, 0.0f);
    EXPECT_EQ(hi, 1.0f);
}

TEST(Samples, ConcentricMapIsOntoTheUnitDisk) {
    EXPECT_EQ(concentricDisk({0.5f, 0.5f}), Vec2(0, 0));
    for (float u : {0.0f, 0.1f, 0.5f, 0.99f})
        for (float v : {0.0f, 0.3f, 0.7f, 1.0f})
            EXPECT_LE(glm::length(concentricDisk({u, v})), 1.0f + 1e-6f);
    EXPECT_NEAR(glm::length(concentricDisk({1.0f, 0.5f})), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace patchsim
