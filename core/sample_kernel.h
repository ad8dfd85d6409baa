#pragma once
// A pixel's samples made several at a time (SIMD over the sample index), compiled once per
// instruction set and chosen at run time. Each lane performs SampleGenerator::sampleOf's integer
// and float operations in the same order, so the samples equal those sample(x, y, i) makes one
// at a time, bit for bit, on every target (tests/sample_kernel_test.cpp).
//
// Representation
// --------------
// The kernel sees a generator as the few numbers it reads (PixelSampleRecipe) and a pixel as its
// twelve hash streams. Hashes are 64-bit multiply-xorshift mixes (SplitMix64), done in 64-bit
// lanes; permutations are 32-bit (Kensler's), done in 32-bit lanes of the same count. The one
// remainder that wants a 64-bit product in scalar code, (i + key) mod n with i < n, is taken
// without it: key mod n is made once per pixel and dimension, and i + key either wraps past 2^32
// (then the wrapped sum is already below n) or is (i + key mod n) less n at most once.

#include <cstdint>

namespace patchsim {

struct Sample;  // samples.h

// What a SampleGenerator fixes for all its pixels, as the kernel needs it (made once, with the
// generator).
struct PixelSampleRecipe {
    std::uint32_t count = 1;            // samples per pixel, n (at least 1)
    std::uint32_t permutationMask = 0;  // the smallest all-ones mask covering [0, n)
    std::uint32_t gridSide = 0;         // sqrt(n) when n is a square, else 0
    bool jitter = true;                 // false for SamplePattern::Grid
    bool timeSamples = false;           // else every time is stillTime
    bool lensSamples = false;           // else every lens point is the centre
    float spread = 1.0f;                // the divisor of time and lens strata
    float stillTime = 0.0f;
};

// Samples 0 .. recipe.count - 1 of the pixel whose hash streams are `streams` (12 of them).
void makePixelSamples(const PixelSampleRecipe& recipe, const std::uint64_t* streams, Sample* out);

// Where each of 0 .. recipe.count - 1 goes in the key's permutation of [0, count), as the kernel
// computes it for a stratum: for tests at keys the hash streams seldom give (sums that wrap).
void permuteIndices(const PixelSampleRecipe& recipe, std::uint32_t key, std::uint32_t* out);

// The instruction set the kernel runs on (for tests that switch targets).
const char* sampleKernelTarget();

}  // namespace patchsim
