#pragma once
// The watertight ray-triangle test (watertight_triangle.h) computed in a narrower number format:
// issue 35's ray-triangle site, rasterizer.triangle_format.
//
// Every input enters the format rounded to nearest (the ray's origin and shear, the vertices
// blended to the ray's time, which the vertex fetch does in fp32). In a float format every
// operation of the fp32 test, in the same order, rounds its result to nearest: the relative
// vertices, the sheared coordinates, the three edge functions, their sum, the depth terms, the
// reciprocal and the products with it. With fp32 this is the fp32 test bit for bit (double
// rounding through double is innocuous for float's +, -, x and /), which the tests check. In
// fixed point the coordinates (relative, sheared) round to the format, while products and their
// sums (edge functions, determinant, depth numerator) are held at full width, as a fixed-point
// rasterizer evaluates edge functions exactly (2p + 2 bits for p-bit coordinates); the depth and
// the weights are one quotient each, rounded to the format. Rounded to p bits, the edge function
// of a triangle smaller than a step squared would vanish. Full width is exact in the double that
// holds it up to 26 bits of format (fixed16.8 and narrower); wider ones round there too, which
// keeps every argument below.
//
// Why lossy and not conservative
// ------------------------------
// The culling sites (node boxes, tile planes, ray-box tests) only decide what to skip, so they
// round outward and lose nothing. This test decides coverage itself: there is no exact answer
// behind it to be conservative toward, and widening it would grow every triangle by the format's
// error, doubling hits along every edge. It rounds to nearest and is lossy by design, as the
// domain-shaded positions are: the image moves away from fp32's, the more the fewer bits.
//
// Why still watertight
// --------------------
// Woop's argument survives the narrowing, within the format's range. Two triangles that share an
// edge shear its two vertices identically (one ray, the same rounded inputs and operations), so
// both evaluate that edge's function from the same two products, in opposite order. In a float
// format the products and their difference round to nearest, which is symmetric (round(-x) =
// -round(x)), so one gets exactly the other's negative; in fixed point the edge function is not
// rounded at all (full width), so the same holds exactly. A sample therefore lies inside at most
// one of them and outside at most one, never outside both. An edge function that is zero is
// recomputed from the rounded coordinates in double (nearly exact, as fp32's fallback is) and
// kept at float's precision, so the sign that breaks the tie is the true sign of the shared
// coordinates, again the same for both.
//
// Beyond the range there is a crack: a float format's product that overflows (fp16: sheared
// coordinates beyond about 256 units) makes an edge function infinite or NaN, the determinant
// is not finite, and both triangles refuse the hit, as fp32 refuses a non-finite determinant
// (HardCases.CoordinatesNear1e5And1eMinus5: fp16 loses the whole surface at 5e5 units). Fixed
// point saturates its coordinates instead. Full width is exact in the double that holds it for
// edge functions of formats up to 26 bits (fixed16.8 and narrower); the depth numerator (about 3p
// bits) is not exact beyond 17 bits, which only moves the rounding of the quotient it feeds.

#include "core/number_format.h"
#include "rasterizer/common/watertight_triangle.h"

namespace patchsim {

// intersectTriangle's test, every value in `format` (see above).
bool intersectTriangleRounded(const ShearedRay& r, const Vec3& a, const Vec3& b, const Vec3& c,
                              float lambdaMin, float lambdaMax, const NumberFormat& format,
                              TriangleHit& hit);

// The fp32 test for fp32, else the rounded one: for callers outside a hot loop.
inline bool intersectTriangleIn(const NumberFormat& format, const ShearedRay& r, const Vec3& a,
                                const Vec3& b, const Vec3& c, float lambdaMin, float lambdaMax,
                                TriangleHit& hit) {
    if (format == NumberFormat::fp32())
        return intersectTriangle(r, a, b, c, lambdaMin, lambdaMax, hit);
    return intersectTriangleRounded(r, a, b, c, lambdaMin, lambdaMax, format, hit);
}

}  // namespace patchsim
