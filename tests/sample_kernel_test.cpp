#include "core/sample_kernel.h"

#include <gtest/gtest.h>
#include <hwy/highway.h>
#include <hwy/targets.h>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "core/samples.h"

namespace patchsim {
namespace {

std::uint32_t bits(float f) {
    return std::bit_cast<std::uint32_t>(f);
}

// The first sample of `pixel` at which the vector kernel (pixelSamples) and the scalar sampler
// (sample) differ in any bit, or -1.
int firstMismatch(const SampleGenerator& g, int x, int y, std::vector<Sample>& made) {
    made.assign(std::size_t(g.samplesPerPixel()), Sample{});
    g.pixelSamples(x, y, made.data());
    for (int s = 0; s < g.samplesPerPixel(); ++s) {
        const Sample one = g.sample(x, y, s);
        const Sample& v = made[std::size_t(s)];
        if (bits(one.pixelOffset.x) != bits(v.pixelOffset.x) ||
            bits(one.pixelOffset.y) != bits(v.pixelOffset.y) || bits(one.time) != bits(v.time) ||
            bits(one.lens.x) != bits(v.lens.x) || bits(one.lens.y) != bits(v.lens.y))
            return s;
    }
    return -1;
}

// Sample counts with every remainder of a lane count, every square up to 64 x 64 (the grid
// cells' quotient by the side), and the largest counts a scene may ask for.
std::vector<int> countsToCheck() {
    std::vector<int> counts;
    for (int n = 1; n <= 70; ++n) counts.push_back(n);
    for (int side = 9; side <= 64; ++side) counts.push_back(side * side);
    for (int n : {127, 129, 255, 257, 1000, 1023, 1025, 4095}) counts.push_back(n);
    return counts;
}

TEST(SampleKernel, EveryTargetMakesTheScalarSamplesBitForBit) {
    const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
    ASSERT_FALSE(targets.empty());
    const Effects effects[] = {Effects{}, Effects{true, false, true, false},
                               Effects{false, true, false, false},
                               Effects{false, false, true, false}};
    const SamplePattern patterns[] = {SamplePattern::Stratified, SamplePattern::Grid,
                                      SamplePattern::Interleaved};
    const std::vector<int> counts = countsToCheck();
    std::vector<Sample> made;
    std::int64_t compared = 0;
    for (std::int64_t target : targets) {
        hwy::SetSupportedTargetsForTest(target);
        EXPECT_STREQ(sampleKernelTarget(), hwy::TargetName(target));
        for (int n : counts)
            for (const Effects& e : effects)
                for (SamplePattern pattern : patterns) {
                    const SampleGenerator g(std::uint64_t(n) * 7919u + 3u, n, e, pattern, 0.5f);
                    // Pixels with large coordinates too: their keys make the sums wrap.
                    const int pixels = n > 256 ? 2 : 6;
                    for (int p = 0; p < pixels; ++p) {
                        const int x = p * 977, y = p * 131 + n;
                        ASSERT_EQ(firstMismatch(g, x, y, made), -1)
                            << hwy::TargetName(target) << ", " << n << " spp, pattern "
                            << int(pattern) << ", pixel (" << x << ", " << y << ")";
                        compared += n;
                    }
                }
    }
    hwy::SetSupportedTargetsForTest(0);
    std::printf("targets: %zu, samples compared: %lld\n", targets.size(),
                static_cast<long long>(compared));
}

// The kernel's remainder without a 64-bit product, (i + key) mod n, where i + key wraps past 2^32
// and just short of it (random hash keys almost never do), and at small keys, on every target.
TEST(SampleKernel, PermutationsAgreeWhereTheOffsetWraps) {
    const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
    std::vector<std::uint32_t> made;
    int compared = 0;
    for (std::int64_t target : targets) {
        hwy::SetSupportedTargetsForTest(target);
        for (int n : {1, 2, 3, 5, 7, 8, 16, 17, 100, 257}) {
            const SampleGenerator g(5, n, Effects{});
            const PixelSampleRecipe& recipe = g.kernelRecipe();
            made.assign(std::size_t(n), 0);
            const auto count = std::uint32_t(n);
            for (std::uint32_t below = 0; below <= count + 1; ++below)
                for (std::uint32_t key :
                     {std::uint32_t(0u - 1u - below), below, std::uint32_t(0x80000000u - below)}) {
                    permuteIndices(recipe, key, made.data());
                    for (std::uint32_t i = 0; i < count; ++i) {
                        ASSERT_EQ(made[i], g.permute(i, key))
                            << hwy::TargetName(target) << ", n " << n << ", key " << key << ", i "
                            << i;
                        ++compared;
                    }
                }
        }
    }
    hwy::SetSupportedTargetsForTest(0);
    std::printf("indices compared: %d\n", compared);
}

}  // namespace
}  // namespace patchsim
