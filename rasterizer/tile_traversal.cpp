#include "rasterizer/tile_traversal.h"

#include <algorithm>

namespace patchsim {

TileTraversal traverseTile(const PatchHierarchy& h, TileFrustum frustum, bool motion,
                           bool refineTime, RasterWork& work) {
    const bool refine = motion && refineTime;
    TileTraversal result;
    // Near and far: tested with the root's p-vertex once; inside both, only the sides remain.
    frustum.testNearFar = !insideNearFar(frustum, h.node(0), work);
    ++work.frustumNodeVisits;
    bool spatialLeaf = false;
    if (overlapsFrustum(frustum, h.node(0), motion, work)) {
        result.times = TimeRange::empty();
        int stack[2 * kMaxLeavesPerHierarchy];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const int node = stack[--top];
            if (h.isLeaf(node)) {
                spatialLeaf = true;
                TimeRange leafTimes = TimeRange::shutter();
                if (refine && !leafTimeInterval(frustum, h.node(node), leafTimes, work)) continue;
                result.leafMask |= std::uint64_t(1)
                                   << (node - PatchHierarchy::firstLeaf(h.depth()));
                result.times.extend(leafTimes);
                if (result.firstSplitNode < 0) result.firstSplitNode = node;
                continue;
            }
            const int left = 2 * node + 1, right = 2 * node + 2;
            work.frustumNodeVisits += 2;
            const bool inLeft = overlapsFrustum(frustum, h.node(left), motion, work);
            const bool inRight = overlapsFrustum(frustum, h.node(right), motion, work);
            if (inLeft && inRight && result.firstSplitNode < 0) result.firstSplitNode = node;
            if (inRight) stack[top++] = right;
            if (inLeft) stack[top++] = left;
        }
    }
    if (result.leafMask == 0) {
        ++(spatialLeaf ? work.tilesRejectedTime : work.tilesRejectedSpace);
        return result;
    }
    result.overlaps = true;
    if (!motion) result.times = TimeRange::shutter();
    return result;
}

}  // namespace patchsim
