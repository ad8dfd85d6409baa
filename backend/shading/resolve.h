#pragma once
// The output merger's final step and the resolve: per sample, the nearest opaque t-fragment (or
// the background) with the sample's transparent t-fragments in front of it sorted back to front
// and blended over it; per pixel, a filter over samples (box, or a Gaussian reaching into the
// neighbouring pixels). AOVs: depth, motion vectors and coverage.
//
// Motion over transparency: a reconstruction filter (McGuire et al. 2012, the hybrid) blurs each
// pixel with one velocity, so a sample's motion is that of the surface whose colour weighs most
// in it: a transparent layer weighs its opacity times what the layers in front of it let
// through, the opaque hit (or the background, which has no motion) what they all let through;
// ties go to the nearer. A moving glass at opacity 0.5 thus gives its own motion over a still
// wall or the empty background, and one at 0.25 leaves the pixel the wall's. Depth stays the
// opaque hits', as a z-buffer's: transparent surfaces do not write it.

#include <string>
#include <vector>

#include "backend/images/image.h"
#include "backend/shading/t_fragment.h"
#include "core/samples.h"
#include "rasterizer/common/transparent_layers.h"

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
    // with any hit, and the mean screen motion (pixels, t=0 to t=1) of the samples' dominant
    // surfaces (above; 0 if the background dominates every sample).
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
