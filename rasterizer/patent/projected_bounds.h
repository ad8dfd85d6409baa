#pragma once
// The patent's other two bounds spaces (US 8,791,945: "time-dependent 2D screen-space bounds"
// and "time-dependent 2D homogeneous bounds (2DH)"), beside the 3D camera-space boxes of
// tile_frustum. Each converts a node's moving box once per group and tests it against a tile.
//
// Representation
// --------------
// 2DH: the box in clip coordinates (X, Y, W) = (x, y, -z), an LBBox whose third axis is W. A tile
// side is a line through the eye in (X, W) or (Y, W): outside when a A + b W + c > 0, the n-vertex
// taking two coordinates. The projection here maps camera space to clip space by a diagonal
// matrix, so the 2DH box is the 3D box relabelled and the tests agree with the 3D ones; they part
// where boxes are oriented or the projection is not axis-aligned, which the patent allows.
//
// 2D: the box's projections on the z = -1 plane at t=0 and t=1 (each corner's circle of
// confusion added, for the square lens [-R, R]^2), and the range of its corners' depth ratios
// r = depth(t=1) / depth(t=0). A point moving linearly projects to a point moving linearly in
// tau = t r / (1 - t + t r), not in t; so at time t every corner lies in the screen rectangle
// blended to some tau in [tau(t, r_min), tau(t, r_max)]. A tile side bounds tau by a crossing of
// the blended rectangle, as the 3D test bounds t; tau converts back to t with
// t = tau / (r (1 - tau) + tau), taking r_max for the lower bound and r_min for the upper (tau is
// increasing in r). A box reaching in front of the near plane has no finite projection and is
// accepted at every time.

#include "core/camera.h"
#include "core/lbbox.h"
#include "core/ray.h"
#include "core/time_range.h"
#include "rasterizer/common/tile_grid.h"
#include "rasterizer/patent/raster_work.h"

namespace patchsim {

// ---- 2D homogeneous ----

// (x, y, z) camera space to (X, Y, W) = (x, y, -z).
LBBox toHomogeneous(const LBBox& cameraSpace);

struct HomogeneousLine {
    int axis = 0;               // 0: X, 1: Y, 2: W only (near and far)
    float a = 0, b = 0, c = 0;  // outside when a * coordinate + b * W + c > 0
};

struct HomogeneousFrustum {
    HomogeneousLine sides[4][2];  // left, right, bottom, top; [k][1] used with defocus
    int planesPerSide = 1;
    HomogeneousLine nearLine, farLine;
    bool testNearFar = true;
};

HomogeneousFrustum makeHomogeneousFrustum(const Camera& camera, const LensModel& lens,
                                          const TileRect& tile, float farDepth);
bool overlapsHomogeneous(const HomogeneousFrustum& f, const LBBox& clip, bool motion,
                         RasterWork& work);
bool homogeneousTimeInterval(const HomogeneousFrustum& f, const LBBox& clip, TimeRange& times,
                             RasterWork& work);
bool insideNearFarHomogeneous(const HomogeneousFrustum& f, const LBBox& clip, RasterWork& work);

// ---- 2D screen space ----

struct ScreenMovingBox {
    Vec2 lower0{0}, upper0{0}, lower1{0}, upper1{0};  // z = -1 plane, at t=0 and t=1
    float ratioMin = 1, ratioMax = 1;                 // depth(t=1) / depth(t=0) of its corners
    float nearDepth0 = 0, nearDepth1 = 0;             // its nearest depth at t=0 and t=1
    bool bounded = false;  // false: empty, or reaches in front of the near plane
    bool empty = true;
};

ScreenMovingBox projectMovingBox(const LBBox& cameraSpace, const Camera& camera,
                                 const LensModel& lens);

struct ScreenTile {
    float x0 = 0, x1 = 0, y0 = 0, y1 = 0;  // z = -1 plane, widened by the tile guard
    float farDepth = 0;
};

ScreenTile makeScreenTile(const Camera& camera, const TileRect& tile, float farDepth);

// False when the box is outside one side of the tile (or beyond the far plane) at both ends.
bool overlapsScreenTile(const ScreenTile& tile, const ScreenMovingBox& box, bool motion,
                        RasterWork& work);
// Narrows `times` to when the box may be seen in the tile; false when never.
bool screenTileTimes(const ScreenTile& tile, const ScreenMovingBox& box, TimeRange& times,
                     RasterWork& work);

}  // namespace patchsim
