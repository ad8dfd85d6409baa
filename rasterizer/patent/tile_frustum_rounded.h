#pragma once
// The leaf test with time refinement (tile_frustum.h, leafTimeInterval) computed in a narrower
// number format (issue 35's tile-plane and leaf-time-interval sites): every plane distance
// n . p + d is evaluated in the format's arithmetic, each operation rounded to nearest, and so is
// each crossing time d0 / (d0 - d1).
//
// Bounded, the test stays conservative by running error analysis (core/rounded_arithmetic.h):
// each distance carries a bound on its distance from the exact one, and the test uses the
// largest value of the format certainly below the exact distance, at t = 0 and at t = 1. The
// distance is linear in time, so the line through those two lower bounds lies below the exact
// distance at every time, and the times it is not positive hold the times the box is inside the
// plane. The crossing time is then rounded outward (down for an entry, up for an exit, the time
// guard too). A distance out of the format's range (fixed point's saturation, a float format's
// overflow) gives the plane up: inside at every time. So whatever the exact fp32 planes accept,
// the bounded test accepts.
//
// Naive, the same datapath compares the rounded distances with zero and rounds every time to
// nearest: kept for the verifier to show what the bound prevents.

#include "core/rounded_arithmetic.h"
#include "rasterizer/patent/tile_frustum.h"

namespace patchsim {

enum class PlaneErrorHandling : std::uint8_t { Bounded, Naive };

// overlapsFrustum in the format: a side rejects only where every plane of it is certainly
// (bounded) or apparently (naive) positive at t = 0 and, with `motion`, at t = 1.
bool overlapsFrustumRounded(const TileFrustum& f, const LBBox& box,
                            const RoundedArithmetic& arithmetic, PlaneErrorHandling handling,
                            bool motion, RasterWork& work);

bool leafTimeIntervalRounded(const TileFrustum& f, const LBBox& box,
                             const RoundedArithmetic& arithmetic, PlaneErrorHandling handling,
                             TimeRange& times, RasterWork& work);

}  // namespace patchsim
