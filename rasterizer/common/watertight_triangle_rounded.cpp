#include "rasterizer/common/watertight_triangle_rounded.h"

#include <cmath>

namespace patchsim {

namespace {

// A datapath of the format, its values held exactly in doubles. A float format rounds every
// result to nearest. Fixed point rounds the coordinates (the relative and sheared vertices, the
// sheared depths) and the quotients (depth and weights) to the format, and holds products and
// their sums at full width, as a fixed-point rasterizer evaluates its edge functions exactly
// (2p + 2 bits for p-bit coordinates): rounded to p bits, the products of two nearby vertices'
// coordinates would vanish for any triangle smaller than a step squared.
struct RoundedDatapath {
    const NumberFormat& format;
    bool fullWidthProducts = format.kind == NumberFormat::Kind::Fixed;

    double coordinate(double x) const { return roundDoubleTo(x, format); }
    double product(double a, double b) const {
        return fullWidthProducts ? a * b : coordinate(a * b);
    }
    double sum(double a, double b) const { return fullWidthProducts ? a + b : coordinate(a + b); }
    // a / b: in a float format as fp32 does it, a reciprocal and a product, each rounded; in
    // fixed point one quotient rounded to the format.
    double quotient(double a, double reciprocal, double b) const {
        return fullWidthProducts ? coordinate(a / b) : coordinate(a * reciprocal);
    }
    double reciprocal(double b) const { return fullWidthProducts ? 0.0 : coordinate(1.0 / b); }
};

struct RoundedVec3 {
    double v[3];
};

// A vertex moved to the ray's origin and sheared: A[kx] - sx A[kz], A[ky] - sy A[kz], and the
// sheared depth sz A[kz].
struct ShearedCorner {
    double x, y, z;
};

ShearedCorner shearCorner(const RoundedDatapath& p, const ShearedRay& r, const RoundedVec3& origin,
                          double sx, double sy, double sz, const Vec3& vertex) {
    double A[3];
    for (int k = 0; k < 3; ++k) A[k] = p.coordinate(p.coordinate(vertex[k]) - origin.v[k]);
    return {p.coordinate(A[r.kx] - p.product(sx, A[r.kz])),
            p.coordinate(A[r.ky] - p.product(sy, A[r.kz])), p.coordinate(p.product(sz, A[r.kz]))};
}

// x1 y2 - y1 x2.
double edgeFunction(const RoundedDatapath& p, double x1, double y1, double x2, double y2) {
    return p.sum(p.product(x1, y2), -p.product(y1, x2));
}

}  // namespace

bool intersectTriangleRounded(const ShearedRay& r, const Vec3& a, const Vec3& b, const Vec3& c,
                              float lambdaMin, float lambdaMax, const NumberFormat& format,
                              TriangleHit& hit) {
    const RoundedDatapath p{format};
    const RoundedVec3 origin{
        {p.coordinate(r.origin.x), p.coordinate(r.origin.y), p.coordinate(r.origin.z)}};
    const double sx = p.coordinate(r.sx), sy = p.coordinate(r.sy), sz = p.coordinate(r.sz);
    const ShearedCorner A = shearCorner(p, r, origin, sx, sy, sz, a);
    const ShearedCorner B = shearCorner(p, r, origin, sx, sy, sz, b);
    const ShearedCorner C = shearCorner(p, r, origin, sx, sy, sz, c);
    double u = edgeFunction(p, C.x, C.y, B.x, B.y);
    double v = edgeFunction(p, A.x, A.y, C.x, C.y);
    double w = edgeFunction(p, B.x, B.y, A.x, A.y);
    if (u == 0 || v == 0 || w == 0) {
        u = float(C.x * B.y - C.y * B.x);
        v = float(A.x * C.y - A.y * C.x);
        w = float(B.x * A.y - B.y * A.x);
    }
    if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return false;
    const double det = p.sum(p.sum(u, v), w);
    if (det == 0 || !std::isfinite(det)) return false;
    const double t = p.sum(p.sum(p.product(u, A.z), p.product(v, B.z)), p.product(w, C.z));
    const double rcp = p.reciprocal(det);
    const double lambda = p.quotient(t, rcp, det);
    if (!(lambda >= lambdaMin && lambda <= lambdaMax)) return false;
    hit = {float(lambda), float(p.quotient(u, rcp, det)), float(p.quotient(v, rcp, det)),
           float(p.quotient(w, rcp, det))};
    return true;
}

}  // namespace patchsim
