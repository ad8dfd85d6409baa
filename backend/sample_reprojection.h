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
// Each sharp frame keeps its nearest hit per sample, so transparent surfaces count as opaque.

#include <cstdint>
#include <vector>

#include "backend/image.h"
#include "backend/t_fragment.h"
#include "pipeline/core/samples.h"
#include "rasterizer/visibility_buffer.h"

namespace patchsim {

struct ReprojectionOptions {
    int cameraSteps = 16;  // interpolated cameras per reprojection cycle (both ends included)
};

struct ReprojectionWork {
    std::int64_t samples = 0;        // samples of the two frames
    std::int64_t reprojections = 0;  // sample-camera reprojections written
    std::int64_t offScreen = 0;      // reprojections that fell outside the image
    std::int64_t holes = 0;          // pixels nothing was reprojected into
    void flush() const;              // into the RP/ counters
};

// One sharp frame: its samples, their colours (3 per sample, VisibilityBuffer order), its time,
// and the sample positions in their pixels.
struct SharpFrame {
    const VisibilityBuffer* visibility;
    const std::vector<float>* colors;
    const SampleGenerator* samples;
    float time;  // 0 or 1
};

Image reprojectSamples(const ShadingContext& context, const SharpFrame& open,
                       const SharpFrame& close, const Image& openPixels, const Image& closePixels,
                       const ReprojectionOptions& options, ReprojectionWork& work);

}  // namespace patchsim
