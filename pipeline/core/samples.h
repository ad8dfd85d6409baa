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

#include "pipeline/core/effects.h"
#include "pipeline/core/math.h"

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
    int samplesPerPixel() const { return spp_; }
    const Effects& effects() const { return effects_; }

  private:
    std::uint64_t seed_;
    int spp_;
    int gridSide_;  // > 0 when spp is a perfect square
    Effects effects_;
    SamplePattern pattern_;
    float stillTime_;
};

// Shirley-Chiu concentric map of [0,1)^2 to the unit disk.
Vec2 concentricDisk(const Vec2& u);

// A 64-bit mix (SplitMix64 finaliser) used for all sample hashing.
std::uint64_t mix64(std::uint64_t x);

}  // namespace patchsim
