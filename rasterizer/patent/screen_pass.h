#pragma once
// A static frame rasterized as a static frame (Effects::screenPlaneSamples: no motion, no lens).
// A sample is then a point in the screen plane, and the branch node's per-sample rays (step 7 of
// US 8,791,945, ray_stream.h) would only redo a 2D coverage test at the cost of a ray descent.
// Steps 1 to 5 stay as they are: the group's hierarchy, its screen bounds, the tile tests and
// the leaves that overlap the tile (at t = 0 and t = 1, which are one time here). For each such
// leaf, each triangle is set up once per tile as fixed-point edge functions
// (rasterizer/common/screen_triangle.h: D3D11's 8 sub-pixel bits and top-left rule), clipped to
// its pixels within the tile, and each of those pixels' samples is tested with the three edge
// functions, a SIMD vector of samples at a time.
//
// The test is exact (integers held in doubles), so the vector kernel, the scalar test and the
// reference method, which uses the scalar test in static frames, agree sample for sample. A
// triangle with no fixed-point screen form (a vertex at or behind the eye, or beyond the guard
// band) is tested with the tile's rays, as the reference tests it.
//
// Work: `RS/Screen triangle setups` and `RS/Edge tests`; no ray, box test or time interval is
// counted unless such a triangle takes rays.
//
// A defocus-only frame (Effects::lensPlaneSamples: a lens, nothing moving) is rasterized the same
// way with the lens edge test (rasterizer/common/lens_triangle.h, after Laine and Karras 2011): a
// sample is a point (x, y, u, v), each triangle of an overlapping leaf is set up once per tile
// from its leaf's projected vertices, and the samples of the pixels it can cover from some point
// of the lens are tested, 16 floats at a time, with the three edge functions of the triangle seen
// from each sample's lens point. Work: `RS/Lens triangle setups` and `RS/Lens edge tests`.

#include "core/camera.h"
#include "rasterizer/patent/ray_stream.h"

namespace patchsim {

// Tests the pass's overlapping leaves' triangles against the tile's samples; nearer opaque hits
// are kept in `rays` (a transparent mesh offers every hit to its layers), counts go to `work`.
// `rays` must be of a screen-plane frame (TileRayFrame::screenPlane).
void rasterizeScreenPass(TileRays& rays, const StreamPass& pass, const Camera& camera,
                         RasterWork& work);
// The same for a defocus-only frame (TileRayFrame::lensPlane), with the pass's lens vertices.
void rasterizeLensPass(TileRays& rays, const StreamPass& pass, const Camera& camera,
                       const LensModel& lens, RasterWork& work);

}  // namespace patchsim
