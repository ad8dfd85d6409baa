#pragma once
// Post-process motion blur (McGuire, Hennessy, Bukowski, Osman 2012, "A reconstruction filter for
// plausible motion blur"), with the sample weights as restated in the appendix of Tan et al. 2022
// ("Hybrid MBlur", Tan, Cui, Bhojan 2022): the `postprocess` visibility method.
//
// Input is one sharp frame rendered with a pinhole at mid-shutter: its colour, depth, and each
// pixel's screen motion over the exposure (the resolve's motion AOV). A pixel's velocity V is
// half that motion (the blur reaches that far on either side), clamped to the tile size k.
// TileMax keeps each k x k tile's longest velocity, NeighbourMax the longest of the 3 x 3 tiles
// around; a pixel whose neighbourhood is still (|v_N| <= 0.5 pixel) is returned unchanged.
// Otherwise it gathers S samples along v_N (jittered, spread over [-1, 1] x v_N) and weights each
// by w = w_f + w_b + w_s:
//
//   z   = (z_target - z_sample) / SOFT_Z_EXTENT   (> 0: the sample is in front)
//   w_f = saturate(1 + z) saturate(1 - s / v_sample)     a blurry sample in front covers it
//   w_b = saturate(1 - z) saturate(1 - s / v_target)     what lies behind a blurry target
//   w_s = cylinder(v_sample, s) cylinder(v_target, s) 2  both blurry
//   cylinder(v, s) = 1 - smoothstep(0.95 v, 1.05 v, s)
//
// with s the distance in pixels. Pixels with no hit are background at the far plane. Its known
// failure: the background behind a moving object is not in the frame, so inner blur shows the
// object's neighbours instead (docs/ACCURACY.md).

#include <cstdint>

#include "backend/images/image.h"
#include "backend/shading/resolve.h"
#include "core/image_pass_trace.h"
#include "core/work_counts.h"

namespace patchsim {

struct PostprocessOptions {
    int tileSize = 20;          // k, pixels (McGuire et al. use 20 at 1280x720)
    int samples = 15;           // S, gathered per pixel (odd: the centre is the pixel itself)
    float softZExtent = 0.05f;  // SOFT_Z_EXTENT, scene units of depth
    std::uint64_t seed = 0;     // the gather's per-pixel jitter
};

// What the filter did (counters PP/*, charged to the pixel shader stage by the timing model).
// X(field, "Stage/Name", "unit", kind, "definition", charges...) (core/work_counts.h). The
// filter's full-screen passes read pixels: charged to the pixel shader stage as post samples.
#define PATCHSIM_POSTPROCESS_WORK(X)                                                     \
    X(pixels, "PP/Pixels", "pixels", Sum, "Pixels of the sharp frame read into TileMax", \
      Op::PostSamples)                                                                   \
    X(tiles, "PP/Tiles", "tiles", Sum, "TileMax and NeighbourMax tiles computed")        \
    X(blurredPixels, "PP/Blurred pixels", "pixels", Sum,                                 \
      "Pixels whose neighbourhood moves by more than half a pixel (gathered)")           \
    X(gatherSamples, "PP/Gather samples", "samples", Sum,                                \
      "Samples read and weighted by the reconstruction filter's gather", Op::PostSamples)

struct PostprocessWork {
    PATCHSIM_POSTPROCESS_WORK(PATCHSIM_WORK_FIELD)
    PATCHSIM_WORK_METHODS(PostprocessWork)
};
struct PostprocessCounters {
    PATCHSIM_POSTPROCESS_WORK(PATCHSIM_WORK_HANDLE)
};
const PostprocessCounters& postprocessCounters();

// Background revealed behind a pixel by rays (the hybrid method): per pixel, its colour, whether
// a ray found one, and the object the pixel shows (-1: none).
struct RevealedBackground {
    std::vector<Vec3> color;
    std::vector<std::uint8_t> found;
    std::vector<int> object;
};

// The planes the filter reads beside the resolved colour, in an image-space trace
// (core/image_pass_trace.h), and the one the hybrid's revealed background lies in (0: none).
struct PostprocessPlanes {
    ImagePassTrace* trace = nullptr;  // null: nothing recorded
    std::uint16_t depth = 0, velocity = 0, revealed = 0;
};
inline constexpr std::uint32_t kPlaneDepthBytes = 4;     // fp32
inline constexpr std::uint32_t kPlaneVelocityBytes = 4;  // two fp16, as are the tile maxima
// Declares the depth and velocity planes in `trace` and records the resolve's writes of them,
// pixel by pixel (the pass "resolve AOVs"): the AOVs the filter reads.
PostprocessPlanes recordResolveAovs(ImagePassTrace& trace, int width, int height);

// The blurred colour of `sharp` (same size). `farDepth` stands in for the depth of pixels with no
// hit. With `revealed` (the hybrid), a pixel is composited as foreground over background, the
// foreground's share of the S gathered samples being its coverage over the exposure:
//   inner blur, a pixel some of whose own object's samples have a revealed background: those
//     samples (weighted as above) over the background revealed behind it (or, in a hole of the
//     ray mask, the mean of its samples' revealed backgrounds);
//   outer blur, a pixel with samples in front of it that move over it (saturate(z) times
//     cylinder(v_sample, s)), some with a revealed background: those samples over the rest of
//     the gather; the same coverage as the inner blur, so the two meet at the silhouette.
// Either is blended with the post-process's colour by the share of those samples whose
// background a ray revealed: the ray mask's holes and edges are no seams, and a pixel with no
// such sample gets the post-process's colour, bit for bit.
// With `planes.trace`, records its passes: TileMax (every pixel's velocity read in row order, a
// tile row's maxima written once its last pixel row is read), NeighbourMax (each tile's 3 x 3
// tile maxima read, its maximum written) and the gather (a pixel's NeighbourMax and colour read;
// a blurred pixel's depth and velocity too, and each tap's colour, depth and velocity, and its
// revealed background with the hybrid's; every pixel's output written, a still one a copy).
Image reconstructMotionBlur(const ResolvedFrame& sharp, float farDepth,
                            const PostprocessOptions& options, PostprocessWork& work,
                            const RevealedBackground* revealed = nullptr,
                            const PostprocessPlanes& planes = {});

// Half the exposure's screen motion of pixel i, clamped to `k` pixels (the filter's velocity).
Vec2 pixelVelocity(const ResolvedFrame& sharp, std::size_t i, float k);

}  // namespace patchsim
