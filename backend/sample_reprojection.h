#pragma once
// Motion blur by sample reprojection (Micah T. Taylor, "Fast motion blur through sample
// reprojection"): the `reprojection` method.
//
// Two sharp frames, at shutter open and close (frames n-1 and n, each through a pinhole with its
// own camera): every sample's world position is reprojected into cameras interpolated across the
// shutter, frame n-1's from its camera towards frame n's and frame n's back, and every
// reprojection's colour accumulated at the pixel it lands in; each pixel is the mean of what
// landed there (the paper's count map). A sample with no hit is the background seen along its
// direction and is reprojected as a direction. No depth test (as in the paper), so occluded
// samples bleed through; a pixel nothing lands in is a disocclusion hole, counted, and filled
// with the blend of the two frames. Only the camera's motion blurs: an object's own motion
// between the frames is not interpolated (the paper leaves object motion to future work).
//
// Transparency (beyond the paper, whose samples are opaque): each sharp frame keeps its
// transparent layers in front of every sample's opaque hit. A sample is split into its parts,
// each layer and the opaque hit (or the background), weighted as the back-to-front blend weighs
// them (a layer by its opacity times what the layers in front let through; the opaque hit by
// what all of them let through; the weights sum to one). Each part is reprojected from its own
// position, and a pixel is the weighted mean of the parts that land in it: where the camera does
// not move, a sample's parts land together and give its blended colour; where it does, each
// layer moves with its own depth. Layers are shaded once per fragment (no per-pixel reuse).

#include <cstdint>
#include <vector>

#include "backend/image.h"
#include "backend/t_fragment.h"
#include "pipeline/core/samples.h"
#include "rasterizer/transparent_layers.h"
#include "rasterizer/visibility_buffer.h"

namespace patchsim {

struct ReprojectionOptions {
    int cameraSteps = 16;  // interpolated cameras per reprojection cycle (both ends included)
};

struct ReprojectionWork {
    std::int64_t samples = 0;        // samples of the two frames
    std::int64_t layers = 0;         // transparent layers in front of their opaque hits
    std::int64_t reprojections = 0;  // part-camera reprojections written
    std::int64_t offScreen = 0;      // reprojections that fell outside the image
    std::int64_t holes = 0;          // pixels nothing was reprojected into
    void flush() const;              // into the RP/ counters
};

// One sharp frame: its samples, their transparent layers (null without transparency), the
// colours of their opaque hits (3 per sample, VisibilityBuffer order, no layers blended), its
// time, and the sample positions in their pixels.
struct SharpFrame {
    const VisibilityBuffer* visibility;
    const TransparentLayers* layers;
    const std::vector<float>* colors;
    const SampleGenerator* samples;
    float time;  // 0 or 1
};

Image reprojectSamples(const ShadingContext& context, const SharpFrame& open,
                       const SharpFrame& close, const Image& openPixels, const Image& closePixels,
                       const ReprojectionOptions& options, ReprojectionWork& work);

}  // namespace patchsim
