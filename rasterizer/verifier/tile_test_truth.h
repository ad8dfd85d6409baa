#pragma once
// Ground truth for tile tests (docs/TILE_TESTS.md): when does a linearly moving box meet a rays
// through a tile?
//
// Representation
// --------------
// The rays of a tile from a rectangle of the lens (a pinhole is the rectangle [0,0]x[0,0]) fill,
// between the near and far planes, a solid whose cross-section at every depth d is an
// axis-aligned rectangle: from lens point l through focal-plane point F s, the ray is at
// (1 - d/F) l + d s. Its bounds are linear in d on each side of the focal plane, so the solid is
// one convex polytope (pinhole, or all of it on one side of focus) or two (split at depth F), each
// with eight vertices. The box blended to time t is an axis-aligned box whose every face moves
// linearly in t. By the separating axis theorem, two convex polytopes are disjoint if and only if
// they are separated along a face normal of either or a cross product of an edge of each. Along a
// fixed axis the polytope's extent is constant and the box's extent is linear in t, so "not
// separated along this axis" is an interval of t, and the times the two overlap are the
// intersection of these intervals over all axes: an exact interval, computed in double precision.
//
// The lens is a disk, but the rasterizer's lens tests and the dual-space bounds bound the square
// [-R, R]^2 that holds it, so the exact truth is taken for the square: a hit through the disk is a
// hit through the square. A sampled witness (rays through a grid of tile points, disk lens points
// and times) checks the exact truth from the other side: every sampled hit must lie inside it.

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/lbbox.h"
#include "core/ray.h"
#include "core/time_range.h"
#include "rasterizer/common/tile_grid.h"

namespace patchsim {

// A rectangle of the lens in units of its radius: [-1, 1]^2 is the whole (square) lens.
struct LensRect {
    float u0 = -1, u1 = 1, v0 = -1, v1 = 1;
    static constexpr LensRect whole() { return {}; }
    bool contains(Vec2 l) const { return l.x >= u0 && l.x <= u1 && l.y >= v0 && l.y <= v1; }
    bool isEmpty() const { return !(u0 <= u1) || !(v0 <= v1); }
};

struct TileTruth {
    bool hit = false;
    TimeRange times = TimeRange::empty();  // hull of the times some ray meets the box
};

// Exact: rays through `tile` (raster pixels, closed) from `lensPart` of the square lens (ignored
// for a pinhole), between the camera's near and far planes, against `box` over the shutter.
TileTruth exactTileTruth(const Camera& camera, const LensModel& lens, const TileRect& tile,
                         const LBBox& box, const LensRect& lensPart = LensRect::whole());

struct WitnessHit {
    float time;
    Vec2 lens;  // unit disk, as the rasterizer maps lens samples
};

// Sampled: rays through a screenSteps^2 grid on the tile (edges included), a lensSteps^2 grid
// over the lens (mapped onto the disk, extremes included), at timeSteps times (0 and 1 included);
// every hit, tested exactly against the box blended to its time.
std::vector<WitnessHit> sampledWitness(const Camera& camera, const LensModel& lens,
                                       const TileRect& tile, const LBBox& box, int screenSteps = 9,
                                       int lensSteps = 5, int timeSteps = 33);

}  // namespace patchsim
