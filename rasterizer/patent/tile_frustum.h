#pragma once
// Tile frustum tests against moving boxes (US 8,791,945), in camera space.
//
// Representation
// --------------
// A plane is (n, d); a point p is outside when n.p + d > 0. Planes need not be normalised. A tile
// has four sides; with a pinhole each side is one plane through the eye and the tile edge. With
// a thin lens of radius R focused at F, the rays through a side are bounded by two planes, each
// through one lens extreme and the tile edge on the focal plane; a box is outside that side only
// when it is outside both. Near and far planes complete the frustum (the far plane may come from
// the z-buffer).
//
// A moving box is outside a plane when its n-vertex (the corner minimising n.p) is outside at
// t=0 and at t=1; since the n-vertex moves linearly, the plane distance d(t) is linear and the
// crossing time is d0 / (d0 - d1). Leaves narrow [tmin, tmax] with it and reject when it empties.

#include <cstdint>

#include "core/camera.h"
#include "core/lbbox.h"
#include "core/ray.h"
#include "core/time_range.h"
#include "rasterizer/common/tile_grid.h"
#include "rasterizer/patent/raster_work.h"

namespace patchsim {

struct Plane {
    Vec3 n{0};
    float d = 0;
    float distance(const Vec3& p) const { return glm::dot(n, p) + d; }
};

struct TileFrustum {
    Plane sides[4][2];      // left, right, bottom, top; [k][1] used with defocus
    int planesPerSide = 1;  // 1 pinhole, 2 thin lens
    Plane nearPlane, farPlane;
    bool testNearFar = true;
};

// `farDepth` is the far plane's depth (the camera's, or the tile's z-buffer maximum).
TileFrustum makeTileFrustum(const Camera& camera, const LensModel& lens, const TileRect& tile,
                            float farDepth);

// The corner of `box` that minimises n.p (the n-vertex).
inline Vec3 nVertex(const Box3& box, const Vec3& n) {
    return {n.x > 0 ? box.lower.x : box.upper.x, n.y > 0 ? box.lower.y : box.upper.y,
            n.z > 0 ? box.lower.z : box.upper.z};
}
inline Vec3 pVertex(const Box3& box, const Vec3& n) {
    return {n.x > 0 ? box.upper.x : box.lower.x, n.y > 0 ? box.upper.y : box.lower.y,
            n.z > 0 ? box.upper.z : box.lower.z};
}

// Tests count into `work.planeTests` (one box vertex against one plane at one time) and
// `work.timeIntervals` (leaf plane crossings computed).

// True unless the moving box is certainly outside the frustum at every time. `motion` false
// tests the t=0 box only.
bool overlapsFrustum(const TileFrustum& f, const LBBox& box, bool motion, RasterWork& work);

// The leaf test with time refinement: narrows `times` (start with the whole shutter) to the times
// the moving box can be inside; false when outside at all times.
bool leafTimeInterval(const TileFrustum& f, const LBBox& box, TimeRange& times, RasterWork& work);

// The near and far planes' parts of the two tests above (for walks that test the sides their own
// way): outside either at both ends; times narrowed to inside both.
bool outsideNearOrFar(const TileFrustum& f, const LBBox& box, bool motion, RasterWork& work);
bool narrowToNearFar(const TileFrustum& f, const LBBox& box, TimeRange& times, RasterWork& work);

// True when the whole moving box is inside the near and far planes at t=0 and t=1 (p-vertex
// test): then only the four sides need testing.
bool insideNearFar(const TileFrustum& f, const LBBox& box, RasterWork& work);

}  // namespace patchsim
