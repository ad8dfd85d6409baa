#include "rasterizer/patent/moving_box_ray_rounded.h"

#include <gtest/gtest.h>

#include <random>

namespace patchsim {
namespace {

using Exact = __float128;

Exact absExact(Exact x) {
    return x < 0 ? -x : x;
}

// moving_box_ray.h's test with its own coefficients, in exact arithmetic.
bool exactTest(const SlabRay& r, const LBBox& box) {
    Exact entry = r.lambdaMin, exit = r.lambdaMax;
    for (int k = 0; k < 3; ++k) {
        if (r.parallel[k]) continue;  // the tests here have no parallel axis
        auto distance = [&](float x0, float x1) {
            return Exact(x0) * Exact(r.a[k]) + Exact(x1) * Exact(r.b[k]) + Exact(r.c[k]);
        };
        const Exact e0 = distance(box.bounds0.lower[k], box.bounds1.lower[k]);
        const Exact e1 = distance(box.bounds0.upper[k], box.bounds1.upper[k]);
        entry = std::max(entry, std::min(e0, e1));
        exit = std::min(exit, std::max(e0, e1));
    }
    return entry <= exit + Exact(kRayBoxRelativeSlack) * (absExact(entry) + absExact(exit)) +
                        Exact(kRayBoxAbsoluteSlack);
}

// Rays from a lens through a small moving box, many grazing it: a box edge near the ray.
struct Case {
    SlabRay ray;
    LBBox box;
    float side;  // the box lies on this side of the ray along x
};

Case randomCase(std::mt19937& random) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), time(0.0f, 1.0f);
    Ray ray;
    ray.origin = Vec3(0.3f * unit(random), 0.3f * unit(random), 0.0f);
    const Vec3 target(unit(random), unit(random), -6.0f + unit(random));
    ray.direction = target - ray.origin;
    ray.time = time(random);
    ray.lambdaMin = 0;
    ray.lambdaMax = 2;
    // A box whose blend at the ray's time has a face within about 0.01 of the ray's point near
    // the target, on a random side.
    const Vec3 point = ray.origin + ray.direction;
    const Vec3 half(0.05f + 0.05f * std::abs(unit(random)), 0.05f, 0.05f);
    const Vec3 motion(0.4f * unit(random), 0.4f * unit(random), 0.2f * unit(random));
    const float side = unit(random) < 0 ? -1.0f : 1.0f;
    const Vec3 centre =
        point + Vec3(side * (half.x + 0.01f * unit(random)), 0, 0) - ray.time * motion;
    LBBox box;
    box.bounds0 = {centre - half, centre + half};
    box.bounds1 = {centre + motion - half, centre + motion + half};
    return {makeSlabRay(ray), box, side};
}

// Over grazing cases, the bounded test accepts whatever the exact test accepts, in every
// format; the naive datapath rejects some of them; and the bound does not accept everything.
TEST(MovingBoxRayRounded, BoundedAcceptsWhatTheExactTestAcceptsNaiveDoesNot) {
    const NumberFormat formats[] = {NumberFormat::fp16(), NumberFormat::bf16(),
                                    NumberFormat::fixed(16, 8), NumberFormat::fixed(8, 4)};
    for (const NumberFormat& format : formats) {
        const RoundedArithmetic arithmetic(format);
        std::mt19937 random(9);
        int exactHits = 0, exactMisses = 0, boundedLosses = 0, naiveLosses = 0, boundedMisses = 0;
        int farMisses = 0;
        for (int i = 0; i < 40000; ++i) {
            const Case c = randomCase(random);
            const bool exact = exactTest(c.ray, c.box);
            const bool bounded =
                hitsMovingBoxRounded(c.ray, c.box, arithmetic, PlaneErrorHandling::Bounded);
            const bool naive =
                hitsMovingBoxRounded(c.ray, c.box, arithmetic, PlaneErrorHandling::Naive);
            exactHits += exact;
            exactMisses += !exact;
            boundedLosses += exact && !bounded;
            naiveLosses += exact && !naive;
            boundedMisses += !bounded;
            // Half a unit further off the ray, the box is a clear miss even for the bound.
            LBBox far = c.box;
            for (Box3* end : {&far.bounds0, &far.bounds1}) {
                end->lower.x += 0.5f * c.side;
                end->upper.x += 0.5f * c.side;
            }
            farMisses += !hitsMovingBoxRounded(c.ray, far, arithmetic, PlaneErrorHandling::Bounded);
        }
        EXPECT_GT(exactHits, 5000) << formatName(format);
        EXPECT_GT(exactMisses, 5000) << formatName(format);
        EXPECT_EQ(boundedLosses, 0) << formatName(format);
        EXPECT_GT(naiveLosses, 0) << formatName(format);
        EXPECT_GT(boundedMisses, 0) << formatName(format);
        // Where 1/d leaves a fixed-point range the axis gives up and a far box passes: 8.4's
        // range is small enough for that to be common, the others' for a rare ray.
        if (format != NumberFormat::fixed(8, 4)) {
            EXPECT_GE(farMisses, 39900) << formatName(format) << ": it accepts clear misses";
        }
    }
}

// The fp32 datapath with the bound agrees with fp32's own test on these cases wherever the
// exact test does not sit within float's rounding of the decision.
TEST(MovingBoxRayRounded, Fp32BoundedIsTheFp32TestUpToItsRounding) {
    const RoundedArithmetic arithmetic(NumberFormat::fp32());
    std::mt19937 random(4);
    int differ = 0;
    for (int i = 0; i < 20000; ++i) {
        const Case c = randomCase(random);
        differ += hitsMovingBoxRounded(c.ray, c.box, arithmetic, PlaneErrorHandling::Bounded) !=
                  hitsMovingBox(c.ray, c.box);
    }
    EXPECT_LT(differ, 20);  // the bound widens by a few float ulps at most
}

}  // namespace
}  // namespace patchsim
