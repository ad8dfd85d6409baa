#pragma once
// t-fragments (Widmer et al. 2016, "Decoupled space and time sampling of motion and defocus blur
// for unified rendering of transparent and opaque objects"): the first half of the `tfragment`
// method, rasterization at t = 1.
//
// Representation
// --------------
// A t-fragment is a surface point seen at a pixel centre at t = 1 (its patch, triangle and
// barycentrics), with its camera-space positions at t = 0 and t = 1: the segment it sweeps over
// the frame, bounded by a capsule of radius epsilon, the circumsphere of a pixel-sized cube at its
// depth (camera space stands in for the paper's anisotropic NDC: epsilon follows the depth).
// Opaque and transparent t-fragments are kept in separate unordered arrays.
//
// Generation: the opaque triangles facing the camera are rasterized at t = 1 (pixel centres,
// perspective-correct) into two depth layers, so the second layer is the next surface behind, not
// a closed object's own far side, and the nearest surface that stays put over the frame is noted;
// the first layer's velocity field gives a motion disocclusion map (a pixel whose velocity differs
// from its right or upper neighbour's by d pixels marks a square of radius d around it), OR'ed with
// thresholded depth Laplacians when the lens blurs. Unmarked pixels cull against the first layer;
// depth edges against the second (what lens rays see past the edge); motion marks against the
// nearest surface that stays put, or not at all: unlike the paper's second layer, which may itself
// move (two moving objects overlapping at t = 1 put the static wall behind them third), only a
// surface that covers the pixel all frame hides what is behind it all frame. A second
// rasterization keeps every fragment that passes that culling depth (opaque ones facing the
// camera; transparent ones both sides). The raster extends past the screen by a guard band.

#include <cstdint>
#include <vector>

#include "backend/t_fragment.h"

namespace patchsim {

struct TFragment {
    Vec3 position0, position1;  // camera space at t = 0 and t = 1
    float radius;               // capsule radius epsilon
    std::int32_t patch;
    std::uint32_t triangle;
    float b1, b2;
};

struct TFragmentOptions {
    int guardBand = 16;               // pixels past each screen edge
    float laplacianThreshold = 0.1f;  // |Laplacian of depth| / depth that marks a depth edge
    float disocclusionPixels = 0.5f;  // velocity difference that marks a disocclusion
    int motionSamples = 4;            // time samples per lens ray
    int maxCollected = 128;           // t-fragments a lens ray keeps (the paper's limit)
};

struct TFragmentWork {
    std::int64_t rasterizedFragments = 0;  // both passes
    std::int64_t disoccludedPixels = 0;
    std::int64_t generatedOpaque = 0, generatedTransparent = 0;
    std::int64_t culled = 0;  // second-pass fragments the culling depth rejected
    std::int64_t bvhNodes = 0, rayNodeTests = 0, capsuleTests = 0, collected = 0,
                 collectOverflow = 0, lensRays = 0, motionSamples = 0, sphereTests = 0,
                 cubeTests = 0;
    std::int64_t visibilitySamples = 0;  // opaque hits nearer than the motion sample's nearest
    void flush() const;                  // into the TF/ counters
};

struct TFragmentSet {
    std::vector<TFragment> opaque, transparent;
};

// `defocus`: add depth edges to the disocclusion map.
TFragmentSet generateTFragments(const ShadingContext& context, bool defocus,
                                const TFragmentOptions& options, TFragmentWork& work);

}  // namespace patchsim
