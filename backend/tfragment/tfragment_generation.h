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

#include "backend/shading/t_fragment.h"
#include "core/work_counts.h"

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

// X(field, "Stage/Name", "unit", kind, "definition", charges...) (core/work_counts.h). Every
// motion sample is shaded; the resolve already charges one shading per sample (the lens ray's
// first motion sample), so the lens rays give that charge back.
#define PATCHSIM_TFRAGMENT_WORK(X)                                                                 \
    X(rasterizedFragments, "TF/Rasterized fragments", "fragments", Sum,                            \
      "Fragments of the two rasterization passes at t = 1 (depth layers, then generation)",        \
      Op::SamplesTested)                                                                           \
    X(disoccludedPixels, "TF/Disoccluded pixels", "pixels", Sum,                                   \
      "Pixels the disocclusion map marks (culled behind their first layer)")                       \
    X(generatedOpaque, "TF/Opaque t-fragments", "t-fragments", Sum,                                \
      "Opaque t-fragments generated")                                                              \
    X(generatedTransparent, "TF/Transparent t-fragments", "t-fragments", Sum,                      \
      "Transparent t-fragments generated")                                                         \
    X(culled, "TF/Culled fragments", "fragments", Sum,                                             \
      "Generation-pass fragments behind the culling depth (not made t-fragments)")                 \
    X(bvhNodes, "TF/BVH nodes", "nodes", Sum,                                                      \
      "LBVH nodes built (opaque and transparent hierarchies)", Op::NodesBuilt)                     \
    X(rayNodeTests, "TF/Ray-node tests", "tests", Sum, "Rays against a node's t-AABB",             \
      Op::RayBoxTests)                                                                             \
    X(capsuleTests, "TF/Capsule tests", "tests", Sum, "Lens rays against a leaf's capsule",        \
      Op::RayTriangleTests)                                                                        \
    X(collected, "TF/Collected t-fragments", "t-fragments", Sum,                                   \
      "t-fragments collected by lens rays")                                                        \
    X(collectOverflow, "TF/Collect overflow", "t-fragments", Sum,                                  \
      "t-fragments a lens ray met beyond its limit (dropped)")                                     \
    X(lensRays, "TF/Lens rays", "rays", Sum, "Lens rays traced (one per sample)",                  \
      Refund{Op::Invocations})                                                                     \
    X(motionSamples, "TF/Motion samples", "samples", Sum,                                          \
      "Time samples taken on collected t-fragments", Op::Invocations)                              \
    X(sphereTests, "TF/Sphere tests", "tests", Sum,                                                \
      "Ray against a t-fragment's circumsphere at a time", Op::RayTriangleTests)                   \
    X(cubeTests, "TF/Cube tests", "tests", Sum, "Ray against a t-fragment's pixel cube at a time", \
      Op::RayTriangleTests)                                                                        \
    X(visibilitySamples, "TF/Visibility samples", "samples", Sum,                                  \
      "Opaque t-fragment hits nearer than the motion sample's nearest so far")

struct TFragmentWork {
    PATCHSIM_TFRAGMENT_WORK(PATCHSIM_WORK_FIELD)
    PATCHSIM_WORK_METHODS(TFragmentWork)
};
struct TFragmentCounters {
    PATCHSIM_TFRAGMENT_WORK(PATCHSIM_WORK_HANDLE)
};
const TFragmentCounters& tfragmentCounters();

struct TFragmentSet {
    std::vector<TFragment> opaque, transparent;
};

// `defocus`: add depth edges to the disocclusion map.
TFragmentSet generateTFragments(const ShadingContext& context, bool defocus,
                                const TFragmentOptions& options, TFragmentWork& work);

}  // namespace patchsim
