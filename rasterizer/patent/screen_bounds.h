#pragma once
// Conservative screen bounds of a moving, defocused patch (US 8,791,945, step 2).
//
// The corners of the boxes at one level of the hierarchy (the root, or deeper for tighter
// bounds), at t=0 and at t=1, are projected; each is widened by the radius of its circle of
// confusion, |R (1/depth - 1/F)| on the z = -1 plane, so every lens position is inside. Any corner
// in front of the near plane during the shutter has no finite projection: the bounds are then the
// whole screen, never NaN. The bounds are widened by a fraction of a pixel for projection rounding.

#include "core/camera.h"
#include "core/ray.h"
#include "rasterizer/common/tile_grid.h"
#include "rasterizer/patent/patch_hierarchy.h"
#include "rasterizer/patent/projected_bounds.h"

namespace patchsim {

struct ScreenBounds {
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // raster pixels (y down)
    bool fullScreen = false;               // a corner reached in front of the near plane
};

ScreenBounds screenBounds(const PatchHierarchy& hierarchy, int level, const Camera& camera,
                          const LensModel& lens);
// The same from the 2D bounds space's nodes (one per hierarchy node, already projected at t=0 and
// t=1 with their circles of confusion): the union of their rectangles at `level`.
ScreenBounds screenBounds(const PatchHierarchy& hierarchy, int level, const Camera& camera,
                          const std::vector<ScreenMovingBox>& screenNodes);

// The tiles the bounds touch (one pixel of slack right and below: samples reach the far edge of
// their pixel); empty when the bounds are off screen.
TileRange tilesCovering(const ScreenBounds& bounds, const TileGrid& grid);

}  // namespace patchsim
