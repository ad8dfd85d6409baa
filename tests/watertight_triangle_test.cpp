#include "rasterizer/common/watertight_triangle.h"

#include <gtest/gtest.h>

#include <random>

namespace patchsim {
namespace {

Ray rayThrough(Vec2 xy) {
    Ray r;
    r.origin = Vec3(xy, 0);
    r.direction = Vec3(0, 0, -1);
    return r;
}

TEST(WatertightTriangle, HitsInsideMissesOutsideWithBarycentrics) {
    const Vec3 a(0, 0, -2), b(1, 0, -2), c(0, 1, -2);
    TriangleHit hit;
    ASSERT_TRUE(intersectTriangle(shearRay(rayThrough({0.25f, 0.25f})), a, b, c, 0, 10, hit));
    EXPECT_NEAR(hit.lambda, 2.0f, 1e-6f);
    EXPECT_NEAR(hit.b1, 0.25f, 1e-6f);
    EXPECT_NEAR(hit.b2, 0.25f, 1e-6f);
    EXPECT_NEAR(hit.b0 + hit.b1 + hit.b2, 1.0f, 1e-6f);
    EXPECT_FALSE(intersectTriangle(shearRay(rayThrough({0.75f, 0.75f})), a, b, c, 0, 10, hit));
    // Both faces count; the range is inclusive at both ends.
    EXPECT_TRUE(intersectTriangle(shearRay(rayThrough({0.25f, 0.25f})), a, c, b, 0, 10, hit));
    EXPECT_TRUE(intersectTriangle(shearRay(rayThrough({0.25f, 0.25f})), a, b, c, 2, 2, hit));
    EXPECT_FALSE(intersectTriangle(shearRay(rayThrough({0.25f, 0.25f})), a, b, c, 0, 1.9f, hit));
}

// Watertight: rays through the shared edge and vertices of a fan of triangles hit at least one
// triangle, never none (no crack), whatever their float positions.
TEST(WatertightTriangle, RaysOnSharedEdgesNeverFallThrough) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int c = 0; c < 2000; ++c) {
        const Vec3 centre(0.3f * u(rng), 0.3f * u(rng), -3 + 0.5f * u(rng));
        std::vector<Vec3> ring;
        for (int k = 0; k < 6; ++k) {
            const float angle = float(k) * 1.0471976f + 0.2f * u(rng);
            ring.push_back(centre + Vec3(std::cos(angle), std::sin(angle), 0.3f * u(rng)));
        }
        // Rays through the centre vertex and through points on the spokes.
        for (int k = 0; k < 6; ++k) {
            for (float s : {0.0f, 0.37f, 0.5f}) {
                const Vec3 target = centre + s * (ring[std::size_t(k)] - centre);
                Ray ray;
                ray.direction = target;  // from the origin through the point
                const ShearedRay sheared = shearRay(ray);
                int claims = 0;
                for (int j = 0; j < 6; ++j) {
                    TriangleHit hit;
                    claims += intersectTriangle(sheared, centre, ring[std::size_t(j)],
                                                ring[std::size_t((j + 1) % 6)], 0, 100, hit);
                }
                ASSERT_GE(claims, 1) << "case " << c << " spoke " << k << " at " << s;
            }
        }
    }
}

}  // namespace
}  // namespace patchsim
