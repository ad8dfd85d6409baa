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

#include "backend/images/image.h"
#include "backend/shading/t_fragment.h"
#include "core/image_pass_trace.h"
#include "core/samples.h"
#include "core/work_counts.h"
#include "rasterizer/common/transparent_layers.h"
#include "rasterizer/common/visibility_buffer.h"

namespace patchsim {

struct ReprojectionOptions {
    int cameraSteps = 16;  // interpolated cameras per reprojection cycle (both ends included)
};

// X(field, "Stage/Name", "unit", kind, "definition", charges...) (core/work_counts.h): each
// reprojection written is a pixel access of a full-screen pass (a post sample).
#define PATCHSIM_REPROJECTION_WORK(X)                                                              \
    X(samples, "RP/Samples", "samples", Sum, "Samples of the two sharp frames reprojected")        \
    X(layers, "RP/Transparent layers", "fragments", Sum,                                           \
      "Transparent layers in front of a sample's opaque hit, reprojected as parts of the sample")  \
    X(reprojections, "RP/Reprojections", "samples", Sum,                                           \
      "Part-camera reprojections (a sample's opaque hit or background, or one of its transparent " \
      "layers) written into the accumulation buffer",                                              \
      Op::PostSamples)                                                                             \
    X(offScreen, "RP/Off-screen reprojections", "samples", Sum,                                    \
      "Reprojections that fell outside the image")                                                 \
    X(holes, "RP/Holes", "pixels", Sum,                                                            \
      "Pixels no sample was reprojected into (disocclusions), filled by blending")

struct ReprojectionWork {
    PATCHSIM_REPROJECTION_WORK(PATCHSIM_WORK_FIELD)
    PATCHSIM_WORK_METHODS(ReprojectionWork)
};
struct ReprojectionCounters {
    PATCHSIM_REPROJECTION_WORK(PATCHSIM_WORK_HANDLE)
};
const ReprojectionCounters& reprojectionCounters();

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

// Each sample's part as the reprojection reads it: its colour (RGBA at 16 bits) and its world
// position or direction (four fp32).
inline constexpr std::uint32_t kSamplePartBytes = 8 + 16;
inline constexpr std::uint32_t kReprojectionSumBytes = 16;  // RGB sum and weight, fp32

// With `trace` (whose planes 0 and 1 are the open and close frames' resolved images), records
// its passes (core/image_pass_trace.h): the resolves' sample parts written (every sample of
// both frames); the reprojection (each sample's part read, and for each camera it lands in, the
// accumulation buffer's pixel updated); and the accumulation's resolve (every pixel's sum read,
// a hole's two frame pixels, every output pixel written). Opaque frames only: a transparent
// layer's part is not recorded.
Image reprojectSamples(const ShadingContext& context, const SharpFrame& open,
                       const SharpFrame& close, const Image& openPixels, const Image& closePixels,
                       const ReprojectionOptions& options, ReprojectionWork& work,
                       ImagePassTrace* trace = nullptr);

}  // namespace patchsim
