#pragma once
// The `tfragment` method (Widmer et al. 2016): t-fragments generated at t = 1
// (tfragment_generation), an LBVH over them (tfragment_bvh), lens rays that collect every
// t-fragment they may meet during the frame, then motion sampling: per time sample, the nearest
// opaque t-fragment (circumsphere, then the pixel-sized cube) and the transparent ones in front
// of it, sorted and blended back to front. Shading is late, at the motion sample's time.
//
// Samples: each of the frame's 5D samples is one lens ray (its pixel position and lens point);
// its motion samples are at times frac(t + j / M), j < M, from the sample's own time t, and its
// colour is their mean. `timeSampled` replaces the decoupled tracing with one traversal per
// motion sample (the paper's comparison, opaque surfaces only). The method renders whole frames:
// it does not split one across MPI ranks (the render refuses, naming --method).

#include <vector>

#include "backend/tfragment/tfragment_bvh.h"
#include "backend/tfragment/tfragment_generation.h"
#include "core/counters.h"
#include "core/samples.h"
#include "rasterizer/common/visibility_buffer.h"

namespace patchsim {

// Per-sample colours (3 floats per sample, VisibilityBuffer order). `visibility` gets each
// sample's first motion sample's opaque hit (for the AOVs and the shading charge).
std::vector<float> renderTFragments(const ShadingContext& context, const SampleGenerator& samples,
                                    const LensModel& lens, const TFragmentOptions& options,
                                    bool timeSampled, int threads, VisibilityBuffer& visibility,
                                    TFragmentWork& work);

// TF/Visibility samples over TF/Sphere tests (docs/COUNTERS.md).
const RatioCounter& tfragmentSampleTestEfficiency();

}  // namespace patchsim
