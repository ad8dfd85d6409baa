#include "rasterizer/patent/projected_bounds.h"

#include <gtest/gtest.h>

#include "rasterizer/patent/tile_frustum.h"
#include "rasterizer/verifier/tile_test_cases.h"
#include "rasterizer/verifier/tile_test_truth.h"

namespace patchsim {
namespace {

// 2DH is the 3D test in clip coordinates: the same answers and the same times, case for case.
TEST(ProjectedBounds, HomogeneousTestsAgreeWithCameraSpaceTests) {
    for (CaseModel model : {CaseModel::Pinhole, CaseModel::Lens}) {
        for (int n = 0; n < 2000; ++n) {
            const TileTestInput in = makeBoxCase(4, model, n).input;
            RasterWork work;
            const TileFrustum f3 = makeTileFrustum(*in.camera, in.lens, in.tile, 50.0f);
            const HomogeneousFrustum fh =
                makeHomogeneousFrustum(*in.camera, in.lens, in.tile, 50.0f);
            const LBBox clip = toHomogeneous(in.box);
            ASSERT_EQ(overlapsFrustum(f3, in.box, true, work),
                      overlapsHomogeneous(fh, clip, true, work));
            TimeRange t3, th;
            ASSERT_EQ(leafTimeInterval(f3, in.box, t3, work),
                      homogeneousTimeInterval(fh, clip, th, work));
            EXPECT_EQ(t3, th) << caseName(model, n);
            EXPECT_EQ(insideNearFar(f3, in.box, work), insideNearFarHomogeneous(fh, clip, work));
        }
    }
}

// A point moving in depth projects to a point moving linearly in tau, not in t: for a point the
// depth ratio is one number and the 2D interval is the exact one (to the guards).
TEST(ProjectedBounds, ScreenSpaceTimesFollowThePerspectiveMotionOfAPoint) {
    const Camera& camera = verifierCamera();
    const TileRect tile{64, 60, 72, 68};
    LBBox box;
    const Vec3 p0(-3.0f, 0.0f, -2.0f), p1(6.0f, 0.0f, -12.0f);  // right and away
    box.bounds0 = {p0, p0};
    box.bounds1 = {p1, p1};
    const ScreenMovingBox s = projectMovingBox(box, camera, {});
    ASSERT_TRUE(s.bounded);
    EXPECT_FLOAT_EQ(s.ratioMin, 6.0f);
    EXPECT_FLOAT_EQ(s.ratioMax, 6.0f);
    RasterWork work;
    TimeRange times;
    ASSERT_TRUE(screenTileTimes(makeScreenTile(camera, tile, 100.0f), s, times, work));
    const TileTruth truth = exactTileTruth(camera, {}, tile, box);
    ASSERT_TRUE(truth.hit);
    EXPECT_NEAR(times.lower, truth.times.lower, 1e-4);
    EXPECT_NEAR(times.upper, truth.times.upper, 1e-4);
    // Linear in t would have been wrong by far more: the screen position at mid-shutter is not
    // the mean of its ends.
    const float tLinear = (0.0f - (-1.5f)) / (0.5f - (-1.5f));  // x/d from -1.5 to 0.5 crosses 0
    EXPECT_GT(std::abs(tLinear - truth.times.lower), 0.3f);
}

TEST(ProjectedBounds, BoxesReachingInFrontOfTheNearPlaneAreAcceptedAtEveryTime) {
    const Camera& camera = verifierCamera();
    LBBox box;
    box.bounds0 = {{-0.1f, -0.1f, -0.2f}, {0.1f, 0.1f, -0.15f}};
    box.bounds1 = {{-0.1f, -0.1f, 0.5f}, {0.1f, 0.1f, 0.6f}};  // behind the camera at t=1
    const ScreenMovingBox s = projectMovingBox(box, camera, {});
    EXPECT_FALSE(s.bounded);
    RasterWork work;
    TimeRange times;
    const ScreenTile tile = makeScreenTile(camera, {0, 0, 4, 4}, 100.0f);
    EXPECT_TRUE(overlapsScreenTile(tile, s, true, work));
    EXPECT_TRUE(screenTileTimes(tile, s, times, work));
    EXPECT_EQ(times, TimeRange::shutter());
}

}  // namespace
}  // namespace patchsim
