#include "rasterizer/common/watertight_triangle_rounded.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace patchsim {
namespace {

bool sameBits(float a, float b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

NumberFormat named(const char* name) {
    NumberFormat f;
    EXPECT_TRUE(parseNumberFormat(name, f)) << name;
    return f;
}

// A ray from a random point of a lens-sized disk toward a random point ahead, in any direction
// (so every shear axis and both windings occur).
Ray randomRay(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    Ray ray;
    ray.origin = Vec3(0.2f * u(rng), 0.2f * u(rng), 0.0f);
    ray.direction = Vec3(u(rng), u(rng), u(rng) - 1.5f);
    return ray;
}

// Emulated in fp32, the test is intersectTriangle operation for operation: the same answer and
// the same bits, on random rays and triangles, hits and misses.
TEST(WatertightTriangleRounded, InFp32ItIsTheFloatTestBitForBit) {
    std::mt19937 rng(35);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int hits = 0;
    for (int c = 0; c < 100000; ++c) {
        const Ray ray = randomRay(rng);
        const ShearedRay sheared = shearRay(ray);
        const Vec3 centre = ray.origin + (2.0f + u(rng)) * ray.direction;
        const float size = c % 2 ? 0.5f : 1e-3f;
        const Vec3 a = centre + size * Vec3(u(rng), u(rng), u(rng));
        const Vec3 b = centre + size * Vec3(u(rng), u(rng), u(rng));
        const Vec3 c3 = centre + size * Vec3(u(rng), u(rng), u(rng));
        TriangleHit want, got;
        const bool wanted = intersectTriangle(sheared, a, b, c3, 0.5f, 2.5f, want);
        const bool gotHit =
            intersectTriangleRounded(sheared, a, b, c3, 0.5f, 2.5f, NumberFormat::fp32(), got);
        ASSERT_EQ(gotHit, wanted) << "case " << c;
        if (!wanted) continue;
        ++hits;
        ASSERT_TRUE(sameBits(got.lambda, want.lambda)) << "case " << c;
        ASSERT_TRUE(sameBits(got.b0, want.b0) && sameBits(got.b1, want.b1) &&
                    sameBits(got.b2, want.b2))
            << "case " << c;
    }
    EXPECT_GT(hits, 10000);
}

// In every format, rays through the shared edges and the shared vertex of a fan hit at least
// one triangle (no crack). The points stay clear of the fan's outer rim, which no neighbour
// shares and which rounding may move.
TEST(WatertightTriangleRounded, RaysOnSharedEdgesNeverFallThroughInAnyFormat) {
    for (const char* name : {"fp16", "bf16", "fixed16.8", "fixed8.4", "fixed24.12"}) {
        const NumberFormat format = named(name);
        std::mt19937 rng(9);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        int rays = 0;
        for (int c = 0; c < 1000; ++c) {
            const Vec3 centre(0.3f * u(rng), 0.3f * u(rng), -3 + 0.5f * u(rng));
            std::vector<Vec3> ring;
            for (int k = 0; k < 6; ++k) {
                const float angle = float(k) * 1.0471976f + 0.2f * u(rng);
                ring.push_back(centre + Vec3(std::cos(angle), std::sin(angle), 0.3f * u(rng)));
            }
            for (int k = 0; k < 6; ++k)
                for (float s : {0.0f, 0.37f, 0.5f}) {
                    Ray ray;
                    ray.direction = centre + s * (ring[std::size_t(k)] - centre);
                    const ShearedRay sheared = shearRay(ray);
                    int claims = 0;
                    for (int j = 0; j < 6; ++j) {
                        TriangleHit hit;
                        claims += intersectTriangleRounded(sheared, centre, ring[std::size_t(j)],
                                                           ring[std::size_t((j + 1) % 6)], 0, 100,
                                                           format, hit);
                    }
                    ++rays;
                    ASSERT_GE(claims, 1) << name << " case " << c << " spoke " << k << " at " << s;
                }
        }
        EXPECT_EQ(rays, 18000);
    }
}

// Lossy by design: away from the edges the narrow test agrees with fp32, near them it may not,
// and its depth is within the format's precision of fp32's. The fewer the bits, the more
// samples change their answer.
TEST(WatertightTriangleRounded, DisagreesWithFp32OnlyNearEdgesAndLessWithMoreBits) {
    const Vec3 a(-1, -1, -4), b(1.2f, -0.8f, -4.5f), c(0.1f, 1.1f, -3.5f);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    std::vector<Ray> rays;
    for (int k = 0; k < 20000; ++k) {
        Ray ray;
        ray.origin = Vec3(0.05f * u(rng), 0.05f * u(rng), 0);
        ray.direction = Vec3(u(rng), u(rng), -4.0f) * 0.25f;
        rays.push_back(ray);
    }
    int previous = -1;
    // Each format's edge band: the barycentric weight within which rounding may move an edge
    // (about a few units in the last place over the triangle's size of two).
    const std::pair<const char*, float> formats[] = {
        {"fp32", 0.0f}, {"fp16", 0.01f}, {"bf16", 0.05f}, {"fixed16.4", 0.25f}};
    for (const auto& [name, edgeBand] : formats) {
        const NumberFormat format = named(name);
        int differ = 0;
        double deepestDepthError = 0;
        for (const Ray& ray : rays) {
            const ShearedRay sheared = shearRay(ray);
            TriangleHit exact, rounded;
            const bool inFp32 = intersectTriangle(sheared, a, b, c, 0, 100, exact);
            const bool inFormat =
                intersectTriangleRounded(sheared, a, b, c, 0, 100, format, rounded);
            if (inFp32 != inFormat) {
                ++differ;
                // Near an edge: the hit that one of them found has a small barycentric weight.
                const TriangleHit& found = inFp32 ? exact : rounded;
                EXPECT_LT(std::min({std::abs(found.b0), std::abs(found.b1), std::abs(found.b2)}),
                          edgeBand)
                    << name;
            } else if (inFp32) {
                deepestDepthError =
                    std::max(deepestDepthError, double(std::abs(rounded.lambda - exact.lambda)));
            }
        }
        EXPECT_GE(differ, previous) << name;
        if (std::string(name) == "fp32") {
            EXPECT_EQ(differ, 0);
        }
        if (std::string(name) == "fp16") {
            EXPECT_LT(deepestDepthError, 0.05) << name;
        }
        previous = differ;
    }
    EXPECT_GT(previous, 0) << "fixed16.4 moves some samples";
}

// Out of range: fp16 overflows beyond 65504, and the hit is refused rather than made up; the
// dispatcher runs the float test for fp32.
TEST(WatertightTriangleRounded, OverflowRefusesAndFp32Dispatches) {
    Ray ray;
    ray.direction = Vec3(0, 0, -1);
    const ShearedRay sheared = shearRay(ray);
    TriangleHit hit;
    const Vec3 a(-1e5f, -1e5f, -2), b(1e5f, -1e5f, -2), c(0, 1e5f, -2);
    EXPECT_TRUE(intersectTriangle(sheared, a, b, c, 0, 10, hit));
    EXPECT_FALSE(intersectTriangleRounded(sheared, a, b, c, 0, 10, NumberFormat::fp16(), hit));
    EXPECT_TRUE(intersectTriangleRounded(sheared, a, b, c, 0, 10, NumberFormat::bf16(), hit));
    EXPECT_TRUE(intersectTriangleIn(NumberFormat::fp32(), sheared, a, b, c, 0, 10, hit));
}

}  // namespace
}  // namespace patchsim
