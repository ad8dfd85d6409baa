#include "rasterizer/patent/moving_box_ray.h"

#include <gtest/gtest.h>

#include <random>

namespace patchsim {
namespace {

// The exact answer in double precision: the box blended to the ray's time, slab by slab.
bool exactHit(const Ray& r, const LBBox& b) {
    double lo = r.lambdaMin, hi = r.lambdaMax;
    const double t = r.time;
    for (int k = 0; k < 3; ++k) {
        const double a = (1 - t) * b.bounds0.lower[k] + t * b.bounds1.lower[k];
        const double c = (1 - t) * b.bounds0.upper[k] + t * b.bounds1.upper[k];
        if (r.direction[k] == 0) {
            if (r.origin[k] < a || r.origin[k] > c) return false;
            continue;
        }
        const double e0 = (a - r.origin[k]) / r.direction[k],
                     e1 = (c - r.origin[k]) / r.direction[k];
        lo = std::max(lo, std::min(e0, e1));
        hi = std::min(hi, std::max(e0, e1));
    }
    return lo <= hi;
}

// Never misses a box the exact test hits (conservative); and agrees wherever the exact answer is
// not within rounding of the edge.
TEST(MovingBoxRay, ConservativeAgainstTheExactSlabTest) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), t01(0.0f, 1.0f);
    int hits = 0, misses = 0;
    for (int c = 0; c < 20000; ++c) {
        LBBox box;
        const Vec3 p0(u(rng), u(rng), -3 + u(rng)), p1 = p0 + Vec3(u(rng), u(rng), u(rng));
        box.bounds0 = {p0 - Vec3(0.3f), p0 + Vec3(0.3f)};
        box.bounds1 = {p1 - Vec3(0.2f), p1 + Vec3(0.4f)};
        Ray ray;
        ray.origin = Vec3(0.1f * u(rng), 0.1f * u(rng), 0);
        ray.direction = Vec3(0.5f * u(rng), 0.5f * u(rng), -1);
        ray.time = t01(rng);
        ray.lambdaMin = 0.01f;
        ray.lambdaMax = 100;
        const bool exact = exactHit(ray, box);
        const bool fast = rayMeetsMovingBox(ray, box);
        if (exact) {
            ASSERT_TRUE(fast) << "false reject in case " << c;
        }
        exact ? ++hits : ++misses;
        if (!exact && fast) {
            // Only a near miss may be accepted: widen the box a little and it hits.
            LBBox wide = box;
            for (Box3* b : {&wide.bounds0, &wide.bounds1}) {
                b->lower -= Vec3(1e-4f);
                b->upper += Vec3(1e-4f);
            }
            EXPECT_TRUE(exactHit(ray, wide)) << "accepted a clear miss in case " << c;
        }
    }
    EXPECT_GT(hits, 1000);
    EXPECT_GT(misses, 1000);
}

TEST(MovingBoxRay, FollowsTheBoxThroughTime) {
    LBBox box;
    box.bounds0 = {Vec3(-3, -0.5f, -6), Vec3(-2, 0.5f, -5)};  // left of the axis at t=0
    box.bounds1 = {Vec3(2, -0.5f, -6), Vec3(3, 0.5f, -5)};    // right of it at t=1
    Ray ray;
    ray.origin = Vec3(0);
    ray.direction = Vec3(0, 0, -1);
    ray.lambdaMax = 100;
    for (float t : {0.0f, 0.2f, 0.8f, 1.0f}) {
        ray.time = t;
        EXPECT_FALSE(rayMeetsMovingBox(ray, box)) << t;
    }
    ray.time = 0.5f;  // centred on the axis at half time
    EXPECT_TRUE(rayMeetsMovingBox(ray, box));
    ray.lambdaMax = 4.9f;  // ends before the box
    EXPECT_FALSE(rayMeetsMovingBox(ray, box));
}

TEST(MovingBoxRay, EmptyBoxesAreNeverHit) {
    Ray ray;
    ray.direction = Vec3(0, 0, -1);
    EXPECT_FALSE(rayMeetsMovingBox(ray, LBBox{}));
}

}  // namespace
}  // namespace patchsim
