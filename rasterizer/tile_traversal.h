#pragma once
// One tile against one hierarchy (US 8,791,945, steps 4 and 5): the tile's frustum walks the tree
// of moving boxes from the root; a node outside a side at t=0 and at t=1 is rejected with its
// subtree; at the leaves the crossing times narrow the tile's time range, and a leaf whose range
// empties is rejected too (early out). What survives is the set of overlapping leaves (a bit
// mask), the union of their time ranges, and the first node where the walk split in two.
//
// The walk is the same in every bounds space; only the node test differs (3D boxes against the
// tile frustum's planes, 2DH boxes against its lines, 2D screen rectangles against its edges).
// Each is a small value type the walk is instantiated with, so the node tests are inlined calls.

#include <cstdint>
#include <vector>

#include "pipeline/core/rasterizer_options.h"
#include "pipeline/core/time_range.h"
#include "rasterizer/patch_hierarchy.h"
#include "rasterizer/projected_bounds.h"
#include "rasterizer/raster_work.h"
#include "rasterizer/tile_frustum.h"

namespace patchsim {

struct TileTraversal {
    bool overlaps = false;
    TimeRange times = TimeRange::shutter();  // when the tile may see the patch
    std::uint64_t leafMask = 0;              // bit j: leaf j overlaps
    int firstSplitNode = -1;  // first node whose two children both overlap (or the single leaf)
};

// A group's nodes in the bounds space of its tile tests; the 3D boxes are the hierarchy's own.
struct SpaceNodes {
    BoundsSpace space = BoundsSpace::Camera3D;
    std::vector<LBBox> homogeneous;       // 2DH, per node
    std::vector<ScreenMovingBox> screen;  // 2D, per node
    // Converts every node (counted in `work.nodesConverted`).
    void build(const PatchHierarchy& hierarchy, BoundsSpace space, const Camera& camera,
               const LensModel& lens, RasterWork& work);
};

// The tile as the test of each bounds space sees it.
struct TileBounds {
    const Camera* camera;
    LensModel lens;
    TileRect tile;
    float farDepth;  // the camera's far plane or the tile's z-buffer maximum
};

// `motion` false tests static boxes only (no time ranges); `refineTime` narrows time ranges at
// the leaves. Counts tiles rejected by space or by time, node visits and plane tests.
TileTraversal traverseTile(const PatchHierarchy& hierarchy, const SpaceNodes& nodes,
                           const TileBounds& tile, bool motion, bool refineTime, RasterWork& work);
// The 3D walk with a given frustum.
TileTraversal traverseTile(const PatchHierarchy& hierarchy, TileFrustum frustum, bool motion,
                           bool refineTime, RasterWork& work);

}  // namespace patchsim
