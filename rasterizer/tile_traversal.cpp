#include "rasterizer/tile_traversal.h"

#include <algorithm>

namespace patchsim {

namespace {

// The node tests of each bounds space: `startAtRoot` (near and far once, with the root's
// p-vertex), `overlaps` (interior nodes) and `leafTimes` (leaves, with time refinement).
struct CameraSpaceTest {
    const PatchHierarchy& h;
    TileFrustum frustum;
    void startAtRoot(RasterWork& work) {
        frustum.testNearFar = !insideNearFar(frustum, h.node(0), work);
    }
    bool overlaps(int node, bool motion, RasterWork& work) const {
        return overlapsFrustum(frustum, h.node(node), motion, work);
    }
    bool leafTimes(int node, TimeRange& times, RasterWork& work) const {
        return leafTimeInterval(frustum, h.node(node), times, work);
    }
};

struct HomogeneousTest {
    const std::vector<LBBox>& nodes;
    HomogeneousFrustum frustum;
    void startAtRoot(RasterWork& work) {
        frustum.testNearFar = !insideNearFarHomogeneous(frustum, nodes[0], work);
    }
    bool overlaps(int node, bool motion, RasterWork& work) const {
        return overlapsHomogeneous(frustum, nodes[std::size_t(node)], motion, work);
    }
    bool leafTimes(int node, TimeRange& times, RasterWork& work) const {
        return homogeneousTimeInterval(frustum, nodes[std::size_t(node)], times, work);
    }
};

struct ScreenTest {
    const std::vector<ScreenMovingBox>& nodes;
    ScreenTile tile;
    void startAtRoot(RasterWork&) {}
    bool overlaps(int node, bool motion, RasterWork& work) const {
        return overlapsScreenTile(tile, nodes[std::size_t(node)], motion, work);
    }
    bool leafTimes(int node, TimeRange& times, RasterWork& work) const {
        return screenTileTimes(tile, nodes[std::size_t(node)], times, work);
    }
};

template <typename Test>
TileTraversal walk(const PatchHierarchy& h, Test test, bool motion, bool refineTime,
                   RasterWork& work) {
    const bool refine = motion && refineTime;
    TileTraversal result;
    test.startAtRoot(work);
    ++work.frustumNodeVisits;
    bool spatialLeaf = false;
    if (test.overlaps(0, motion, work)) {
        result.times = TimeRange::empty();
        int stack[2 * kMaxLeavesPerHierarchy];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const int node = stack[--top];
            if (h.isLeaf(node)) {
                spatialLeaf = true;
                TimeRange leafTimes = TimeRange::shutter();
                if (refine && !test.leafTimes(node, leafTimes, work)) continue;
                result.leafMask |= std::uint64_t(1)
                                   << (node - PatchHierarchy::firstLeaf(h.depth()));
                result.times.extend(leafTimes);
                if (result.firstSplitNode < 0) result.firstSplitNode = node;
                continue;
            }
            const int left = 2 * node + 1, right = 2 * node + 2;
            work.frustumNodeVisits += 2;
            const bool inLeft = test.overlaps(left, motion, work);
            const bool inRight = test.overlaps(right, motion, work);
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

}  // namespace

void SpaceNodes::build(const PatchHierarchy& h, BoundsSpace s, const Camera& camera,
                       const LensModel& lens, RasterWork& work) {
    space = s;
    homogeneous.clear();
    screen.clear();
    if (s == BoundsSpace::Camera3D) return;
    for (int i = 0; i < h.nodeCount(); ++i) {
        if (s == BoundsSpace::Homogeneous2D)
            homogeneous.push_back(toHomogeneous(h.node(i)));
        else
            screen.push_back(projectMovingBox(h.node(i), camera, lens));
    }
    work.nodesConverted += h.nodeCount();
}

TileTraversal traverseTile(const PatchHierarchy& h, const SpaceNodes& nodes, const TileBounds& t,
                           bool motion, bool refineTime, RasterWork& work) {
    switch (nodes.space) {
        case BoundsSpace::Homogeneous2D:
            return walk(
                h,
                HomogeneousTest{nodes.homogeneous,
                                makeHomogeneousFrustum(*t.camera, t.lens, t.tile, t.farDepth)},
                motion, refineTime, work);
        case BoundsSpace::Screen2D:
            return walk(h, ScreenTest{nodes.screen, makeScreenTile(*t.camera, t.tile, t.farDepth)},
                        motion, refineTime, work);
        case BoundsSpace::Camera3D:
            break;
    }
    return walk(h, CameraSpaceTest{h, makeTileFrustum(*t.camera, t.lens, t.tile, t.farDepth)},
                motion, refineTime, work);
}

TileTraversal traverseTile(const PatchHierarchy& h, TileFrustum frustum, bool motion,
                           bool refineTime, RasterWork& work) {
    return walk(h, CameraSpaceTest{h, frustum}, motion, refineTime, work);
}

}  // namespace patchsim
