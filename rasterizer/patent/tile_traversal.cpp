// The tile walk, compiled once per SIMD target (Highway's foreach_target re-includes this file):
// the camera-space node test evaluates the tile's side planes in vector lanes.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "rasterizer/patent/tile_traversal.cpp"
#include "rasterizer/patent/tile_traversal.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <bit>

#include "rasterizer/common/conservative_margins.h"
#include "rasterizer/patent/projected_bounds_rounded.h"
#include "rasterizer/patent/tile_frustum_rounded.h"

HWY_BEFORE_NAMESPACE();
namespace patchsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The node tests of each bounds space: `startAtRoot` (near and far once, with the root's
// p-vertex), `overlaps` (interior nodes) and `leafTimes` (leaves, with time refinement).

// The scalar camera-space test (tile_frustum.h), for checking the vector one.
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

// The camera-space test computed in rasterizer.plane_format (tile_frustum_rounded.h), each
// distance bounded by its rounding error: scalar, as an emulation of the format.
struct RoundedCameraSpaceTest {
    const PatchHierarchy& h;
    TileFrustum frustum;
    RoundedArithmetic arithmetic;
    void startAtRoot(RasterWork& work) {
        frustum.testNearFar = !insideNearFar(frustum, h.node(0), work);
    }
    bool overlaps(int node, bool motion, RasterWork& work) const {
        return overlapsFrustumRounded(frustum, h.node(node), arithmetic,
                                      PlaneErrorHandling::Bounded, motion, work);
    }
    bool leafTimes(int node, TimeRange& times, RasterWork& work) const {
        return leafTimeIntervalRounded(frustum, h.node(node), arithmetic,
                                       PlaneErrorHandling::Bounded, times, work);
    }
};

// The same test with the side planes in vector lanes (plane p = side * planesPerSide + k): one
// pass finds which planes a node's n-vertex is outside of, at t=0 and at t=1, with the float
// operations of Plane::distance; what follows (which planes a scalar walk would have tested, and
// the counts) is replayed from those bits, so results and counts equal CameraSpaceTest's.
struct CameraSpaceLanes {
    static constexpr int kPlanes = 8;
    using DP = hn::CappedTag<float, kPlanes>;

    const PatchHierarchy& h;
    TileFrustum frustum;
    int planes = 0;
    // Per plane: normal, offset, and whether the n-vertex takes each axis's lower corner.
    alignas(64) float nx[kPlanes], ny[kPlanes], nz[kPlanes], offset[kPlanes];
    alignas(64) float lowerX[kPlanes], lowerY[kPlanes], lowerZ[kPlanes];

    CameraSpaceLanes(const PatchHierarchy& hierarchy, const TileFrustum& f)
        : h(hierarchy), frustum(f), planes(4 * f.planesPerSide) {
        for (int p = 0; p < kPlanes; ++p) {
            // Unused lanes: a plane nothing is outside of.
            const Plane pl = p < planes ? f.sides[p / f.planesPerSide][p % f.planesPerSide]
                                        : Plane{Vec3(0), -1.0f};
            nx[p] = pl.n.x;
            ny[p] = pl.n.y;
            nz[p] = pl.n.z;
            offset[p] = pl.d;
            lowerX[p] = pl.n.x > 0 ? 1.0f : 0.0f;
            lowerY[p] = pl.n.y > 0 ? 1.0f : 0.0f;
            lowerZ[p] = pl.n.z > 0 ? 1.0f : 0.0f;
        }
#if HWY_TARGET <= HWY_AVX3
        initBothEnds();
#endif
    }

#if HWY_TARGET <= HWY_AVX3
    // 16 lanes: plane p at t=0 in lane p, at t=1 in lane p + 8. A node's 12 box floats load as
    // one vector; each lane picks its n-vertex coordinates out of it with a lane permute.
    using D16 = hn::FixedTag<float, 16>;
    using Pick = decltype(hn::SetTableIndices(D16(), static_cast<const std::int32_t*>(nullptr)));
    static_assert(sizeof(LBBox) == 12 * sizeof(float));
    hn::Vec<D16> nx16, ny16, nz16, offset16;
    Pick pickX, pickY, pickZ;

    void initBothEnds() {
        const D16 d;
        alignas(64) float n[4][16];
        alignas(64) std::int32_t pick[3][16];
        const float* lower[3] = {lowerX, lowerY, lowerZ};
        for (int lane = 0; lane < 16; ++lane) {
            const int p = lane % kPlanes, end = lane / kPlanes;
            n[0][lane] = nx[p];
            n[1][lane] = ny[p];
            n[2][lane] = nz[p];
            n[3][lane] = offset[p];
            // bounds0.lower, bounds0.upper, bounds1.lower, bounds1.upper: 3 floats each.
            for (int axis = 0; axis < 3; ++axis)
                pick[axis][lane] = 6 * end + (lower[axis][p] > 0 ? 0 : 3) + axis;
        }
        nx16 = hn::Load(d, n[0]);
        ny16 = hn::Load(d, n[1]);
        nz16 = hn::Load(d, n[2]);
        offset16 = hn::Load(d, n[3]);
        pickX = hn::SetTableIndices(d, pick[0]);
        pickY = hn::SetTableIndices(d, pick[1]);
        pickZ = hn::SetTableIndices(d, pick[2]);
    }

    // Plane distances of the n-vertex at both ends (lanes as above).
    hn::Vec<D16> bothEnds(const LBBox& box) const {
        const D16 d;
        const auto v = hn::MaskedLoad(hn::FirstN(d, 12), d, reinterpret_cast<const float*>(&box));
        const auto x = hn::TableLookupLanes(v, pickX);
        const auto y = hn::TableLookupLanes(v, pickY);
        const auto z = hn::TableLookupLanes(v, pickZ);
        return hn::Add(hn::Add(hn::Add(hn::Mul(nx16, x), hn::Mul(ny16, y)), hn::Mul(nz16, z)),
                       offset16);
    }
#endif

    void startAtRoot(RasterWork& work) {
        frustum.testNearFar = !insideNearFar(frustum, h.node(0), work);
    }

    // The n-vertex coordinate of one axis in lanes [c, c + Lanes).
    static hn::Vec<DP> corner(const float* lower, int c, float lo, float hi) {
        const DP d;
        return hn::IfThenElse(hn::Gt(hn::Load(d, lower + c), hn::Zero(d)), hn::Set(d, lo),
                              hn::Set(d, hi));
    }

    // Plane distances of the box's n-vertex, lanes [c, c + Lanes).
    hn::Vec<DP> distances(const Box3& box, int c) const {
        const DP d;
        const auto x = corner(lowerX, c, box.lower.x, box.upper.x);
        const auto y = corner(lowerY, c, box.lower.y, box.upper.y);
        const auto z = corner(lowerZ, c, box.lower.z, box.upper.z);
        const auto dot =
            hn::Add(hn::Add(hn::Mul(hn::Load(d, nx + c), x), hn::Mul(hn::Load(d, ny + c), y)),
                    hn::Mul(hn::Load(d, nz + c), z));
        return hn::Add(dot, hn::Load(d, offset + c));
    }

    // Bit p: the n-vertex is outside plane p at that shutter end.
    unsigned outsideBits(const Box3& box) const {
        const DP d;
        unsigned bits = 0;
        for (int c = 0; c < planes; c += int(hn::Lanes(d))) {
            std::uint8_t lanes[8] = {};
            hn::StoreMaskBits(d, hn::Gt(distances(box, c), hn::Zero(d)), lanes);
            bits |= unsigned(lanes[0]) << c;
        }
        return bits;
    }

    // A node's n-vertex against the side planes at both shutter ends.
    struct Measure {
        unsigned open = 0, close = 0;  // bit p: outside plane p at t=0, at t=1
        alignas(64) float d0[kPlanes], d1[kPlanes], crossing[kPlanes];
    };

    void measure(const LBBox& box, bool withTimes, Measure& m) const {
#if HWY_TARGET <= HWY_AVX3
        const D16 d;
        const auto both = bothEnds(box);
        std::uint8_t bits[8] = {};
        hn::StoreMaskBits(d, hn::Gt(both, hn::Zero(d)), bits);
        m.open = bits[0];
        m.close = bits[1];
        if (!withTimes) return;
        const hn::FixedTag<float, 8> d8;
        const auto d0 = hn::LowerHalf(d8, both), d1 = hn::UpperHalf(d8, both);
        hn::Store(d0, d8, m.d0);
        hn::Store(d1, d8, m.d1);
        hn::Store(hn::Div(d0, hn::Sub(d0, d1)), d8, m.crossing);
#else
        m.open = outsideBits(box.bounds0);
        m.close = outsideBits(box.bounds1);
        if (!withTimes) return;
        const DP d;
        for (int c = 0; c < planes; c += int(hn::Lanes(d))) {
            const auto d0 = distances(box.bounds0, c), d1 = distances(box.bounds1, c);
            hn::Store(d0, d, m.d0 + c);
            hn::Store(d1, d, m.d1 + c);
            hn::Store(hn::Div(d0, hn::Sub(d0, d1)), d, m.crossing + c);
        }
#endif
    }

    // overlapsFrustum's result and counts, from the measured bits.
    bool overlapsAfter(const LBBox& box, const Measure& m, bool motion, RasterWork& work) const {
        for (int side = 0; side < 4; ++side) {
            bool outside = true;
            for (int k = 0; k < frustum.planesPerSide && outside; ++k) {
                const int p = side * frustum.planesPerSide + k;
                ++work.planeTests;
                outside = m.open >> p & 1u;
                if (!outside || !motion) continue;
                ++work.planeTests;
                outside = m.close >> p & 1u;
            }
            if (outside) return false;
        }
        return !(frustum.testNearFar && outsideNearOrFar(frustum, box, motion, work));
    }

#if HWY_TARGET <= HWY_AVX3
    // leafTimeInterval's result and counts, from the measured distances: each plane's interval
    // and each side's union (its two lens planes) in lanes, then the sides in turn, as the scalar
    // test would narrow and stop.
    bool timesAfter(const LBBox& box, const Measure& m, TimeRange& times, RasterWork& work) const {
        const hn::FixedTag<float, 8> d;
        const auto zero = hn::Zero(d), one = hn::Set(d, 1.0f), guard = hn::Set(d, kTimeGuard);
        const auto d0 = hn::Load(d, m.d0), d1 = hn::Load(d, m.d1);
        const auto crossing = hn::Load(d, m.crossing);
        const auto out0 = hn::Gt(d0, zero), out1 = hn::Gt(d1, zero);
        const auto both = hn::And(out0, out1);
        // Entering: [max(0, t - guard), 1]; leaving: [0, min(1, t + guard)]; outside at both
        // ends: no interval ([1, 0], which a union ignores).
        auto lower =
            hn::IfThenElse(hn::AndNot(out1, out0), hn::Max(hn::Sub(crossing, guard), zero), zero);
        auto upper =
            hn::IfThenElse(hn::AndNot(out0, out1), hn::Min(hn::Add(crossing, guard), one), one);
        lower = hn::IfThenElse(both, one, lower);
        upper = hn::IfThenElse(both, zero, upper);
        if (frustum.planesPerSide == 2) {  // a side's two lens planes: the union
            lower = hn::Min(lower, hn::Shuffle2301(lower));
            upper = hn::Max(upper, hn::Shuffle2301(upper));
        }
        alignas(32) float lowers[8], uppers[8];
        hn::Store(lower, d, lowers);
        hn::Store(upper, d, uppers);
        // The sides narrow in turn and the scalar test stops at the first that leaves nothing.
        // Once empty the running intersection stays empty, so the sides it tests follow from how
        // many of the four running intersections are empty: no branch per side, whose outcome
        // the predictor cannot learn.
        const int perSide = frustum.planesPerSide;
        int emptyAfter = 0;  // sides after which the running intersection is empty
        for (int side = 0; side < 4; ++side) {
            times.intersect({lowers[side * perSide], uppers[side * perSide]});
            emptyAfter += times.isEmpty();
        }
        const int sidesTested = emptyAfter == 0 ? 4 : 5 - emptyAfter;
        const unsigned testedPlanes = (1u << (sidesTested * perSide)) - 1;
        work.planeTests += 2 * perSide * sidesTested;
        work.timeIntervals += std::popcount((m.open ^ m.close) & testedPlanes);
        if (emptyAfter != 0) return false;
        return !frustum.testNearFar || narrowToNearFar(frustum, box, times, work);
    }
#else
    // leafTimeInterval's result and counts, from the measured distances.
    bool timesAfter(const LBBox& box, const Measure& m, TimeRange& times, RasterWork& work) const {
        for (int side = 0; side < 4; ++side) {
            TimeRange sideTimes = TimeRange::empty();
            for (int k = 0; k < frustum.planesPerSide; ++k) {
                const int p = side * frustum.planesPerSide + k;
                work.planeTests += 2;
                TimeRange inside = TimeRange::shutter();
                if (m.d0[p] > 0 && m.d1[p] > 0) continue;
                if (m.d0[p] > 0) {  // moves from outside to inside
                    ++work.timeIntervals;
                    inside.lower = std::max(0.0f, m.crossing[p] - kTimeGuard);
                } else if (m.d1[p] > 0) {  // moves from inside to outside
                    ++work.timeIntervals;
                    inside.upper = std::min(1.0f, m.crossing[p] + kTimeGuard);
                }
                sideTimes.extend(inside);
            }
            times.intersect(sideTimes);
            if (times.isEmpty()) return false;
        }
        return !frustum.testNearFar || narrowToNearFar(frustum, box, times, work);
    }
#endif

    bool overlaps(int node, bool motion, RasterWork& work) const {
        const LBBox& box = h.node(node);
        if (box.empty()) return false;
        Measure m;
        measure(box, false, m);
        return overlapsAfter(box, m, motion, work);
    }

    bool leafTimes(int node, TimeRange& times, RasterWork& work) const {
        const LBBox& box = h.node(node);
        if (box.empty()) return false;
        Measure m;
        measure(box, true, m);
        return timesAfter(box, m, times, work);
    }

    // Time refinement at every level: the interval test alone decides (a box outside a side at
    // both ends has no interval there), and counts; whether a rejected box was outside in space
    // as well is read from the same measurement, uncounted, to tell why a tile was rejected (the
    // walk asks only of rejected nodes, so `spatial` is left false for a kept one).
    bool refine(int node, TimeRange& times, bool& spatial, RasterWork& work) const {
        const LBBox& box = h.node(node);
        spatial = false;
        if (box.empty()) return false;
        Measure m;
        measure(box, true, m);
        if (timesAfter(box, m, times, work)) return true;
        spatial = !outsideInSpace(box, m);
        return false;
    }

    // overlapsAfter's answer with motion, without its counts: outside every plane of a side at
    // both shutter ends (from the bits), or beyond the near or far plane at both.
    bool outsideInSpace(const LBBox& box, const Measure& m) const {
        const unsigned both = m.open & m.close;
        const unsigned sidePlanes = (1u << frustum.planesPerSide) - 1;
        for (int side = 0; side < 4; ++side) {
            const unsigned planesOfSide = sidePlanes << (side * frustum.planesPerSide);
            if ((both & planesOfSide) == planesOfSide) return true;
        }
        if (!frustum.testNearFar) return false;
        auto beyond = [&box](const Plane& pl) {
            return pl.distance(nVertex(box.bounds0, pl.n)) > 0 &&
                   pl.distance(nVertex(box.bounds1, pl.n)) > 0;
        };
        return beyond(frustum.nearPlane) || beyond(frustum.farPlane);
    }
};

// Time refinement at every level with a test's node tests: the times (those of the parent,
// narrowed) decide and count; the spatial test only says whether a rejection was in space.
template <typename Test>
bool refineNode(const Test& test, int node, TimeRange& times, bool& spatial, RasterWork& work) {
    if constexpr (requires { test.refine(node, times, spatial, work); }) {
        return test.refine(node, times, spatial, work);
    } else {
        RasterWork uncounted;
        spatial = test.overlaps(node, true, uncounted);
        return test.leafTimes(node, times, work);
    }
}

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
TileTraversal walk(const PatchHierarchy& h, Test&& test, bool motion, TimeRefinement refinement,
                   RasterWork& work) {
    const bool atLeaves = motion && refinement != TimeRefinement::Off;
    const bool everyLevel = motion && refinement == TimeRefinement::EveryLevel;
    TileTraversal result;
    test.startAtRoot(work);
    ++work.frustumNodeVisits;
    // Whether a node overlapped in space but never in time (the tile is then rejected by time).
    bool onlyByTime = false;
    // A node's test: in space only, or (every level) its times narrowed from its parent's.
    auto visit = [&](int node, TimeRange& times) {
        if (!everyLevel) return test.overlaps(node, motion, work);
        bool spatial;
        const bool in = refineNode(test, node, times, spatial, work);
        onlyByTime = onlyByTime || (spatial && !in);
        return in;
    };
    TimeRange rootTimes = TimeRange::shutter();
    if (visit(0, rootTimes)) {
        result.times = TimeRange::empty();
        // Nodes and their times in separate arrays: a pop then loads what one push stored (a
        // 12-byte entry's loads straddled its stores, which defeats store-to-load forwarding).
        // A child is written above the top either way and kept by moving the top, no branch. The
        // stack holds at most one waiting sibling per level, the two children and one spare.
        int stackNodes[kMaxHierarchyDepth + 2];
        TimeRange stackTimes[kMaxHierarchyDepth + 2];
        int top = 0;
        stackNodes[top] = 0;
        stackTimes[top++] = rootTimes;
        while (top > 0) {
            --top;
            const int node = stackNodes[top];
            const TimeRange times = stackTimes[top];
            if (h.isLeaf(node)) {
                TimeRange leafTimes = times;
                if (atLeaves && !everyLevel) {
                    onlyByTime = true;  // the leaf overlaps in space
                    if (!test.leafTimes(node, leafTimes, work)) continue;
                }
                const int leaf = node - PatchHierarchy::firstLeaf(h.depth());
                result.leafMask |= std::uint64_t(1) << leaf;
                result.leafTimes[std::size_t(leaf)] = leafTimes;
                result.times.extend(leafTimes);
                if (result.firstSplitNode < 0) result.firstSplitNode = node;
                continue;
            }
            const int left = 2 * node + 1, right = 2 * node + 2;
            work.frustumNodeVisits += 2;
            TimeRange leftTimes = times, rightTimes = times;
            const bool inLeft = visit(left, leftTimes);
            const bool inRight = visit(right, rightTimes);
            if (inLeft && inRight && result.firstSplitNode < 0) result.firstSplitNode = node;
            stackNodes[top] = right;
            stackTimes[top] = rightTimes;
            top += inRight;
            stackNodes[top] = left;
            stackTimes[top] = leftTimes;
            top += inLeft;
        }
    }
    if (result.leafMask == 0) {
        ++(onlyByTime ? work.tilesRejectedTime : work.tilesRejectedSpace);
        return result;
    }
    result.overlaps = true;
    if (!motion) result.times = TimeRange::shutter();
    return result;
}

TileTraversal TraverseImpl(const PatchHierarchy& h, const SpaceNodes& nodes, const TileBounds& t,
                           bool motion, TimeRefinement refineTime, RasterWork& work) {
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
    const TileFrustum frustum = makeTileFrustum(*t.camera, t.lens, t.tile, t.farDepth);
    if (t.planeFormat != NumberFormat::fp32())
        return walk(h, RoundedCameraSpaceTest{h, frustum, RoundedArithmetic(t.planeFormat)}, motion,
                    refineTime, work);
    return walk(h, CameraSpaceLanes(h, frustum), motion, refineTime, work);
}

TileTraversal TraverseFrustumImpl(const PatchHierarchy& h, const TileFrustum& frustum, bool motion,
                                  TimeRefinement refineTime, bool vectorTest, RasterWork& work) {
    if (vectorTest) return walk(h, CameraSpaceLanes(h, frustum), motion, refineTime, work);
    return walk(h, CameraSpaceTest{h, frustum}, motion, refineTime, work);
}

}  // namespace HWY_NAMESPACE
}  // namespace patchsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace patchsim {

HWY_EXPORT(TraverseImpl);
HWY_EXPORT(TraverseFrustumImpl);

void SpaceNodes::build(const PatchHierarchy& h, BoundsSpace s, const Camera& camera,
                       const LensModel& lens, RasterWork& work, const NumberFormat& screenFormat) {
    space = s;
    homogeneous.clear();
    screen.clear();
    if (s == BoundsSpace::Camera3D) return;
    for (int i = 0; i < h.nodeCount(); ++i) {
        if (s == BoundsSpace::Homogeneous2D)
            homogeneous.push_back(toHomogeneous(h.node(i)));
        else
            screen.push_back(storedIn(projectMovingBox(h.node(i), camera, lens), screenFormat,
                                      /*outward=*/true, camera));
    }
    work.nodesConverted += h.nodeCount();
}

TimeRefinement timeRefinementOf(const RasterizerOptions& o) {
    if (!o.timeRefinement) return TimeRefinement::Off;
    return o.interiorTimeRefinement ? TimeRefinement::EveryLevel : TimeRefinement::Leaves;
}

TileTraversal traverseTile(const PatchHierarchy& h, const SpaceNodes& nodes, const TileBounds& t,
                           bool motion, TimeRefinement refineTime, RasterWork& work) {
    return HWY_DYNAMIC_DISPATCH(TraverseImpl)(h, nodes, t, motion, refineTime, work);
}

TileTraversal traverseTile(const PatchHierarchy& h, TileFrustum frustum, bool motion,
                           TimeRefinement refineTime, RasterWork& work) {
    return HWY_DYNAMIC_DISPATCH(TraverseFrustumImpl)(h, frustum, motion, refineTime, true, work);
}

TileTraversal traverseTileScalar(const PatchHierarchy& h, TileFrustum frustum, bool motion,
                                 TimeRefinement refineTime, RasterWork& work) {
    return HWY_DYNAMIC_DISPATCH(TraverseFrustumImpl)(h, frustum, motion, refineTime, false, work);
}

}  // namespace patchsim
#endif
