#include "rasterizer/patent/tile_frustum.h"

#include <gtest/gtest.h>

#include "rasterizer/patent/tile_traversal.h"

namespace patchsim {
namespace {

Camera testCamera() {
    CameraDesc desc;
    desc.open = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}};
    desc.close = desc.open;
    return Camera(desc, ShutterDesc{}, 64, 64);
}

// A small box on the view axis seen through the centre tile, at a chosen x at t=0 and t=1.
LBBox boxMovingInX(float x0, float x1) {
    LBBox b;
    b.bounds0 = {Vec3(x0 - 0.05f, -0.05f, -5.05f), Vec3(x0 + 0.05f, 0.05f, -4.95f)};
    b.bounds1 = {Vec3(x1 - 0.05f, -0.05f, -5.05f), Vec3(x1 + 0.05f, 0.05f, -4.95f)};
    return b;
}

TEST(TileFrustum, AcceptsInsideRejectsOutsideAtBothEnds) {
    const Camera camera = testCamera();
    const TileFrustum centre = makeTileFrustum(camera, {}, {28, 28, 36, 36}, 1000);
    RasterWork work;
    EXPECT_TRUE(overlapsFrustum(centre, boxMovingInX(0, 0), true, work));
    EXPECT_FALSE(overlapsFrustum(centre, boxMovingInX(3, 3), true, work));
    EXPECT_FALSE(overlapsFrustum(centre, boxMovingInX(3, 4), true, work));  // outside at both
    EXPECT_TRUE(overlapsFrustum(centre, boxMovingInX(-3, 3), true, work));  // sweeps across
    EXPECT_GT(work.planeTests, 0);
}

// Sweeping across the tile, the box is inside only around t = 0.5: the leaf test narrows the time
// range to about that, and never below the true times.
TEST(TileFrustum, LeafTimeIntervalHoldsTheTrueCrossingTimes) {
    const Camera camera = testCamera();
    const TileFrustum centre = makeTileFrustum(camera, {}, {28, 28, 36, 36}, 1000);
    RasterWork work;
    TimeRange times = TimeRange::shutter();
    ASSERT_TRUE(leafTimeInterval(centre, boxMovingInX(-3, 3), times, work));
    EXPECT_GT(times.lower, 0.4f);
    EXPECT_LT(times.upper, 0.6f);
    // True overlap: the box's x range [-3 + 6t - 0.05, ...] meets the tile's cone at depth ~5.
    const float halfWidth = 4.0f / 32.0f * std::tan(glm::radians(20.0f)) * 5.05f;  // 4 pixels
    EXPECT_LE(times.lower, (3.0f - 0.05f - halfWidth) / 6.0f);
    EXPECT_GE(times.upper, (3.0f + 0.05f + halfWidth) / 6.0f);
    EXPECT_GT(work.timeIntervals, 0);
    TimeRange never = TimeRange::shutter();
    EXPECT_FALSE(leafTimeInterval(centre, boxMovingInX(3, 4), never, work));
}

TEST(TileFrustum, ALensWidensWhatATileSees) {
    const Camera camera = testCamera();
    const LensModel lens{0.5f, 2.0f};  // focused far in front of the box
    const TileFrustum pinhole = makeTileFrustum(camera, {}, {28, 28, 36, 36}, 1000);
    const TileFrustum thinLens = makeTileFrustum(camera, lens, {28, 28, 36, 36}, 1000);
    RasterWork work;
    const LBBox offAxis = boxMovingInX(0.6f, 0.6f);
    EXPECT_FALSE(overlapsFrustum(pinhole, offAxis, false, work));
    EXPECT_TRUE(overlapsFrustum(thinLens, offAxis, false, work));
}

TEST(TileTraversal, ReportsLeavesTimesAndWhyATileWasRejected) {
    const Camera camera = testCamera();
    MovingMesh mesh;
    // Two triangles far apart in x: leaf 0 near the axis, leaf 1 off screen.
    const LBBox near = boxMovingInX(-3, 3), far = boxMovingInX(20, 20);
    mesh.position0 = {near.bounds0.lower, near.bounds0.upper, near.bounds0.lower,
                      far.bounds0.lower,  far.bounds0.upper,  far.bounds0.lower};
    mesh.position1 = {near.bounds1.lower, near.bounds1.upper, near.bounds1.lower,
                      far.bounds1.lower,  far.bounds1.upper,  far.bounds1.lower};
    mesh.domain = {Vec2(0.1f), Vec2(0.2f), Vec2(0.1f), Vec2(0.8f), Vec2(0.9f), Vec2(0.8f)};
    mesh.indices = {0, 1, 2, 3, 4, 5};
    const std::uint32_t tris[2] = {0, 1};
    PatchHierarchy h;
    h.build(mesh, tris, 2, 1);
    ASSERT_EQ(h.leafCount(), 2);
    RasterWork work;
    const TileTraversal centre = traverseTile(
        h, makeTileFrustum(camera, {}, {28, 28, 36, 36}, 1000), true, TimeRefinement::Leaves, work);
    EXPECT_TRUE(centre.overlaps);
    EXPECT_EQ(centre.leafMask, 1u);
    EXPECT_GT(centre.times.lower, 0.4f);
    const TileTraversal corner = traverseTile(h, makeTileFrustum(camera, {}, {0, 0, 8, 8}, 1000),
                                              true, TimeRefinement::Leaves, work);
    EXPECT_FALSE(corner.overlaps);
    EXPECT_EQ(work.tilesRejectedSpace + work.tilesRejectedTime, 1);
}

}  // namespace
}  // namespace patchsim
