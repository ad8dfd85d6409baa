#include "rasterizer/common/lens_triangle.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/ray.h"
#include "core/samples.h"
#include "rasterizer/common/watertight_triangle.h"
#include "tests/test_camera.h"

namespace patchsim {
namespace {

using test::atRaster;
Camera testCamera() {
    return test::smallCamera();
}

constexpr float kInfinity = std::numeric_limits<float>::infinity();

bool covers(const LensTriangle& t, Vec2 screen, Vec2 lensPoint, ScreenHit& hit) {
    return t.kind == LensTriangle::Kind::Covers &&
           coverLensSample(t, screen.x, screen.y, lensPoint.x, lensPoint.y, 0.0f, kInfinity, hit);
}

// Away from its edges the lens test finds the ray test's hit, and misses where the ray misses:
// random triangles in front of and behind the focus distance, random samples and lens points.
// Every covered sample also lies in the triangle's pixels across the lens.
TEST(LensTriangle, AgreesWithTheRayTestAwayFromEdges) {
    const Camera camera = testCamera();
    const LensModel lens{0.4f, 6.0f};
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> x(-8.0f, 72.0f), y(-8.0f, 56.0f), depth(1.0f, 30.0f);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    int hits = 0, misses = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const Vec3 v[3] = {atRaster(camera, x(rng), y(rng), depth(rng)),
                           atRaster(camera, x(rng), y(rng), depth(rng)),
                           atRaster(camera, x(rng), y(rng), depth(rng))};
        const LensTriangle t = setupLensTriangle(camera, lens, v[0], v[1], v[2]);
        ASSERT_EQ(t.kind == LensTriangle::Kind::NeedsRay, false);
        for (int s = 0; s < 200; ++s) {
            const Vec2 raster(unit(rng) * 64.0f, unit(rng) * 48.0f);
            const Vec2 screen = rasterToScreen(camera, raster);
            const Ray ray =
                makeCameraRay(camera, screen, concentricDisk({unit(rng), unit(rng)}), 0.0f, lens);
            TriangleHit rayHit;
            const bool rayCovers =
                intersectTriangle(shearRay(ray), v[0], v[1], v[2], 0.0f, 1e9f, rayHit);
            ScreenHit hit{};
            const bool lensCovers = covers(t, screen, {ray.origin.x, ray.origin.y}, hit);
            if (lensCovers) {
                EXPECT_TRUE(raster.x >= float(t.pixels.x0) && raster.x < float(t.pixels.x1) &&
                            raster.y >= float(t.pixels.y0) && raster.y < float(t.pixels.y1));
            }
            const float b0 = 1.0f - hit.b1 - hit.b2;
            if (rayCovers && std::min({rayHit.b0, rayHit.b1, rayHit.b2}) > 1e-3f) {
                ASSERT_TRUE(lensCovers) << "trial " << trial << " sample " << s;
                EXPECT_NEAR(hit.depth, rayHit.lambda * ray.depthPerLambda,
                            1e-3f * rayHit.lambda * ray.depthPerLambda);
                EXPECT_NEAR(hit.b1, rayHit.b1, 1e-3f);
                EXPECT_NEAR(hit.b2, rayHit.b2, 1e-3f);
                ++hits;
            } else if (lensCovers && std::min({b0, hit.b1, hit.b2}) > 1e-3f) {
                ADD_FAILURE() << "the lens test covers what the ray misses, trial " << trial;
            } else if (!rayCovers && !lensCovers) {
                ++misses;
            }
        }
    }
    EXPECT_GT(hits, 2000);
    EXPECT_GT(misses, 20000);
}

// A mesh of 8 x 6 quads with its border at one depth and its inner vertices jittered in screen
// and in depth (in front of and behind the focus), each quad split along a random diagonal and
// each triangle wound either way. From any lens point the border is the same rectangle shifted,
// and the lens is small enough (images move by at most 0.6 pixel) that the mesh never folds over
// itself, so every sample inside the border is covered by exactly one triangle: no crack, no
// double hit. Samples
// exactly on the inner vertices, seen from the lens centre, put two edge functions of every
// triangle around them at exactly zero, and the tie rule gives each to one triangle.
TEST(LensTriangle, EverySampleInsideAMeshIsCoveredExactlyOnce) {
    const Camera camera = testCamera();
    const LensModel lens{0.05f, 5.0f};
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> jitter(-2.5f, 2.5f), depth(2.0f, 12.0f);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    constexpr int kColumns = 8, kRows = 6;
    constexpr float kBorderDepth = 8.0f;
    std::vector<Vec3> grid;
    for (int j = 0; j <= kRows; ++j)
        for (int i = 0; i <= kColumns; ++i) {
            const bool inner = i > 0 && i < kColumns && j > 0 && j < kRows;
            const float px = 4.0f + 7.0f * float(i) + (inner ? jitter(rng) : 0.0f);
            const float py = 3.0f + 7.0f * float(j) + (inner ? jitter(rng) : 0.0f);
            grid.push_back(atRaster(camera, px, py, inner ? depth(rng) : kBorderDepth));
        }
    std::vector<LensTriangle> triangles;
    int reversedCount = 0;
    const auto add = [&](const Vec3& p, const Vec3& q, const Vec3& r) {
        const bool reverse = rng() % 2;
        reversedCount += reverse;
        triangles.push_back(reverse ? setupLensTriangle(camera, lens, r, q, p)
                                    : setupLensTriangle(camera, lens, p, q, r));
    };
    for (int j = 0; j < kRows; ++j)
        for (int i = 0; i < kColumns; ++i) {
            const Vec3& a = grid[std::size_t(j * (kColumns + 1) + i)];
            const Vec3& b = grid[std::size_t(j * (kColumns + 1) + i + 1)];
            const Vec3& c = grid[std::size_t((j + 1) * (kColumns + 1) + i)];
            const Vec3& d = grid[std::size_t((j + 1) * (kColumns + 1) + i + 1)];
            if (rng() % 2) {
                add(a, b, d);
                add(d, c, a);
            } else {
                add(a, b, c);
                add(b, d, c);
            }
        }
    for (const LensTriangle& t : triangles) ASSERT_EQ(t.kind, LensTriangle::Kind::Covers);
    const auto coverCount = [&](Vec2 screen, Vec2 lensPoint) {
        int count = 0;
        ScreenHit hit{};
        for (const LensTriangle& t : triangles) count += covers(t, screen, lensPoint, hit);
        return count;
    };
    // The border's corners on the plane z = -1, and its shift per unit of lens offset.
    const Vec2 lo = rasterToScreen(camera, Vec2(4.0f, 45.0f));
    const Vec2 hi = rasterToScreen(camera, Vec2(60.0f, 3.0f));
    const float borderBlur = 1.0f / lens.focusDistance - 1.0f / kBorderDepth;
    for (int s = 0; s < 200000; ++s) {
        const Vec2 lensPoint = lens.radius * concentricDisk({unit(rng), unit(rng)});
        // Strictly inside the shifted border (a margin against the float edge at the border).
        const float u = 0.001f + 0.998f * unit(rng), w = 0.001f + 0.998f * unit(rng);
        const Vec2 screen(lo.x + u * (hi.x - lo.x) + borderBlur * lensPoint.x,
                          lo.y + w * (hi.y - lo.y) + borderBlur * lensPoint.y);
        ASSERT_EQ(coverCount(screen, lensPoint), 1) << "sample " << s;
    }
    int vertices = 0;
    for (int j = 1; j < kRows; ++j)
        for (int i = 1; i < kColumns; ++i) {
            const LensVertex v =
                projectThroughLens(lens, grid[std::size_t(j * (kColumns + 1) + i)]);
            EXPECT_EQ(coverCount({v.x, v.y}, {0.0f, 0.0f}), 1) << "inner vertex " << i << ", " << j;
            ++vertices;
        }
    EXPECT_EQ(vertices, (kRows - 1) * (kColumns - 1));
    EXPECT_GT(reversedCount, 10) << "both windings, so the canonical edge order is exercised";
}

// A sample exactly on a vertex's image seen from a lens point off the centre: the vertex is in
// focus (its image does not move with the lens point), and the fan of three triangles around it
// does not fold from that lens point. Its two edge functions at the vertex are exactly zero in
// each triangle; the tie rule (the sample moved by (eps, eps^2)) gives it to exactly one. (A
// review found this case; the rule before it, the canonical edge's positive side, gave it to
// none.)
TEST(LensTriangle, ASampleOnAVertexImageOffTheLensCentreIsCoveredOnce) {
    const Camera camera = testCamera();
    const LensModel lens{1.0f, 1.0f};
    const Vec3 v(0.0f, 0.0f, -1.0f);
    const Vec3 w[3] = {
        {0x1.ap-5f, 0x1.3p-5f, -0.25f}, {0.0f, 0.5f, -2.0f}, {0x1.2p-3f, -0x1.78p-1f, -4.0f}};
    const Vec2 lensPoint(-0.875f, -0.125f);
    int count = 0, zeros = 0;
    for (int k = 0; k < 3; ++k) {
        const LensTriangle t = setupLensTriangle(camera, lens, v, w[k], w[(k + 1) % 3]);
        ASSERT_EQ(t.kind, LensTriangle::Kind::Covers);
        for (int i = 0; i < 3; ++i)
            zeros += lensEdgeFunction(t, i, 0.0f, 0.0f, lensPoint.x, lensPoint.y).e == 0.0f;
        ScreenHit hit{};
        count += coverLensSample(t, 0.0f, 0.0f, lensPoint.x, lensPoint.y, 0.0f, kInfinity, hit);
    }
    EXPECT_EQ(zeros, 6) << "two edges of each triangle exactly through the sample";
    EXPECT_EQ(count, 1);
}

// A triangle seen from its back from some lens points is still covered there (both faces count,
// as in the ray test): a triangle whose plane passes between the lens's two sides.
TEST(LensTriangle, BothFacesCountAsTheLensCrossesTheTrianglesPlane) {
    const Camera camera = testCamera();
    const LensModel lens{1.0f, 4.0f};
    // The plane x = 0.2 z + 0.05 through the lens plane at x = 0.05, inside the lens radius.
    const Vec3 a(0.05f - 0.2f * 3.0f, -0.5f, -3.0f), b(0.05f - 0.2f * 5.0f, -0.5f, -5.0f);
    const Vec3 c(0.05f - 0.2f * 4.0f, 0.8f, -4.0f);
    const LensTriangle t = setupLensTriangle(camera, lens, a, b, c);
    ASSERT_EQ(t.kind, LensTriangle::Kind::Covers);
    const Vec3 target = (a + b + c) / 3.0f;
    int facing[2] = {0, 0};  // from lens points on either side of the plane: +1 or -1
    for (const float lx : {-0.9f, 0.9f}) {
        // Aim the sample at the triangle's centroid from this lens point: the focus-plane point
        // on the line from (lx, 0, 0) through the centroid, scaled to z = -1.
        const Vec3 from(lx, 0.0f, 0.0f);
        const Vec3 focus = from + (target - from) * (lens.focusDistance / -target.z);
        const Vec2 screen(focus.x / lens.focusDistance, focus.y / lens.focusDistance);
        ScreenHit hit{};
        ASSERT_TRUE(covers(t, screen, {lx, 0.0f}, hit)) << "lens x " << lx;
        // The triangle's orientation as this lens point sees it: the sign of its image's area,
        // the sum of its oriented edge functions at any point.
        float area = 0.0f;
        for (int i = 0; i < 3; ++i) {
            const float e = lensEdgeFunction(t, i, screen.x, screen.y, lx, 0.0f).e;
            area += t.flipped[i] ? -e : e;
        }
        facing[lx > 0] = area > 0.0f ? 1 : -1;
        EXPECT_NEAR(hit.depth, -target.z, 1e-3f);
        EXPECT_NEAR(hit.b1, 1.0f / 3.0f, 1e-3f);
    }
    EXPECT_EQ(facing[0] * facing[1], -1) << "the two lens points see opposite faces";
}

TEST(LensTriangle, TrianglesWithNoLensFormTakeRays) {
    const Camera camera = testCamera();
    const LensModel lens{0.2f, 5.0f};
    const Vec3 a = atRaster(camera, 10, 10, 3), b = atRaster(camera, 20, 10, 3);
    const Vec3 c = atRaster(camera, 10, 20, 3);
    EXPECT_EQ(setupLensTriangle(camera, lens, a, b, c).kind, LensTriangle::Kind::Covers);
    // A vertex behind the lens or on its plane, not finite, or beyond the guard band.
    EXPECT_EQ(setupLensTriangle(camera, lens, a, b, Vec3(0.1f, 0.1f, 1.0f)).kind,
              LensTriangle::Kind::NeedsRay);
    EXPECT_EQ(setupLensTriangle(camera, lens, a, b, Vec3(0.1f, 0.1f, 0.0f)).kind,
              LensTriangle::Kind::NeedsRay);
    EXPECT_EQ(setupLensTriangle(camera, lens, a, b, Vec3(std::nanf(""), 0.0f, -3.0f)).kind,
              LensTriangle::Kind::NeedsRay);
    EXPECT_EQ(setupLensTriangle(camera, lens, a, b, atRaster(camera, 40000, 10, 3)).kind,
              LensTriangle::Kind::NeedsRay);
    // So near the lens that its circle of confusion reaches past the guard band.
    EXPECT_EQ(setupLensTriangle(camera, lens, a, b, atRaster(camera, 15, 15, 1e-4f)).kind,
              LensTriangle::Kind::NeedsRay);
    // Wholly off the screen from every lens point: nothing to test.
    EXPECT_EQ(setupLensTriangle(camera, lens, atRaster(camera, 100, 10, 5),
                                atRaster(camera, 110, 10, 5), atRaster(camera, 100, 20, 5))
                  .kind,
              LensTriangle::Kind::Empty);
}

// The pixels across the lens hold every vertex's image from every lens point, and from one lens
// point the pixels of its three images only.
TEST(LensTriangle, PixelsSpanTheCircleOfConfusion) {
    const Camera camera = testCamera();
    // A vertex 5 in front of the focus plane at 10 and radius 0.5: c = 1/10 - 1/5 = -0.1, spread
    // 0.05 on the plane z = -1, i.e. 0.05 / tan(30 deg) * 24 = 2.08 pixels.
    const LensModel lens{0.5f, 10.0f};
    const LensTriangle t =
        setupLensTriangle(camera, lens, atRaster(camera, 20.5f, 20.5f, 5),
                          atRaster(camera, 30.5f, 20.5f, 5), atRaster(camera, 20.5f, 30.5f, 5));
    ASSERT_EQ(t.kind, LensTriangle::Kind::Covers);
    EXPECT_EQ(t.pixels.x0, 18);
    EXPECT_EQ(t.pixels.x1, 33);
    EXPECT_EQ(t.pixels.y0, 18);
    EXPECT_EQ(t.pixels.y1, 33);
    const LensPixels centre = lensPixelsFrom(camera, t, 0.0f, 0.0f);
    EXPECT_EQ(centre.x0, 20);
    EXPECT_EQ(centre.x1, 31);
    EXPECT_EQ(centre.y0, 20);
    EXPECT_EQ(centre.y1, 31);
}

}  // namespace
}  // namespace patchsim
