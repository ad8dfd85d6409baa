#pragma once
// One tile against one hierarchy (US 8,791,945, steps 4 and 5): the tile's frustum walks the tree
// of moving boxes from the root; a node outside a plane at t=0 and at t=1 is rejected with its
// subtree; at the leaves the crossing times narrow the tile's time range, and a leaf whose range
// empties is rejected too (early out). What survives is the set of overlapping leaves (a bit
// mask), the union of their time ranges, and the first node where the walk split in two.

#include <cstdint>

#include "pipeline/core/time_range.h"
#include "rasterizer/patch_hierarchy.h"
#include "rasterizer/raster_work.h"
#include "rasterizer/tile_frustum.h"

namespace patchsim {

struct TileTraversal {
    bool overlaps = false;
    TimeRange times = TimeRange::shutter();  // when the tile may see the patch
    std::uint64_t leafMask = 0;              // bit j: leaf j overlaps
    int firstSplitNode = -1;  // first node whose two children both overlap (or the single leaf)
};

// `motion` false tests static boxes only (no time ranges); `refineTime` narrows time ranges at
// the leaves. Counts tiles rejected by space or by time, node visits and plane tests.
TileTraversal traverseTile(const PatchHierarchy& hierarchy, TileFrustum frustum, bool motion,
                           bool refineTime, RasterWork& work);

}  // namespace patchsim
