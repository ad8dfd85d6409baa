#include "rasterizer/patent/tile_frustum.h"

#include <algorithm>
#include <cmath>

#include "rasterizer/common/conservative_margins.h"

namespace patchsim {

namespace {

// Outside when s-coordinate < edge (sign = -1, left/bottom) or > edge (sign = +1, right/top),
// for rays leaving the lens at offset `lensOffset` along that axis.
Plane sidePlane(int axis, float sign, float edge, float lensOffset, float focus) {
    // Point p is seen at screen coordinate s = (p_a - o (1 + p_z / F)) / (-p_z) along axis a.
    // Outside (sign * (s - edge) > 0), multiplied by -p_z > 0:
    //   sign * (p_a - o - o p_z / F + edge p_z) > 0.
    Plane pl;
    pl.n[axis] = sign;
    pl.n.z = sign * (edge - (focus > 0 ? lensOffset / focus : 0.0f));
    pl.d = -sign * lensOffset;
    return pl;
}

bool outsideAtBothEnds(const Plane& pl, const LBBox& box, bool motion, RasterWork& work) {
    ++work.planeTests;
    if (!(pl.distance(nVertex(box.bounds0, pl.n)) > 0)) return false;
    if (!motion) return true;
    ++work.planeTests;
    return pl.distance(nVertex(box.bounds1, pl.n)) > 0;
}

// The times the n-vertex is inside the plane; false if never.
bool insideInterval(const Plane& pl, const LBBox& box, TimeRange& inside, RasterWork& work) {
    work.planeTests += 2;
    const float d0 = pl.distance(nVertex(box.bounds0, pl.n));
    const float d1 = pl.distance(nVertex(box.bounds1, pl.n));
    inside = TimeRange::shutter();
    if (d0 > 0 && d1 > 0) return false;
    if (d0 > 0) {  // moves from outside to inside
        ++work.timeIntervals;
        inside.lower = std::max(0.0f, d0 / (d0 - d1) - kTimeGuard);
    } else if (d1 > 0) {  // moves from inside to outside
        ++work.timeIntervals;
        inside.upper = std::min(1.0f, d0 / (d0 - d1) + kTimeGuard);
    }
    return true;
}

}  // namespace

TileFrustum makeTileFrustum(const Camera& camera, const LensModel& lens, const TileRect& tile,
                            float farDepth) {
    TileFrustum f;
    const Vec2 lo = rasterToScreen(
        camera, {float(tile.x0) - kTileGuardPixels, float(tile.y1) + kTileGuardPixels});
    const Vec2 hi = rasterToScreen(
        camera, {float(tile.x1) + kTileGuardPixels, float(tile.y0) - kTileGuardPixels});
    const float edges[4] = {lo.x, hi.x, lo.y, hi.y};
    const float signs[4] = {-1, 1, -1, 1};
    const float focus = lens.radius > 0 ? lens.focusDistance : 0.0f;
    f.planesPerSide = lens.radius > 0 ? 2 : 1;
    for (int side = 0; side < 4; ++side) {
        const int axis = side / 2;
        if (lens.radius > 0) {
            f.sides[side][0] = sidePlane(axis, signs[side], edges[side], -lens.radius, focus);
            f.sides[side][1] = sidePlane(axis, signs[side], edges[side], lens.radius, focus);
        } else {
            f.sides[side][0] = sidePlane(axis, signs[side], edges[side], 0.0f, 0.0f);
        }
    }
    // Depth is -z: outside the near plane when -z < near, beyond the far plane when -z > far.
    f.nearPlane = {Vec3(0, 0, 1), camera.nearPlane()};
    f.farPlane = {Vec3(0, 0, -1), -farDepth};
    return f;
}

bool overlapsFrustum(const TileFrustum& f, const LBBox& box, bool motion, RasterWork& work) {
    if (box.empty()) return false;
    for (int side = 0; side < 4; ++side) {
        bool outside = true;
        for (int k = 0; k < f.planesPerSide && outside; ++k)
            outside = outsideAtBothEnds(f.sides[side][k], box, motion, work);
        if (outside) return false;
    }
    return !(f.testNearFar && outsideNearOrFar(f, box, motion, work));
}

bool outsideNearOrFar(const TileFrustum& f, const LBBox& box, bool motion, RasterWork& work) {
    return outsideAtBothEnds(f.nearPlane, box, motion, work) ||
           outsideAtBothEnds(f.farPlane, box, motion, work);
}

namespace {

// Narrows `times` to when the box may be inside some of `planes` (for some lens position along a
// side when inside either extreme plane: the union of the two intervals, bounded by their hull).
bool narrow(const Plane* planes, int count, const LBBox& box, TimeRange& times, RasterWork& work) {
    TimeRange side = TimeRange::empty();
    for (int k = 0; k < count; ++k) {
        TimeRange inside;
        if (insideInterval(planes[k], box, inside, work)) side.extend(inside);
    }
    times.intersect(side);
    return !times.isEmpty();
}

}  // namespace

bool leafTimeInterval(const TileFrustum& f, const LBBox& box, TimeRange& times, RasterWork& work) {
    if (box.empty()) return false;
    for (int side = 0; side < 4; ++side)
        if (!narrow(f.sides[side], f.planesPerSide, box, times, work)) return false;
    return !f.testNearFar || narrowToNearFar(f, box, times, work);
}

bool narrowToNearFar(const TileFrustum& f, const LBBox& box, TimeRange& times, RasterWork& work) {
    return narrow(&f.nearPlane, 1, box, times, work) && narrow(&f.farPlane, 1, box, times, work);
}

bool insideNearFar(const TileFrustum& f, const LBBox& box, RasterWork& work) {
    work.planeTests += 4;
    for (const Plane* pl : {&f.nearPlane, &f.farPlane}) {
        if (pl->distance(pVertex(box.bounds0, pl->n)) > 0) return false;
        if (pl->distance(pVertex(box.bounds1, pl->n)) > 0) return false;
    }
    return true;
}

}  // namespace patchsim
