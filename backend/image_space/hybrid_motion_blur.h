#pragma once
// Hybrid motion blur (Tan, Cui, Bhojan 2022, "Hybrid MBlur: a systematic approach to augment
// rasterization with ray tracing for rendering motion blur in games"): the
// post-process of motion_blur_postprocess, plus rays that reveal the background the sharp frame
// hides behind moving objects: the `hybrid` visibility method.
//
// Ray mask, on the mid-shutter pinhole frame (its colour, depth, motion, and per pixel the object
// most of its opaque hits show, with that object's camera-space normal: the same hits as the
// depth and motion, so a silhouette pixel whose first sample misses is still its object's):
//   1. a moving pixel is a candidate when the pixel at its position plus its exposure's motion
//      shows another object (m_n != m_t) deeper by more than SOFT_Z_EXTENT (z_n - z_t > extent):
//      it is a foreground edge the motion uncovers;
//   2. a candidate is an edge when x_n = saturate(1 - 1 / (x + 1)) exceeds the threshold e, where
//      x = delta_d + delta_n, the unnormalised 5x5 Sobel gradient of depth (relative to the
//      pixel's depth) and the Frobenius norm of the normals' Sobel gradient: the paper's scale,
//      on which it sets e = 0.9 to 0.98;
//   3. range check: a moving pixel is masked when one of S samples along its velocity (the
//      gather's span) is an edge.
// Ray reveal: for each masked pixel, a ray through its centre at mid-shutter, and a second ray
// after the first hit (from the pixel's depth, skipping the pixel's object: its own far side is
// not a background), to the nearest surface of a different object behind it (one background
// layer), shaded at mid-shutter. Where nothing else is behind, nothing is revealed.
// Composite (reconstructMotionBlur with the revealed background): as the paper post-processes the
// ray-revealed background and the rasterized colour and composites them, the gather here splits a
// pixel's samples into the moving foreground, its coverage their share of the samples, and the
// background, the revealed colour where rays found one; the result is blended with the plain
// post-process by the share of the foreground whose background was revealed, so the mask's holes
// (its range check samples the velocity and can step over a thin edge) and its border are blends,
// not seams. The paper's optional extra weights in the mask (background x3, outer blur w_f x30)
// are not applied: the coverage composite makes the inner and outer blur meet at the silhouette.

#include <cstdint>

#include "backend/image_space/motion_blur_postprocess.h"
#include "backend/shading/resolve.h"
#include "backend/shading/t_fragment.h"
#include "core/work_counts.h"
#include "rasterizer/common/visibility_buffer.h"

namespace patchsim {

struct HybridOptions {
    PostprocessOptions post;
    float edgeThreshold = 0.9f;  // e, on x_n in [0, 1): the paper's 0.9 (0.96, 0.98 elsewhere)
};

// What the hybrid did beyond the post-process (counters HY/*).
// X(field, "Stage/Name", "unit", kind, "definition", charges...) (core/work_counts.h): the mask
// passes read pixels (post samples of the pixel shader stage); the second rays are the
// rasterizer's ray tests.
#define PATCHSIM_HYBRID_WORK(X)                                                                   \
    X(candidates, "HY/Mask candidates", "pixels", Sum,                                            \
      "Moving pixels whose motion uncovers a deeper, different object")                           \
    X(edgePixels, "HY/Edge pixels", "pixels", Sum, "Candidates above the Sobel edge threshold")   \
    X(maskedPixels, "HY/Masked pixels", "pixels", Sum,                                            \
      "Pixels in the ray mask (an edge within their velocity's reach)")                           \
    X(maskReads, "HY/Mask reads", "pixels", Sum, "Pixels read by the three mask passes",          \
      Op::PostSamples)                                                                            \
    X(rays, "HY/Rays", "rays", Sum, "Ray-reveal rays: the first and the second per masked pixel") \
    X(rayBoxTests, "HY/Ray-box tests", "tests", Sum, "Second rays against a patch's box",         \
      Op::RayBoxTests)                                                                            \
    X(rayTriangleTests, "HY/Ray-triangle tests", "tests", Sum,                                    \
      "Second rays against triangles (watertight test, mid-shutter)", Op::RayTriangleTests)       \
    X(revealed, "HY/Revealed pixels", "pixels", Sum,                                              \
      "Masked pixels whose second ray found another object behind")

struct HybridWork {
    PATCHSIM_HYBRID_WORK(PATCHSIM_WORK_FIELD)
    PATCHSIM_WORK_METHODS(HybridWork)
};
struct HybridCounters {
    PATCHSIM_HYBRID_WORK(PATCHSIM_WORK_HANDLE)
};
const HybridCounters& hybridCounters();

// `sharp` is the resolved mid-shutter frame, `visibility` its samples.
// With `trace`, records its passes (core/image_pass_trace.h): the resolve's AOVs and its
// object and normal planes written; the edge pass (every pixel's object and motion read; a moving
// pixel's neighbour along its motion, its object, and where that differs both depths; a
// candidate's 5 x 5 depths and normals; every pixel's edge byte written); the mask pass (every
// pixel's velocity, a moving pixel's span of edge bytes; every mask byte written); the reveal
// (every mask byte read, a masked pixel's depth and object, its revealed colour written; the
// rays' own traffic through the scene is not recorded); then the post-process's passes, whose
// gather reads each tap's object and revealed colour too.
Image hybridMotionBlur(const ShadingContext& context, const ResolvedFrame& sharp,
                       const VisibilityBuffer& visibility, const HybridOptions& options,
                       PostprocessWork& post, HybridWork& work, ImagePassTrace* trace = nullptr);

}  // namespace patchsim
