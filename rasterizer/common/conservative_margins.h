#pragma once
// Every rounding margin and limit of the rasterizer, in one place, with the reason for each.
//
// The patch rasterizer must never reject a sample that holds a hit (a false reject), whatever
// rounding the float tests make. Each test that could lose a sample to rounding is widened by a
// margin small against the scene but large against float error. The reference method and the
// tile-test verifier hold the rasterizer to this, sample for sample; changing a margin changes
// work counts, never which samples hit.

namespace patchsim {

// Screen bounds (pixels): projection of box corners rounds; a sample exactly on a patch's edge
// must stay inside its bounds.
inline constexpr float kScreenBoundsMarginPixels = 1.0f / 64.0f;

// Tile frusta (pixels): tiles are widened so plane tests cannot reject a sample that lies exactly
// on the tile's edge.
inline constexpr float kTileGuardPixels = 1.0f / 256.0f;

// Leaf time intervals (shutter time): crossing times d0 / (d0 - d1) are widened by this much.
inline constexpr float kTimeGuard = 1e-5f;

// Ray against moving box: the 12 multiply-adds round; entry may exceed exit by this relative
// slack (plus an absolute 1e-30) and still count as a hit, so flat boxes are never missed.
inline constexpr float kRayBoxRelativeSlack = 1e-5f;
inline constexpr float kRayBoxAbsoluteSlack = 1e-30f;

// A ray direction component this small is treated as parallel to that axis (decided by where the
// origin lies), so 0 x inf never enters the slab test.
inline constexpr float kParallelDirection = 1e-30f;

// Ray end from the z-buffer depth (relative): inclusive and slightly widened, so a hit at exactly
// the stored depth still reaches the (depth, patch, triangle) tie-break.
inline constexpr float kDepthTieWidening = 1e-6f;

// Transparent layers (relative depth): two fragments of one object this close are the same
// surface seen twice (a ray through an edge two triangles share); only one is kept.
inline constexpr float kSameSurfaceDepth = 1e-6f;

}  // namespace patchsim
