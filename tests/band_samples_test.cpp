#include "rasterizer/baselines/band_samples.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <bit>
#include <limits>
#include <random>
#include <utility>

#include "core/camera.h"
#include "core/effects.h"
#include "core/samples.h"
#include "rasterizer/common/sample_rays.h"
#include "rasterizer/common/watertight_triangle.h"

namespace patchsim {
namespace {

// A wide camera with a lens and motion: rays that shear along z and rays (at the frame's sides,
// beyond 45 degrees) that do not.
struct WideFrame {
    static constexpr int kWidth = 40, kHeight = 12, kSpp = 8;
    Camera camera{[] {
                      CameraDesc desc;
                      desc.fovYDegrees = 100.0f;
                      return desc;
                  }(),
                  {},
                  kWidth,
                  kHeight};
    Effects effects{true, false, true, false};
    SampleGenerator generator{7, kSpp, effects};
    RayCaster caster{camera, {0.2f, 3.0f}, generator, true, true};
};

TEST(BandSamples, EachSampleKeepsItsRayBitForBit) {
    const WideFrame f;
    const BandSamples band(f.caster, WideFrame::kWidth, WideFrame::kSpp, 4, 7, 0);
    int alongZ = 0, other = 0;
    for (int y = 4; y < 7; ++y)
        for (int x = 0; x < WideFrame::kWidth; ++x)
            for (int s = 0; s < WideFrame::kSpp; ++s) {
                const std::size_t i = band.index(y - 4, x, s);
                const Ray ray = sampleRay(f.caster, x, y, s);
                const ShearedRay want = shearRay(ray), got = band.shearedRay(i);
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got.origin.x),
                          std::bit_cast<std::uint32_t>(want.origin.x));
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got.origin.y),
                          std::bit_cast<std::uint32_t>(want.origin.y));
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got.sx),
                          std::bit_cast<std::uint32_t>(want.sx));
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got.sy),
                          std::bit_cast<std::uint32_t>(want.sy));
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got.sz),
                          std::bit_cast<std::uint32_t>(want.sz));
                ASSERT_EQ(got.kx, want.kx);
                ASSERT_EQ(got.ky, want.ky);
                ASSERT_EQ(got.kz, want.kz);
                ASSERT_EQ(band.time(i), f.generator.sample(x, y, s).time);
                ASSERT_EQ(band.lambdaMin(i), ray.lambdaMin);
                const bool z = want.kx == 1 && want.ky == 0 && want.kz == 2;
                ASSERT_EQ(band.alongZ(i), z);
                (z ? alongZ : other) += 1;
            }
    EXPECT_GT(alongZ, 0);
    EXPECT_GT(other, 0) << "the wide frame has rays that take the scalar test";
}

// The vector test against the scalar one on the same samples and triangles, on every SIMD target
// this host runs: the same hits, and the same bits of every ray parameter and barycentric.
// Triangles include degenerate ones (two equal corners), whose edge function is exactly zero and
// takes the double-precision path (though it decides no hit there), and ones with an infinite or
// NaN corner; lists are runs of samples (loads) and strided ones (gathers).
TEST(BandSamples, TheVectorTestEqualsTheScalarTestBitForBitOnEveryTarget) {
    const WideFrame f;
    const BandSamples band(f.caster, WideFrame::kWidth, WideFrame::kSpp, 2, 10, 0);
    const std::size_t n = std::size_t(8 * WideFrame::kWidth * WideFrame::kSpp);
    CandidateList list(n);
    const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
    ASSERT_FALSE(targets.empty());
    for (std::int64_t target : targets) {
        hwy::SetSupportedTargetsForTest(target);
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> xy(-3.0f, 3.0f), z(-6.0f, -0.5f), move(-0.5f, 0.5f),
            end(0.5f, 20.0f);
        int hits = 0, tests = 0;
        for (int trial = 0; trial < 300; ++trial) {
            MovingTriangle tri;
            for (int k = 0; k < 3; ++k) {
                tri.open[k] = {xy(rng), xy(rng), z(rng)};
                tri.close[k] = tri.open[k] + Vec3(move(rng), move(rng), move(rng));
            }
            if (trial % 5 == 0) {  // degenerate: corners 1 and 2 equal
                tri.open[2] = tri.open[1];
                tri.close[2] = tri.close[1];
            }
            if (trial % 7 == 3) tri.close[0].x = std::numeric_limits<float>::infinity();
            if (trial % 11 == 4) tri.open[1].y = std::numeric_limits<float>::quiet_NaN();
            list.clear();
            std::vector<float> ends;
            for (std::size_t i = std::size_t(trial % 2); i < n;
                 i += 1 + std::size_t(trial % 3 == 0))
                if (band.alongZ(i)) {
                    ends.push_back(end(rng));
                    list.add(std::int32_t(i), ends.back());
                }
            const int found = list.test(band, tri);
            int next = 0;
            for (int c = 0; c < list.size(); ++c) {
                const auto i = std::size_t(list.sample(c));
                const float t = band.time(i);
                TriangleHit want;
                const bool hit = intersectTriangle(
                    band.shearedRay(i), lerp(tri.open[0], tri.close[0], t),
                    lerp(tri.open[1], tri.close[1], t), lerp(tri.open[2], tri.close[2], t),
                    band.lambdaMin(i), ends[std::size_t(c)], want);
                ++tests;
                const bool got = next < found && list.hits()[next].candidate == c;
                ASSERT_EQ(got, hit)
                    << hwy::TargetName(target) << " trial " << trial << " candidate " << c;
                if (!hit) continue;
                const CandidateHit& h = list.hits()[next++];
                ++hits;
                ASSERT_EQ(std::bit_cast<std::uint32_t>(h.lambda),
                          std::bit_cast<std::uint32_t>(want.lambda))
                    << hwy::TargetName(target);
                ASSERT_EQ(std::bit_cast<std::uint32_t>(h.b1),
                          std::bit_cast<std::uint32_t>(want.b1));
                ASSERT_EQ(std::bit_cast<std::uint32_t>(h.b2),
                          std::bit_cast<std::uint32_t>(want.b2));
            }
            ASSERT_EQ(next, found);
        }
        EXPECT_GT(hits, 1000) << "of " << tests;
        EXPECT_GT(tests - hits, 1000);
    }
    hwy::SetSupportedTargetsForTest(0);
}

// A corner exactly on a sample's ray makes two edge functions exactly zero, so the
// double-precision path decides the hit and its barycentrics. A pinhole's rays leave the origin
// at t = 0, and the corner (-4 sy, -4 sx, -4) sheds to ax = ay = 0 exactly (a power-of-two
// scale of the shear): u is the only non-zero edge function, and the hit has b1 = b2 = 0. Lists
// of one candidate also test a vector's masked tail.
TEST(BandSamples, ACornerOnTheRayIsDecidedByTheDoublePrecisionPath) {
    const Camera camera{CameraDesc{}, {}, 16, 8};
    const SampleGenerator generator{3, 4, Effects{}};
    const RayCaster caster{camera, {}, generator, false, true};
    const BandSamples band(caster, 16, 4, 0, 8, 0);
    const std::size_t n = 16 * 4 * 8;
    CandidateList list(n);
    const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
    for (std::int64_t target : targets) {
        hwy::SetSupportedTargetsForTest(target);
        int hits = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const ShearedRay ray = band.shearedRay(i);
            ASSERT_TRUE(band.alongZ(i));
            ASSERT_EQ(ray.origin, Vec3(0.0f));
            ASSERT_EQ(band.time(i), 0.0f);
            const Vec3 corner(-4.0f * ray.sy, -4.0f * ray.sx, -4.0f);
            const MovingTriangle tri{
                {corner, corner + Vec3(1, 0.25f, 0), corner + Vec3(0.5f, 1, 0)},
                {corner, corner + Vec3(1, 0.25f, 0), corner + Vec3(0.5f, 1, 0)}};
            for (const bool flipped : {false, true}) {  // both windings: u > 0 and u < 0
                MovingTriangle t = tri;
                if (flipped) std::swap(t.open[1], t.open[2]), std::swap(t.close[1], t.close[2]);
                TriangleHit want;
                const bool hit = intersectTriangle(ray, t.open[0], t.open[1], t.open[2],
                                                   band.lambdaMin(i), 1e30f, want);
                ASSERT_TRUE(hit) << "sample " << i;
                EXPECT_EQ(want.b1, 0.0f);
                EXPECT_EQ(want.b2, 0.0f);
                list.clear();
                list.add(std::int32_t(i), 1e30f);
                ASSERT_EQ(list.test(band, t), 1) << hwy::TargetName(target) << " sample " << i;
                const CandidateHit& got = list.hits()[0];
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got.lambda),
                          std::bit_cast<std::uint32_t>(want.lambda));
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got.b1),
                          std::bit_cast<std::uint32_t>(want.b1));
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got.b2),
                          std::bit_cast<std::uint32_t>(want.b2));
                ++hits;
            }
        }
        EXPECT_EQ(hits, int(2 * n));
    }
    hwy::SetSupportedTargetsForTest(0);
}

}  // namespace
}  // namespace patchsim
