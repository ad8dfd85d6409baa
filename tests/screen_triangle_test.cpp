#include "rasterizer/common/screen_triangle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/ray.h"
#include "rasterizer/common/watertight_triangle.h"
#include "tests/test_camera.h"

namespace patchsim {
namespace {

using test::atRaster;
Camera testCamera() {
    return test::smallCamera();
}

bool covers(const ScreenTriangle& t, double x, double y) {
    ScreenHit hit;
    return t.kind == ScreenTriangle::Kind::Covers &&
           coverSample(t, x, y, 0.0f, std::numeric_limits<float>::infinity(), hit);
}

// A mesh of 8 x 6 quads over the frame at varying depth, its inner vertices jittered except on
// every other row and every third column (so edges also run along pixel lines), each quad split
// along a diagonal chosen at random and each triangle wound either way: every sub-pixel lattice
// point strictly inside the mesh, on edges and vertices included, is covered by exactly one
// triangle.
TEST(ScreenTriangle, EverySubpixelInsideAMeshIsCoveredExactlyOnce) {
    const Camera camera = testCamera();
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> jitter(-2.5f, 2.5f), depth(2.0f, 9.0f);
    constexpr int kColumns = 8, kRows = 6;
    std::vector<Vec3> grid;
    for (int j = 0; j <= kRows; ++j)
        for (int i = 0; i <= kColumns; ++i) {
            const bool inner = i > 0 && i < kColumns && j > 0 && j < kRows;
            // Some inner vertices on exact pixel corners, so edges run along lattice lines.
            const bool snapped = j % 2 == 0 || i % 3 == 0;
            const float x = 4.0f + 7.0f * float(i) + (inner && !snapped ? jitter(rng) : 0.0f);
            const float y = 3.0f + 7.0f * float(j) + (inner && !snapped ? jitter(rng) : 0.0f);
            grid.push_back(atRaster(camera, x, y, depth(rng)));
        }
    std::vector<ScreenTriangle> triangles;
    int reversedCount = 0;
    for (int j = 0; j < kRows; ++j)
        for (int i = 0; i < kColumns; ++i) {
            const Vec3& a = grid[std::size_t(j * (kColumns + 1) + i)];
            const Vec3& b = grid[std::size_t(j * (kColumns + 1) + i + 1)];
            const Vec3& c = grid[std::size_t((j + 1) * (kColumns + 1) + i)];
            const Vec3& d = grid[std::size_t((j + 1) * (kColumns + 1) + i + 1)];
            // Either winding: the tie rule must hold after the orientation flip.
            const auto add = [&](const Vec3& p, const Vec3& q, const Vec3& r) {
                const bool reverse = rng() % 2;
                reversedCount += reverse;
                triangles.push_back(reverse ? setupScreenTriangle(camera, r, q, p)
                                            : setupScreenTriangle(camera, p, q, r));
            };
            if (rng() % 2) {
                add(a, b, d);
                add(d, c, a);
            } else {
                add(a, b, c);
                add(b, d, c);
            }
        }
    int onEdges = 0;
    // The mesh's outer rows and columns are straight lines at raster 4, 60 and 3, 45.
    for (const ScreenTriangle& t : triangles) ASSERT_EQ(t.kind, ScreenTriangle::Kind::Covers);
    for (int y = 3 * 256 + 1; y < 45 * 256; y += 5)
        for (int x = 4 * 256 + 1; x < 60 * 256; x += 5) {
            int count = 0;
            for (const ScreenTriangle& t : triangles) {
                const int px = x / 256, py = y / 256;
                if (px < t.pixelX0 || px >= t.pixelX1 || py < t.pixelY0 || py >= t.pixelY1)
                    continue;
                count += covers(t, x, y);
                for (int k = 0; k < 3; ++k)
                    onEdges += t.a[k] * (x - t.x0[k]) + t.b[k] * (y - t.y0[k]) == 0.0;
            }
            ASSERT_EQ(count, 1) << "sub-pixel (" << x << ", " << y << ")";
        }
    EXPECT_GT(onEdges, 1000) << "the lattice should put many samples exactly on edges";
    EXPECT_GT(reversedCount, 10) << "both orientations, so the flip is exercised";
}

void expectTopLeftSquare(bool reversed) {
    const Camera camera = testCamera();
    const Vec3 topLeft = atRaster(camera, 10, 10, 3), topRight = atRaster(camera, 20, 10, 3);
    const Vec3 bottomLeft = atRaster(camera, 10, 20, 3), bottomRight = atRaster(camera, 20, 20, 3);
    const ScreenTriangle upper = reversed
                                     ? setupScreenTriangle(camera, bottomRight, topRight, topLeft)
                                     : setupScreenTriangle(camera, topLeft, topRight, bottomRight);
    const ScreenTriangle lower =
        reversed ? setupScreenTriangle(camera, topLeft, bottomLeft, bottomRight)
                 : setupScreenTriangle(camera, bottomRight, bottomLeft, topLeft);
    const auto inSquare = [&](double x, double y) {
        return int(covers(upper, x * 256, y * 256)) + int(covers(lower, x * 256, y * 256));
    };
    EXPECT_EQ(inSquare(15, 10), 1) << "top edge";
    EXPECT_EQ(inSquare(10, 15), 1) << "left edge";
    EXPECT_EQ(inSquare(10, 10), 1) << "top-left corner";
    EXPECT_EQ(inSquare(15, 20), 0) << "bottom edge";
    EXPECT_EQ(inSquare(20, 15), 0) << "right edge";
    EXPECT_EQ(inSquare(20, 20), 0) << "bottom-right corner";
    EXPECT_EQ(inSquare(20, 10), 0) << "top-right corner (on the right edge)";
    EXPECT_EQ(inSquare(10, 20), 0) << "bottom-left corner (on the bottom edge)";
    EXPECT_EQ(inSquare(15, 15), 1) << "the diagonal";
    EXPECT_EQ(inSquare(12.5, 12.5), 1) << "the diagonal";
}

// D3D11's rule for a square of two triangles, wound either way: samples on its top and left
// edges are inside, on its bottom and right edges outside, and the shared diagonal belongs to one
// triangle.
TEST(ScreenTriangle, TheTopLeftRuleOwnsTopAndLeftEdges) {
    for (const bool reversed : {false, true}) {
        SCOPED_TRACE(reversed ? "clockwise on screen" : "counter-clockwise on screen");
        expectTopLeftSquare(reversed);
    }
}

// Away from its edges, the screen test finds the ray test's hit: the same depth and barycentrics,
// up to the snapping of the vertices to 1/256 pixel.
TEST(ScreenTriangle, DepthAndBarycentricsAgreeWithTheRayTest) {
    const Camera camera = testCamera();
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> x(0.0f, 64.0f), y(0.0f, 48.0f), depth(1.0f, 50.0f);
    int compared = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const Vec3 v[3] = {atRaster(camera, x(rng), y(rng), depth(rng)),
                           atRaster(camera, x(rng), y(rng), depth(rng)),
                           atRaster(camera, x(rng), y(rng), depth(rng))};
        const ScreenTriangle t = setupScreenTriangle(camera, v[0], v[1], v[2]);
        if (t.kind != ScreenTriangle::Kind::Covers) continue;
        for (int s = 0; s < 20; ++s) {
            const Vec2 raster(x(rng), y(rng));
            const Ray ray = makeCameraRay(camera, rasterToScreen(camera, raster), Vec2(0.0f), 0.0f,
                                          LensModel{});
            TriangleHit rayHit;
            if (!intersectTriangle(shearRay(ray), v[0], v[1], v[2], 0.0f, 1e9f, rayHit)) continue;
            // Only samples well inside (every weight above 5%), where snapping cannot flip them.
            if (rayHit.b0 < 0.05f || rayHit.b1 < 0.05f || rayHit.b2 < 0.05f) continue;
            ScreenHit hit;
            ASSERT_TRUE(coverSample(t, std::round(double(raster.x) * 256.0),
                                    std::round(double(raster.y) * 256.0), 0.0f, 1e9f, hit));
            EXPECT_NEAR(hit.depth, rayHit.lambda, 2e-3f * rayHit.lambda);
            EXPECT_NEAR(hit.b1, rayHit.b1, 0.02f);
            EXPECT_NEAR(hit.b2, rayHit.b2, 0.02f);
            ++compared;
        }
    }
    EXPECT_GT(compared, 200);
}

// Rounding to the sub-pixel grid: ties to even, and a sample stays inside its pixel.
TEST(ScreenTriangle, SamplesSnapToTheirPixelsSubpixelGrid) {
    EXPECT_EQ(roundToInteger(2.5), 2.0);
    EXPECT_EQ(roundToInteger(3.5), 4.0);
    EXPECT_EQ(roundToInteger(-2.5), -2.0);
    EXPECT_EQ(roundToInteger(-2.75), -3.0);
    EXPECT_EQ(roundToInteger(8388607.4), 8388607.0);
    EXPECT_EQ(sampleSubpixel(3, 0.0f), 768.0);
    EXPECT_EQ(sampleSubpixel(3, 0.5f), 896.0);
    EXPECT_EQ(sampleSubpixel(3, 0.99999f), 1023.0) << "not the next pixel's 1024";
    EXPECT_EQ(sampleSubpixel(3, 1.0f / 512.0f), 768.0) << "a tie, to even";
}

TEST(ScreenTriangle, TrianglesWithNoFixedPointFormTakeRays) {
    const Camera camera = testCamera();
    const Vec3 a = atRaster(camera, 10, 10, 3), b = atRaster(camera, 20, 10, 3);
    const Vec3 c = atRaster(camera, 10, 20, 3);
    EXPECT_EQ(setupScreenTriangle(camera, a, b, c).kind, ScreenTriangle::Kind::Covers);
    // A vertex behind the eye, on the camera plane, or far outside the guard band.
    EXPECT_EQ(setupScreenTriangle(camera, a, b, Vec3(0.1f, 0.1f, 1.0f)).kind,
              ScreenTriangle::Kind::NeedsRay);
    EXPECT_EQ(setupScreenTriangle(camera, a, b, Vec3(0.1f, 0.1f, 0.0f)).kind,
              ScreenTriangle::Kind::NeedsRay);
    EXPECT_EQ(setupScreenTriangle(camera, a, b, atRaster(camera, 40000, 10, 3)).kind,
              ScreenTriangle::Kind::NeedsRay);
    EXPECT_EQ(setupScreenTriangle(camera, a, b, Vec3(std::nanf(""), 0.0f, -3.0f)).kind,
              ScreenTriangle::Kind::NeedsRay);
    // No area on the sub-pixel grid, or wholly off the screen: nothing to test.
    EXPECT_EQ(setupScreenTriangle(camera, a, b, atRaster(camera, 15, 10, 5)).kind,
              ScreenTriangle::Kind::Empty);
    EXPECT_EQ(setupScreenTriangle(camera, atRaster(camera, 100, 10, 3),
                                  atRaster(camera, 110, 10, 3), atRaster(camera, 100, 20, 3))
                  .kind,
              ScreenTriangle::Kind::Empty);
}

}  // namespace
}  // namespace patchsim
