#pragma once
// The 5D sample set (x, y, u, v, t) shared by every visibility method.
//
// Representation
// --------------
// Samples are a pure function of (seed, pixel, sample index), so any method, tile order or thread
// count sees exactly the same set. Within a pixel the n samples are stratified: (x, y) on a
// jittered grid when n is a square (Latin hypercube otherwise), and t and the lens (u, v) each on
// their own shuffled stratification (Latin hypercube), so every dimension is evenly covered and
// the dimensions are decorrelated. Dimensions the scene does not call for are fixed: t = 0 when
// nothing varies over the shutter, (u, v) = lens centre without defocus. Lens (u, v) in [0,1)^2
// maps to the disk with Shirley's concentric mapping.

#include <cstdint>
#include <vector>

#include "core/effects.h"
#include "core/fixed_divisor.h"
#include "core/math.h"
#include "core/sample_kernel.h"

namespace patchsim {

struct Sample {
    Vec2 pixelOffset;  // in [0,1)^2 within the pixel
    Vec2 lens;         // in [0,1)^2; (0.5, 0.5) is the lens centre
    float time;        // in [0,1]
};

// `Stratified` jitters inside each stratum (the default). `Grid` puts samples on the stratum
// corners without jitter: pixel offsets k/n (so samples lie exactly on pixel and tile edges),
// times and lens coordinates k/(n-1) (so t is exactly 0 and 1 for some samples). For hard-case
// tests and studies of edge behaviour. `Interleaved` gives sample index s the same (x, y, u, v, t)
// offsets in every pixel, as an accumulation buffer renders s static passes, each at one time,
// lens point and sub-pixel shift: constant cost, and strobing where things move.
// (SamplePattern is declared with the film, in scene.h.)

class SampleGenerator {
  public:
    // `stillTime`: every sample's time when nothing varies over the shutter (the post-process
    // methods' sharp frame is taken at mid-shutter).
    SampleGenerator(std::uint64_t seed, int samplesPerPixel, const Effects& effects,
                    SamplePattern pattern = SamplePattern::Stratified, float stillTime = 0.0f);

    Sample sample(int x, int y, int index) const;
    // All `samplesPerPixel()` samples of pixel (x, y), equal to sample(x, y, 0..) bit for bit: the
    // pixel's hash streams are made once for all of them, and the samples several at a time by
    // the SIMD kernel of sample_kernel.h.
    void pixelSamples(int x, int y, Sample* out) const;
    int samplesPerPixel() const { return spp_; }
    const Effects& effects() const { return effects_; }
    // Index i's place in the key's random permutation of [0, samplesPerPixel()): the stratum
    // a sample takes in one dimension.
    std::uint32_t permute(std::uint32_t i, std::uint32_t key) const;
    // What the vector kernel that makes pixelSamples needs of this generator.
    const PixelSampleRecipe& kernelRecipe() const { return recipe_; }

  private:
    struct PixelStreams {
        std::uint64_t dimension[12];  // one hash stream per sample dimension
    };
    PixelStreams pixelStreams(int x, int y) const;
    Sample sampleOf(const PixelStreams& streams, int index) const;

    std::uint64_t seed_;
    int spp_;
    FixedDivisor count_;        // by spp
    FixedDivisor gridDivisor_;  // by the grid's side (by 1 when there is none)
    Effects effects_;
    SamplePattern pattern_;
    // The permutation mask, the grid's side (> 0 when spp is a perfect square), the time and lens
    // strata's divisor and the still time, which the scalar sampler reads too.
    PixelSampleRecipe recipe_;
};

// Shirley-Chiu concentric map of [0,1)^2 to the unit disk.
Vec2 concentricDisk(const Vec2& u);

// A frame's samples made once, pixel-major like the visibility buffer, each with its lens point
// mapped to the disk. Methods compared on the same samples read them from here, so what is timed
// is their visibility work, not the sampler (bench/embree_compare_bench.cpp).
class SampleTable {
  public:
    SampleTable(const SampleGenerator& generator, int width, int height, int threads);
    int samplesPerPixel() const { return spp_; }
    const Sample* pixel(int x, int y) const { return &samples_[index(x, y)]; }
    const Vec2* disk(int x, int y) const { return &disk_[index(x, y)]; }

  private:
    std::size_t index(int x, int y) const {
        return (std::size_t(y) * std::size_t(width_) + std::size_t(x)) * std::size_t(spp_);
    }
    int width_, spp_;
    std::vector<Sample> samples_;
    std::vector<Vec2> disk_;
};

// Where the rasterizer reads a pixel's samples: the table when there is one, else the generator.
struct SampleSource {
    const SampleGenerator* generator = nullptr;
    const SampleTable* table = nullptr;
    // The pixel's samples and their lens points on the disk: the table's own, or made by the
    // generator into `samples` and `disk` (room for samplesPerPixel each).
    void pixel(int x, int y, Sample* samples, Vec2* disk, const Sample*& pixelSamples,
               const Vec2*& pixelDisk) const;
    // Asks the cache for the table's samples of pixels [x0, x1) of row y, which are read next (a
    // tile's rows are short runs the hardware prefetcher finds too late).
    void prefetch(int x0, int x1, int y) const;
};

// A 64-bit mix (SplitMix64 finaliser) used for all sample hashing.
std::uint64_t mix64(std::uint64_t x);

}  // namespace patchsim
