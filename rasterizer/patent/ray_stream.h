#pragma once
// Per-sample rays from the branch node (US 8,791,945, step 7), traced as a stream: all the rays of
// a tile go down the group's hierarchy together, a SIMD vector of rays at a time.
//
// The tile's rays are in time-bucket order (tile_rays.h). A pass over one group starts with the
// rays whose time lies in the tile's time range (an index range, then a per-ray check: "samples
// tested"), all tested against the branch node's box. The rays that meet a node are a list of
// sample indices with the box test's per-ray data beside them (TileRays::RayList), packed by vector
// compression, so each vector tested against a box is full however few rays reach it and loads its
// data instead of gathering it. A child is visited only when a leaf below it overlaps the tile, and
// a ray meets the child only when its time lies in the child's time range (the union of the time
// intervals of its overlapping leaves, from the tile test) and it passes the 12-multiply-add
// moving-box test; both children are tested with one load of the rays' data, then the nearer
// child's subtree is traced first, so its hits shorten the rays before the farther child's subtree.
// At a leaf, each ray is tested watertight against the leaf's triangles blended to its time; an
// opaque surface keeps the nearest hit in (depth, patch, triangle) order and shortens the ray, a
// transparent one offers every hit to the sample's layers.
//
// Every per-ray result equals the scalar tests' (moving_box_ray.h, watertight_triangle.h): the
// vector code performs the same float operations in the same order, without fused multiply-adds,
// so images and counts are the same on every SIMD target and on every thread count. Rays parallel
// to an axis and triangle tests with an edge function exactly zero take the scalar tests.
//
// The kernels are compiled for every x86 SIMD target Highway knows and dispatched at run time to
// the best the host supports, once per pass.

#include "core/time_range.h"
#include "rasterizer/common/lens_triangle.h"
#include "rasterizer/common/moving_mesh.h"
#include "rasterizer/common/screen_triangle.h"
#include "rasterizer/common/transparent_layers.h"
#include "rasterizer/patent/patch_hierarchy.h"
#include "rasterizer/patent/raster_work.h"
#include "rasterizer/patent/tile_rays.h"
#include "rasterizer/patent/tile_traversal.h"

namespace patchsim {

class RoundedArithmetic;

// Levels of mask scratch a pass may use: the branch node's rays, then one per level below it.
inline constexpr int kMaxStreamLevels = kMaxHierarchyDepth + 2;

// One group's pass over a tile.
struct StreamPass {
    const MovingMesh* mesh;
    const PatchHierarchy* hierarchy;
    const TileTraversal* traversal;
    int branchNode = 0;
    bool zCulling = true;  // rays end at their sample's depth (else at the far plane)
    // Set for a transparent mesh: every hit is offered to the layers from pool `pool`.
    TransparentLayers* transparent = nullptr;
    int pool = 0;
    // A static frame's projected leaf vertices (PatchRasterizer::Group), for screen_pass.h.
    const ScreenVertex* screenVertices = nullptr;
    // A defocus-only frame's projected leaf vertices, for lens_pass.h.
    const LensVertex* lensVertices = nullptr;
    // rasterizer.ray_box_format narrower than fp32: the ray-box tests in its arithmetic, bounded
    // (moving_box_ray_rounded.h), lane by lane; null for the fp32 vector test.
    const RoundedArithmetic* rayBoxArithmetic = nullptr;
    // rasterizer.triangle_format narrower than fp32: the ray-triangle tests in it, rounded to
    // nearest (watertight_triangle_rounded.h), lane by lane; null for the fp32 vector test.
    const NumberFormat* triangleFormat = nullptr;
};

// Traces the pass's rays; nearer opaque hits are kept in `rays`, counts go to `work`.
void traceRayStream(TileRays& rays, const StreamPass& pass, RasterWork& work);

// The largest of min(depth[i], farDepth) over i < count (count a multiple of kMaxLanes), and 0.
float farthestBoundOf(const float* depth, int count, float farDepth);

// Which SIMD target the kernels run on (e.g. "AVX3", "AVX2").
const char* rayStreamTarget();

}  // namespace patchsim
