#include "rasterizer/patent/screen_bounds.h"

#include <gtest/gtest.h>

#include <random>

#include "core/samples.h"

namespace patchsim {
namespace {

Camera testCamera() {
    CameraDesc desc;
    desc.open = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}};  // camera space = world space
    desc.close = desc.open;
    return Camera(desc, ShutterDesc{}, 64, 48);
}

// One leaf over two moving triangles, for a hierarchy of one node.
PatchHierarchy hierarchyOf(const LBBox& box) {
    MovingMesh mesh;
    mesh.position0 = {box.bounds0.lower, box.bounds0.upper, box.bounds0.lower};
    mesh.position1 = {box.bounds1.lower, box.bounds1.upper, box.bounds1.lower};
    mesh.domain = {Vec2(0), Vec2(1), Vec2(0)};
    mesh.indices = {0, 1, 2};
    PatchHierarchy h;
    const std::uint32_t tri = 0;
    h.build(mesh, &tri, 1, 1);
    return h;
}

// Every point of the moving box at every time, seen from every lens point, projects inside the
// bounds: they are conservative for motion and defocus together.
TEST(ScreenBounds, HoldEveryPointAtEveryTimeFromEveryLensPoint) {
    const Camera camera = testCamera();
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (const LensModel lens : {LensModel{0, 1}, LensModel{0.2f, 4.0f}}) {
        for (int c = 0; c < 50; ++c) {
            LBBox box;
            const Vec3 p0(u(rng) - 0.5f, u(rng) - 0.5f, -3 - u(rng)), d(u(rng), u(rng), u(rng));
            box.bounds0 = {p0, p0 + 0.3f * d};
            box.bounds1 = {p0 + Vec3(0.4f, 0, -1), p0 + Vec3(0.4f, 0, -1) + 0.2f * d};
            const PatchHierarchy h = hierarchyOf(box);
            const ScreenBounds b = screenBounds(h, 0, camera, lens);
            ASSERT_FALSE(b.fullScreen);
            for (int k = 0; k < 200; ++k) {
                const float t = u(rng);
                const Box3 at = box.at(t);
                const Vec3 p = at.lower + Vec3(u(rng), u(rng), u(rng)) * (at.upper - at.lower);
                const Vec2 lensPoint = lens.radius * concentricDisk({u(rng), u(rng)});
                // Where a ray from the lens point through p meets the z = -1 plane (the screen of
                // rasterToScreen), for a lens focused at F: the image of p.
                const float depth = -p.z;
                const Vec2 onFocus =
                    Vec2(lensPoint) +
                    (Vec2(p.x, p.y) - lensPoint) *
                        (lens.radius > 0 ? lens.focusDistance / depth : 1.0f / depth);
                const Vec2 screen = lens.radius > 0 ? onFocus / lens.focusDistance : onFocus;
                const float tanX = camera.tanHalfFovY() * camera.aspect();
                const float px = (screen.x / tanX + 1.0f) * 0.5f * 64.0f;
                const float py = (1.0f - screen.y / camera.tanHalfFovY()) * 0.5f * 48.0f;
                ASSERT_TRUE(px >= b.x0 && px <= b.x1 && py >= b.y0 && py <= b.y1)
                    << "case " << c << " point " << k << " at " << px << "," << py;
            }
        }
    }
}

TEST(ScreenBounds, ABoxReachingThroughTheNearPlaneIsTheWholeScreen) {
    const Camera camera = testCamera();
    LBBox box;
    box.bounds0 = {Vec3(-0.1f, -0.1f, -2), Vec3(0.1f, 0.1f, -1.5f)};
    box.bounds1 = {Vec3(-0.1f, -0.1f, 0.5f), Vec3(0.1f, 0.1f, 1)};  // behind the camera at t=1
    const ScreenBounds b = screenBounds(hierarchyOf(box), 0, camera, LensModel{});
    EXPECT_TRUE(b.fullScreen);
    const TileRange tiles = tilesCovering(b, TileGrid{64, 48, 8});
    EXPECT_EQ(tiles.x0, 0);
    EXPECT_EQ(tiles.y0, 0);
    EXPECT_EQ(tiles.x1, 8);
    EXPECT_EQ(tiles.y1, 6);
}

TEST(ScreenBounds, TilesCoverTheBoundsPlusAPixelAndNothingOffScreen) {
    const TileGrid grid{64, 48, 8};
    const TileRange r = tilesCovering({10.5f, 3.0f, 17.9f, 8.0f, false}, grid);
    EXPECT_EQ(r.x0, 1);
    EXPECT_EQ(r.x1, 3);
    EXPECT_EQ(r.y0, 0);
    EXPECT_EQ(r.y1, 2);  // a sample at y = 8.0 belongs to row 1
    EXPECT_TRUE(tilesCovering({-20, -20, -10, -10, false}, grid).empty());
    EXPECT_TRUE(tilesCovering({70, 50, 80, 60, false}, grid).empty());
    EXPECT_EQ(grid.rect(7, 5).x1, 64);
    EXPECT_EQ(grid.tilesX(), 8);
    EXPECT_EQ(TileGrid({65, 48, 8}).tilesX(), 9);
    EXPECT_EQ(TileGrid({65, 48, 8}).rect(8, 0).x1, 65);
}

}  // namespace
}  // namespace patchsim
