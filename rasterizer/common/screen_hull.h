#pragma once
// The convex hull, on the z = -1 screen plane, of a moving primitive over a span of the shutter and
// the whole lens: the bound McGuire et al. (2010) rasterize for a moving, defocused triangle.
//
// Why it holds the primitive: a point of the primitive at time t is a convex combination of its
// vertices at t, and each vertex moves on a segment, so the point is a convex combination of the
// vertices at the span's two ends. Seen from one lens point, projection maps a convex combination
// of points in front of the lens to a convex combination of their images. And a point's image
// from lens point l is its pinhole image plus l (1/F - 1/depth). The project's lens tests bound
// the square [-R, R]^2 that holds the lens disk (as the verifier's exact truth does), so each
// point's images fill the square of half-side R |1/F - 1/depth| around its pinhole image: its
// circle of confusion's square. Every image of the primitive, at any time of the span and from
// any lens point, lies in the hull of those squares; the hull is pushed out by `margin` so
// rounding never loses a sample on its edge.
//
// Representation
// --------------
// Points in double (the inputs are floats; double keeps the hull's own rounding far below the
// margin), at most kMaxPoints of them (eight corners of a box at both ends, four square corners
// each), in
// fixed arrays: a hull is built per triangle in the baselines' hot loop, which allocates nothing.
// The built hull is its counter-clockwise vertices and one outward edge line per side
// (n . p <= c inside), already moved out by the margin.

#include <array>

#include "core/camera.h"
#include "core/math.h"

namespace patchsim {

class ScreenHull {
  public:
    static constexpr int kMaxPoints = 64;
    static constexpr int kPointsPerBlurredPoint = 4;

    // A point seen through the whole lens: its pinhole image (x, y) and the half-side `spread` of
    // the square its images fill (R |1/F - 1/depth|; 0: the point alone). False when the hull is
    // full or a number is not finite (then `build` fails too).
    bool addBlurredPoint(double x, double y, double spread);
    // The hull of the points added, widened by `margin` (screen units): each edge moved out by it,
    // so `contains` and `overlapsRect` test the mitred offset polygon. False when it has no area
    // (fewer than three corners) or a point was refused: the caller keeps a box for such a
    // primitive.
    bool build(double margin);
    // Instead of the hull, the rectangle of least area that holds it (any orientation), widened
    // by `margin` the same way: the oriented box a rasterizer may bound the primitive by. Its
    // corners are rounded in double, some 1e-16 of the screen's extent, far below the margin.
    bool buildOrientedBox(double margin);

    bool contains(Vec2 p) const;
    // Separating axes: the rectangle's two and each hull edge's normal.
    bool overlapsRect(double x0, double y0, double x1, double y1) const;

    // The x extent of the hull's points with y in [ya, yb], the strip and the extent each widened
    // by the margin (which holds every point within the margin of the hull, if not the mitred
    // polygon's sharpest tips): where a rasterizer walking the hull row by row visits. False when
    // the strip misses the hull.
    bool xRangeInStrip(double ya, double yb, double& xa, double& xb) const;

    int cornerCount() const { return corners_; }
    double area() const;  // before the margin (for reports and tests)
    double lower(int axis) const { return lo_[axis]; }
    double upper(int axis) const { return hi_[axis]; }

  private:
    bool chain();  // the hull's corners into hull_ (counter-clockwise); false without area
    void setEdges(double margin);
    struct Point {
        double x, y;
    };
    struct EdgeLine {
        double nx, ny, c;  // inside: nx x + ny y <= c
    };
    // Filled before they are read (count_, corners_), so left uninitialised: a hull is made per
    // triangle.
    std::array<Point, kMaxPoints> points_;
    std::array<Point, kMaxPoints + 1> hull_;  // the chain repeats its first point at the end
    std::array<EdgeLine, kMaxPoints> edges_;
    int count_ = 0, corners_ = 0;
    bool refused_ = false;
    double margin_ = 0;
    double lo_[2] = {0, 0}, hi_[2] = {0, 0};  // bounds, with the margin
};

// Screen-plane (z = -1) units per pixel (the larger of its width and height).
double screenUnitsPerPixel(const Camera& camera);

}  // namespace patchsim
