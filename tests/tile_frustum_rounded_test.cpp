#include "rasterizer/patent/tile_frustum_rounded.h"

#include <gtest/gtest.h>

#include <cmath>

namespace patchsim {
namespace {

Camera testCamera() {
    CameraDesc desc;
    desc.open = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}};
    desc.close = desc.open;
    return Camera(desc, ShutterDesc{}, 64, 64);
}

LBBox boxMovingInX(float x0, float x1, float halfSize = 0.05f, float depth = 5) {
    LBBox b;
    b.bounds0 = {Vec3(x0 - halfSize, -halfSize, -depth - halfSize),
                 Vec3(x0 + halfSize, halfSize, -depth + halfSize)};
    b.bounds1 = {Vec3(x1 - halfSize, -halfSize, -depth - halfSize),
                 Vec3(x1 + halfSize, halfSize, -depth + halfSize)};
    return b;
}

const NumberFormat kFormats[] = {NumberFormat::fp16(), NumberFormat::bf16(),
                                 NumberFormat::fixed(16, 8)};

// Sweeping across the centre tile, every format's bounded interval holds the true crossing
// times (tile_frustum_test's figures) and still narrows the shutter.
TEST(TileFrustumRounded, BoundedIntervalsHoldTheTrueCrossingTimes) {
    const Camera camera = testCamera();
    const TileFrustum centre = makeTileFrustum(camera, {}, {28, 28, 36, 36}, 1000);
    const float halfWidth = 4.0f / 32.0f * std::tan(glm::radians(20.0f)) * 5.05f;
    for (const NumberFormat& format : kFormats) {
        RasterWork work;
        TimeRange times = TimeRange::shutter();
        ASSERT_TRUE(leafTimeIntervalRounded(centre, boxMovingInX(-3, 3), RoundedArithmetic(format),
                                            PlaneErrorHandling::Bounded, times, work));
        EXPECT_LE(times.lower, (3.0f - 0.05f - halfWidth) / 6.0f) << formatName(format);
        EXPECT_GE(times.upper, (3.0f + 0.05f + halfWidth) / 6.0f) << formatName(format);
        EXPECT_GT(times.lower, 0.3f) << formatName(format);
        EXPECT_LT(times.upper, 0.7f) << formatName(format);
        EXPECT_GT(work.timeIntervals, 0);
        TimeRange never = TimeRange::shutter();
        EXPECT_FALSE(leafTimeIntervalRounded(centre, boxMovingInX(3, 4), RoundedArithmetic(format),
                                             PlaneErrorHandling::Bounded, never, work))
            << formatName(format) << ": the bound must not accept everything";
    }
}

bool fp32Accepts(const TileFrustum& tile, float x, float depth) {
    RasterWork work;
    TimeRange times = TimeRange::shutter();
    return leafTimeInterval(tile, boxMovingInX(x, x, 0.05f, depth), times, work);
}

// A static box slid in steps of 1e-5 units across the right plane of a tile at the screen's
// right edge (where the plane leans most, so its rounding is largest against the tile guard):
// wherever the fp32 test accepts, the bounded test accepts in every format (its margin is the
// format's rounding, far above fp32's own), while the naive one, comparing rounded distances with
// zero, rejects some.
TEST(TileFrustumRounded, NearAPlaneOnlyTheNaiveDatapathRejectsWhatFp32Accepts) {
    const Camera camera = testCamera();
    const TileFrustum tile = makeTileFrustum(camera, {}, {56, 28, 64, 36}, 1000);
    // At several depths, so that the depth's rounding goes against the box at some of them.
    const float depths[] = {4.99f, 5.05f, 6.3f, 7.7f, 9.9f, 13.1f};
    for (const NumberFormat& format : kFormats) {
        const RoundedArithmetic arithmetic(format);
        int accepted = 0, boundedLosses = 0, naiveLosses = 0;
        for (const float depth : depths) {
            float inside = 0.3f * depth, outside = 0.5f * depth;  // bisect for the plane
            ASSERT_TRUE(fp32Accepts(tile, inside, depth));
            ASSERT_FALSE(fp32Accepts(tile, outside, depth));
            for (int i = 0; i < 40; ++i) {
                const float middle = 0.5f * (inside + outside);
                (fp32Accepts(tile, middle, depth) ? inside : outside) = middle;
            }
            for (int step = -2000; step <= 0; ++step) {
                const float x = inside + float(step) * 1e-5f;
                if (!fp32Accepts(tile, x, depth)) continue;
                ++accepted;
                const LBBox box = boxMovingInX(x, x, 0.05f, depth);
                RasterWork work;
                TimeRange bounded = TimeRange::shutter(), naive = bounded;
                boundedLosses += !leafTimeIntervalRounded(
                    tile, box, arithmetic, PlaneErrorHandling::Bounded, bounded, work);
                naiveLosses += !leafTimeIntervalRounded(tile, box, arithmetic,
                                                        PlaneErrorHandling::Naive, naive, work);
            }
        }
        EXPECT_EQ(accepted, 6 * 2001) << formatName(format);
        EXPECT_EQ(boundedLosses, 0) << formatName(format);
        EXPECT_GT(naiveLosses, 0) << formatName(format);
    }
}

// A box beyond fixed point's range: the bounded test cannot bound its distances and gives the
// planes up (inside at every time) instead of trusting saturated values.
TEST(TileFrustumRounded, BeyondAFixedPointRangeTheBoundedTestAccepts) {
    const Camera camera = testCamera();
    const TileFrustum centre = makeTileFrustum(camera, {}, {28, 28, 36, 36}, 1e6f);
    LBBox far = boxMovingInX(0, 0, 0.05f);
    far.bounds0.lower.z = far.bounds1.lower.z = -50000.0f;  // reaches deep, as the true box does
    RasterWork work;
    TimeRange fp32Times = TimeRange::shutter(), bounded = fp32Times;
    ASSERT_TRUE(leafTimeInterval(centre, far, fp32Times, work));
    EXPECT_TRUE(leafTimeIntervalRounded(centre, far, RoundedArithmetic(NumberFormat::fixed(8, 4)),
                                        PlaneErrorHandling::Bounded, bounded, work));
    EXPECT_EQ(bounded, TimeRange::shutter());
}

}  // namespace
}  // namespace patchsim
