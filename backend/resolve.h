#pragma once
// The output merger's final step and the resolve: per sample, the nearest opaque t-fragment (or
// the background) with the sample's transparent t-fragments in front of it sorted back to front
// and blended over it; per pixel, a filter over samples (box, or a Gaussian reaching into the
// neighbouring pixels). AOVs: depth, motion vectors and coverage.

#include <string>
#include <vector>

#include "backend/image.h"
#include "backend/t_fragment.h"
#include "pipeline/core/samples.h"
#include "rasterizer/transparent_layers.h"

namespace patchsim {

enum class ResolveFilter : std::uint8_t { Box, Gaussian };
const char* resolveFilterName(ResolveFilter f);

struct ResolveOptions {
    ResolveFilter filter = ResolveFilter::Box;
    ShadingRate shadingRate = ShadingRate::PerFragment;
    float gaussianSigma = 0.5f;   // pixels
    float gaussianRadius = 1.5f;  // pixels; samples farther from the pixel centre are ignored
};

struct ResolvedFrame {
    Image color;
    // Per pixel: mean depth of the samples with an opaque hit (0 if none), fraction of samples
    // with any hit, and the mean screen motion (pixels, t=0 to t=1) of the opaque hits.
    FloatPlane depth, coverage, motionX, motionY;
    // Per patch: the pixel-shader invocations it caused in the resolve (its visible t-fragments,
    // or its distinct pixel-triangle pairs at the per-pixel-primitive rate), for the timing model.
    std::vector<double> shadedPerPatch;
};

// Per-sample colours (3 floats per sample, sample-major like VisibilityBuffer) after blending.
// `progress`, when given, advances by one per row shaded.
std::vector<float> shadeSamples(const ShadingContext& context, const VisibilityBuffer& opaque,
                                const TransparentLayers* transparent, ShadingRate rate, int threads,
                                class Progress* progress = nullptr);

// Filters per-sample colours to pixels, a row per work item on `threads` workers; `samples` gives
// each sample's position in its pixel.
Image filterSamples(const std::vector<float>& sampleColors, const VisibilityBuffer& layout,
                    const SampleGenerator& samples, const ResolveOptions& options, int threads = 1);

// `samples` gives each sample's position in its pixel, for the Gaussian filter.
ResolvedFrame resolveFrame(const ShadingContext& context, const VisibilityBuffer& opaque,
                           const TransparentLayers* transparent, const SampleGenerator& samples,
                           const ResolveOptions& options, int threads,
                           class Progress* progress = nullptr);

// EXR with channels R, G, B, Z, coverage, motion.x, motion.y (linear float).
void writeExrWithAovs(const ResolvedFrame& frame, const std::string& path);

}  // namespace patchsim
