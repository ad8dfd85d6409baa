#pragma once
// A static triangle seen through a pinhole, tested the way a conventional rasterizer tests it:
// edge functions at the sample's screen position, in fixed point, with a tie rule. Every
// visibility method uses it for a static frame (no motion, no lens), where a sample is a point
// in the screen plane and a ray would only redo this test at higher cost.
//
// Representation
// --------------
// Positions are in sub-pixels: raster coordinates (pixels, y down) times 2^kSubpixelBits, rounded
// to integers (ties to even), as D3D11 snaps vertices to 16.8 fixed point with 8 sub-pixel bits.
// The sample positions are snapped to the same grid, each inside its pixel (sampleSubpixel; films
// are at most 16384 pixels wide and high, so a sample's coordinate is below 2^22 and exact in
// float). The integers are held in doubles, where every quantity below is exact: vertex
// coordinates lie within the guard band (|x| < 2^23 sub-pixels, D3D11's 16 integer bits, which
// holds every film), so an edge function A (x - xa) +
// B (y - ya) has factors below 2^24, products below 2^48 and a sum below 2^49, and twice the
// triangle's area below 2^51 (a double holds integers to 2^53). Exact edge functions make the test
// independent of evaluation order, so the scalar test here and the vector ones in the rasterizers
// agree bit for bit. A small triangle (kSmallExtent) has them exact in float as well, where a
// vector holds twice the samples.
//
// Edge i is the one opposite vertex i; its function is scaled so the triangle's inside is
// positive (a triangle seen from behind is flipped: both faces count, as in the ray test). A
// sample exactly on an edge (E_i = 0) is inside only when the edge owns it: D3D11's top-left rule,
// in raster coordinates with y down a left edge has A > 0 (inside lies to its right) and a top
// edge A = 0, B > 0 (inside lies below). The rule is antisymmetric in (A, B), and a neighbour
// sharing the edge sees it as (-A, -B), so a sample on a shared edge or vertex belongs to exactly
// one of the triangles around it: no crack, no double hit.
//
// Depth and the barycentrics are perspective correct: with screen-space weights E_i / area and
// camera depths w_i, the hit's depth is area / S and vertex i's weight (E_i / w_i) / S, where
// S = E_0 / w_0 + E_1 / w_1 + E_2 / w_2, summed in that order; each is a product with 1 / S. They
// are computed in float from the edge functions rounded to float (exact for a small triangle),
// the same operations in every test.
//
// A triangle with a vertex at or behind the eye (w <= 0) or projected outside the guard band has
// no fixed-point screen form: it is tested with rays (`needsRay`), as a conventional pipeline
// clips it first. A hit's depth must lie in [near, depthMax], as a ray's parameter must.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/camera.h"
#include "core/math.h"

namespace patchsim {

inline constexpr int kSubpixelBits = 8;
inline constexpr double kSubpixelsPerPixel = double(1 << kSubpixelBits);
// Vertices beyond this many pixels from the raster origin take the ray test.
inline constexpr double kGuardBandPixels = 32767.0;

// x rounded to an integer, ties to even, for |x| < 2^51: adding 1.5 * 2^52 leaves no fraction
// bits (two adds, where std::round is a library call).
inline double roundToInteger(double x) {
    constexpr double kShift = 6755399441055744.0;  // 1.5 * 2^52
    return (x + kShift) - kShift;
}

// The sub-pixel coordinate of a sample at `offset` in [0, 1) into pixel `pixel`: on the grid of
// the pixel's 256 positions [0, 255] (an offset that rounds up to the next pixel's edge stays
// at 255), so a pixel's samples never leave it.
inline double sampleSubpixel(int pixel, float offset) {
    return double(pixel) * kSubpixelsPerPixel +
           std::min(roundToInteger(double(offset) * kSubpixelsPerPixel), kSubpixelsPerPixel - 1.0);
}

struct ScreenTriangle {
    enum class Kind : std::uint8_t { Covers, Empty, NeedsRay };
    Kind kind = Kind::Empty;
    // Edge i: E_i(x, y) = a[i] (x - x0[i]) + b[i] (y - y0[i]), inside positive.
    double a[3], b[3], x0[3], y0[3];
    bool ownsTies[3];
    // The sub-pixel box spans at most kSmallExtent on both axes: every quantity of the edge
    // functions over the samples of its pixels is then below 2^24, exact in float too.
    bool small;
    float inverseDepth[3];  // 1 / w_i, rounded to float
    float area;             // E_i(vertex i) > 0, rounded to float
    // The pixels whose samples it can cover: [pixelX0, pixelX1) x [pixelY0, pixelY1), those
    // its sub-pixel box reaches.
    int pixelX0, pixelX1, pixelY0, pixelY1;
};

// 2^11 sub-pixels (8 pixels): samples of the box's pixels lie within 2^11 + 2^9 < 2^12 of every
// vertex, so each product of an edge function is below 2^23 and their sum below 2^24.
inline constexpr double kSmallExtent = 2048.0;

// A camera-space vertex projected and snapped, once for every triangle that shares it.
struct ScreenVertex {
    double x = 0, y = 0;     // sub-pixels, integers
    float inverseDepth = 0;  // 1 / w
    bool valid = false;      // in front of the eye and within the guard band
};
ScreenVertex projectToScreen(const Camera& camera, const Vec3& p);

// The triangle of three projected vertices.
ScreenTriangle setupScreenTriangle(const Camera& camera, const ScreenVertex& a,
                                   const ScreenVertex& b, const ScreenVertex& c);
// Projects and snaps the camera-space triangle (a, b, c).
inline ScreenTriangle setupScreenTriangle(const Camera& camera, const Vec3& a, const Vec3& b,
                                          const Vec3& c) {
    return setupScreenTriangle(camera, projectToScreen(camera, a), projectToScreen(camera, b),
                               projectToScreen(camera, c));
}

struct ScreenHit {
    float depth, b1, b2;
};

// The hit at a covered sample from its three edge functions (as floats; exact, or rounded once
// from the exact double): perspective-correct depth and barycentrics, in float.
inline ScreenHit interpolateScreenHit(const ScreenTriangle& t, float e0, float e1, float e2) {
    const float w0 = e0 * t.inverseDepth[0], w1 = e1 * t.inverseDepth[1],
                w2 = e2 * t.inverseDepth[2];
    const float inverseSum = 1.0f / ((w0 + w1) + w2);
    return {t.area * inverseSum, w1 * inverseSum, w2 * inverseSum};
}

// Whether the triangle covers the sample at sub-pixel (x, y), with a depth in
// [nearPlane, depthMax] (both inclusive). The triangle must be of kind Covers.
inline bool coverSample(const ScreenTriangle& t, double x, double y, float nearPlane,
                        float depthMax, ScreenHit& hit) {
    double e[3];
    for (int i = 0; i < 3; ++i) {
        e[i] = t.a[i] * (x - t.x0[i]) + t.b[i] * (y - t.y0[i]);
        if (e[i] < 0.0 || (e[i] == 0.0 && !t.ownsTies[i])) return false;
    }
    const ScreenHit h = interpolateScreenHit(t, float(e[0]), float(e[1]), float(e[2]));
    if (!(h.depth >= nearPlane && h.depth <= depthMax)) return false;
    hit = h;
    return true;
}

}  // namespace patchsim
