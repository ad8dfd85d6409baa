#pragma once
// A 2D bounds-space node (projected_bounds.h's ScreenMovingBox) stored in a narrower number
// format: issue 35's screen-bounds site, rasterizer.screen_bounds_format in the render and
// `patent-2d-time-F` in the verifier.
//
// Outward, the lower corners round down and the upper corners up, the depth ratios' range widens
// and the near depths come nearer. The stored box then holds the fp32 box at every blend of its
// two ends, and the 2D tile test is monotone in the box, so whatever it accepts for the fp32 box
// it accepts for the stored one: no false reject, only more accepts. A float format rounds the
// z = -1 plane coordinates as they are; fixed point stores pixels, as D3D11's 16.8 snap does
// (x from the left, y from the top), and keeps the depths in float, as a fixed-point screen
// datapath keeps z separately. Each step to pixels and back is in double, widened by its own
// error bound in the rounding's direction, and so is the float result, so outward stays outward;
// a pixel beyond the format's range keeps its float value, as a rasterizer clips at its guard
// band. With Rounding::Nearest, the naive variant, a box may shrink and reject falsely: kept for
// the verifier to show what the outward rounding prevents.

#include "core/camera.h"
#include "core/number_format.h"
#include "rasterizer/patent/projected_bounds.h"

namespace patchsim {

// `box` stored in `format`: outward (`outward` true) or to nearest. fp32 returns it unchanged.
ScreenMovingBox storedIn(const ScreenMovingBox& box, const NumberFormat& format, bool outward,
                         const Camera& camera);

}  // namespace patchsim
