#pragma once
// One tile against one hierarchy (US 8,791,945, steps 4 and 5): the tile's frustum walks the tree
// of moving boxes from the root; a node outside a side at t=0 and at t=1 is rejected with its
// subtree; at the leaves the crossing times narrow the tile's time range, and a leaf whose range
// empties is rejected too (early out). Optionally the times are narrowed at every node on the way
// down, so a subtree that sweeps past the tile at other times is rejected at its top. What survives
// is the set of overlapping leaves (a bit mask), the union of their time ranges, and the first node
// where the walk split in two.
//
// The walk is the same in every bounds space; only the node test differs (3D boxes against the
// tile frustum's planes, 2DH boxes against its lines, 2D screen rectangles against its edges).
// Each is a small value type the walk is instantiated with, so the node tests are inlined calls.
// In camera space the tile's side planes sit in SIMD lanes: a node is tested against all of them,
// at both shutter ends, at once; results and counts equal the scalar tests'. The walk is compiled
// for every SIMD target and dispatched once per tile.

#include <array>
#include <cstdint>
#include <vector>

#include "core/rasterizer_options.h"
#include "core/time_range.h"
#include "rasterizer/patent/patch_hierarchy.h"
#include "rasterizer/patent/projected_bounds.h"
#include "rasterizer/patent/raster_work.h"
#include "rasterizer/patent/tile_frustum.h"

namespace patchsim {

struct TileTraversal {
    bool overlaps = false;
    TimeRange times = TimeRange::shutter();  // when the tile may see the patch
    std::uint64_t leafMask = 0;              // bit j: leaf j overlaps
    int firstSplitNode = -1;  // first node whose two children both overlap (or the single leaf)
    // When leaf j overlaps (bit j of leafMask): the times it may be seen through the tile.
    std::array<TimeRange, kMaxLeavesPerHierarchy> leafTimes;
};

// A group's nodes in the bounds space of its tile tests; the 3D boxes are the hierarchy's own.
struct SpaceNodes {
    BoundsSpace space = BoundsSpace::Camera3D;
    std::vector<LBBox> homogeneous;       // 2DH, per node
    std::vector<ScreenMovingBox> screen;  // 2D, per node
    // Converts every node (counted in `work.nodesConverted`); the 2D nodes are stored in
    // `screenFormat`, rounded outward (rasterizer.screen_bounds_format).
    void build(const PatchHierarchy& hierarchy, BoundsSpace space, const Camera& camera,
               const LensModel& lens, RasterWork& work,
               const NumberFormat& screenFormat = NumberFormat::fp32());
};

// The tile as the test of each bounds space sees it.
struct TileBounds {
    const Camera* camera;
    LensModel lens;
    TileRect tile;
    float farDepth;  // the camera's far plane or the tile's z-buffer maximum
    // The 3D planes' arithmetic (rasterizer.plane_format): fp32 is the vector test.
    NumberFormat planeFormat = NumberFormat::fp32();
};

// How a walk narrows time: not at all, at the leaves (the patent), or at every node from the root
// down (a child's times lie within its parent's, so a subtree seen only at other times is
// rejected where it starts).
enum class TimeRefinement : std::uint8_t { Off, Leaves, EveryLevel };
TimeRefinement timeRefinementOf(const RasterizerOptions& options);

// `motion` false tests static boxes only (no time ranges). Counts tiles rejected by space or by
// time, node visits and plane tests.
TileTraversal traverseTile(const PatchHierarchy& hierarchy, const SpaceNodes& nodes,
                           const TileBounds& tile, bool motion, TimeRefinement refine,
                           RasterWork& work);
// The 3D walk with a given frustum.
TileTraversal traverseTile(const PatchHierarchy& hierarchy, TileFrustum frustum, bool motion,
                           TimeRefinement refine, RasterWork& work);
// The same walk with the scalar node tests of tile_frustum.h (the vector walk must equal it).
TileTraversal traverseTileScalar(const PatchHierarchy& hierarchy, TileFrustum frustum, bool motion,
                                 TimeRefinement refine, RasterWork& work);

}  // namespace patchsim
