#pragma once
// The ray against a moving box (moving_box_ray.h) computed in a narrower number format (issue 35's
// ray-test site, rasterizer.ray_box_format): the box's corners and the ray's per-axis terms A, B
// and C enter the format, and each slab distance x0 A + x1 B + C is evaluated in its arithmetic,
// with a running error bound (core/rounded_arithmetic.h).
//
// The test stays conservative by widening: each slab distance is known to lie between its
// certain lower and upper bounds, so the ray's entry (a maximum of minima) lies between the same
// maxima and minima of those bounds, and so does its exit. The test accepts when the lowest
// possible entry is no further than the highest possible exit plus the fp32 test's slack taken at the
// largest magnitudes either could have: whatever the fp32 test accepts in exact arithmetic, this
// accepts. An axis whose distances leave the format's range adds no constraint; an axis the ray
// runs parallel to is decided as in fp32 (no arithmetic beyond a blend).
//
// Naive, the same datapath compares the rounded distances as fp32 compares its own: kept for the
// tests to show what the bound prevents.

#include "core/rounded_arithmetic.h"
#include "rasterizer/patent/moving_box_ray.h"
#include "rasterizer/patent/tile_frustum_rounded.h"

namespace patchsim {

bool hitsMovingBoxRounded(const SlabRay& ray, const LBBox& box, const RoundedArithmetic& arithmetic,
                          PlaneErrorHandling handling);

}  // namespace patchsim
