#pragma once
// A static triangle seen through a thin lens, tested the way a stochastic rasterizer tests a
// defocus-only sample (Laine and Karras, HPG 2011, section 4): the sample is a point (x, y, u, v)
// of the screen and the lens, and the triangle's coverage of it is three edge functions of the
// triangle's vertices as seen from the lens point, without a ray. Every visibility method uses it
// in a defocus-only frame (a lens, nothing moving), as they use screen_triangle.h's fixed-point
// test in a static frame.
//
// Representation
// --------------
// Coordinates are the image plane z = -1 (camera space: x right, y up; rasterToScreen's). Seen
// from the lens point L (the ray's origin, radius times the disk sample, on the plane z = 0), a
// vertex P at depth w = -P.z projects through L onto the focus plane z = -F at F/w of the way, so
// scaled back to z = -1 its image is
//     q(L) = (P.x, P.y) / w + c L,   c = 1/F - 1/w
// (c is the vertex's signed circle of confusion per unit of lens offset: zero at the focus
// distance). A sample at screen position s is covered from L when s lies in the triangle of
// q_0(L), q_1(L), q_2(L). For the edge from vertex a to vertex b, with D = q_b - q_a, dc = c_b -
// c_a and R = s - q_a, the edge function cross(D + dc L, R - c_a L) expands with its L x L term
// vanishing:
//     E = R.x (-(D.y + dc L.y)) + R.y (D.x + dc L.x) + c_a (L.x D.y - L.y D.x),
// about five multiply-adds an edge (Laine and Karras count about 25 for the three edges with
// motion and defocus). The depth and barycentrics follow as in the static test: with the
// oriented edge functions F_i (vertex i's is the edge opposite it) and the vertices' 1/w,
// S = F_0/w_0 + F_1/w_1 + F_2/w_2, the hit's depth is (F_0 + F_1 + F_2) / S and vertex i's weight
// (F_i/w_i) / S, which is the ray test's hit (a central projection keeps 1/w linear).
//
// Watertight in float. An edge shared by two triangles is computed from the same two vertices in
// the same order in both: the order is canonical (the vertices' (x, y, c) compared), and a
// triangle that meets the edge the other way negates it (`flipped`), which is exact. A triangle
// seen from behind from some lens points is inside where every oriented F_i is negative, so the
// test is "all positive or all negative". A sample exactly on an edge (E = 0) is decided as if it
// were moved by (eps, eps^2) on the screen, D3D11's top-left rule in another form: E's sign is
// then that of dE/dx (the factor of R.x above), or if that is zero of dE/dy (R.y's). Both
// triangles on an edge compute the same canonical E and derivatives and read them with opposite
// signs, so a sample on a shared edge belongs to exactly one; and as the moved point lies on no
// edge, a sample exactly on a vertex's image belongs to exactly one triangle of a fan that does
// not fold over itself, from any lens point.
//
// Every operation is a separate IEEE float operation (the build sets -ffp-contract=off), so the
// scalar test here and the vector kernels in the rasterizers agree bit for bit, and the reference
// equals every method sample for sample.
//
// A vertex at or behind the lens plane (w <= 0), or a triangle whose image reaches beyond the
// guard band from some lens point, has no such form: it is tested with rays (`NeedsRay`), as a
// pipeline would clip it first. A hit's depth must lie in [near, depthMax], as a ray's must.

#include <cstdint>

#include "core/camera.h"
#include "core/math.h"
#include "core/ray.h"
#include "rasterizer/common/screen_triangle.h"

namespace patchsim {

// A camera-space vertex projected once for every triangle that shares it.
struct LensVertex {
    float x = 0, y = 0;      // P.x / w and P.y / w on the plane z = -1
    float blur = 0;          // c = 1/F - 1/w
    float inverseDepth = 0;  // 1 / w
    bool valid = false;      // in front of the lens plane, finite
};
LensVertex projectThroughLens(const LensModel& lens, const Vec3& p);

// Pixels [x0, x1) x [y0, y1).
struct LensPixels {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x0 >= x1 || y0 >= y1; }
};

struct LensTriangle {
    enum class Kind : std::uint8_t { Covers, Empty, NeedsRay };
    Kind kind = Kind::Empty;
    float x[3], y[3], blur[3];  // the vertices (LensVertex)
    float inverseDepth[3];
    // Edge i (opposite vertex i) runs from vertex `from[i]` by (dx, dy, dblur) in its canonical
    // order; `flipped[i]` when that order runs against the triangle's (i + 1 to i + 2).
    std::uint8_t from[3];
    float dx[3], dy[3], dblur[3];
    bool flipped[3];
    // The pixels whose samples it can cover from some point of the lens.
    LensPixels pixels;
};

LensTriangle setupLensTriangle(const Camera& camera, const LensModel& lens, const LensVertex& a,
                               const LensVertex& b, const LensVertex& c);
inline LensTriangle setupLensTriangle(const Camera& camera, const LensModel& lens, const Vec3& a,
                                      const Vec3& b, const Vec3& c) {
    return setupLensTriangle(camera, lens, projectThroughLens(lens, a), projectThroughLens(lens, b),
                             projectThroughLens(lens, c));
}

// The pixels the triangle can cover seen from the one lens point (lensX, lensY) (an interleaved
// pass's): its three images there, the same margin as `pixels`.
LensPixels lensPixelsFrom(const Camera& camera, const LensTriangle& t, float lensX, float lensY);

// Edge i's canonical function at screen point (sx, sy) from lens point (lx, ly) (the ray's
// origin), and its derivatives along the screen's x and y there.
struct LensEdgeValue {
    float e, dx, dy;
    // The sign of e at the sample moved by (eps, eps^2): the tie rule.
    bool positive() const {
        return e > 0.0f || (e == 0.0f && (dx > 0.0f || (dx == 0.0f && dy > 0.0f)));
    }
};

// The operations the vector kernels repeat lane by lane, in this order.
inline LensEdgeValue lensEdgeFunction(const LensTriangle& t, int i, float sx, float sy, float lx,
                                      float ly) {
    const int a = t.from[i];
    const float rx = sx - t.x[a], ry = sy - t.y[a];
    const float ex = -(t.dy[i] + t.dblur[i] * ly);
    const float ey = t.dx[i] + t.dblur[i] * lx;
    const float offset = t.blur[a] * (lx * t.dy[i] - ly * t.dx[i]);
    return {(rx * ex + ry * ey) + offset, ex, ey};
}

// The hit at a covered sample from its three oriented edge functions.
inline ScreenHit interpolateLensHit(const LensTriangle& t, float f0, float f1, float f2) {
    const float w0 = f0 * t.inverseDepth[0], w1 = f1 * t.inverseDepth[1],
                w2 = f2 * t.inverseDepth[2];
    const float inverseSum = 1.0f / ((w0 + w1) + w2);
    return {((f0 + f1) + f2) * inverseSum, w1 * inverseSum, w2 * inverseSum};
}

// Whether the triangle covers the sample at screen point (sx, sy) from lens point (lx, ly), with
// a depth in [nearPlane, depthMax] (both inclusive). The triangle must be of kind Covers.
inline bool coverLensSample(const LensTriangle& t, float sx, float sy, float lx, float ly,
                            float nearPlane, float depthMax, ScreenHit& hit) {
    float f[3];
    int positive = 0;  // oriented edges positive at the moved sample
    for (int i = 0; i < 3; ++i) {
        const LensEdgeValue edge = lensEdgeFunction(t, i, sx, sy, lx, ly);
        positive += edge.positive() != t.flipped[i];
        f[i] = t.flipped[i] ? -edge.e : edge.e;
    }
    if (positive != 0 && positive != 3) return false;
    const ScreenHit h = interpolateLensHit(t, f[0], f[1], f[2]);
    if (!(h.depth >= nearPlane && h.depth <= depthMax)) return false;
    hit = h;
    return true;
}

}  // namespace patchsim
