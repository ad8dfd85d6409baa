#pragma once
// Watertight ray-triangle intersection (Woop, Benthin, Wald 2013), on triangles blended to the
// ray's time. The ray is sheared so it runs along +z; edge functions are evaluated in that frame
// and recomputed in double precision when one is exactly zero, so a ray through a shared edge or
// vertex hits at least one of the triangles, and never falls through the crack between them.

#include <cmath>

#include "core/ray.h"

namespace patchsim {

struct ShearedRay {
    Vec3 origin{0.0f};
    int kx = 0, ky = 1, kz = 2;
    float sx = 0, sy = 0, sz = 1;
};

ShearedRay shearRay(const Ray& ray);

struct TriangleHit {
    float lambda = 0.0f;                    // ray parameter
    float b0 = 0.0f, b1 = 0.0f, b2 = 0.0f;  // barycentric weights of vertices 0, 1, 2
};

// Hit in [lambdaMin, lambdaMax] (both inclusive); both faces count. Inline, like the box test:
// it runs for every triangle of every leaf a ray reaches.
inline bool intersectTriangle(const ShearedRay& r, const Vec3& a, const Vec3& b, const Vec3& c,
                              float lambdaMin, float lambdaMax, TriangleHit& hit) {
    const Vec3 A = a - r.origin, B = b - r.origin, C = c - r.origin;
    const float ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
    const float bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
    const float cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        u = float(double(cx) * double(by) - double(cy) * double(bx));
        v = float(double(ax) * double(cy) - double(ay) * double(cx));
        w = float(double(bx) * double(ay) - double(by) * double(ax));
    }
    if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return false;
    const float det = u + v + w;
    if (det == 0.0f || !std::isfinite(det)) return false;
    const float az = r.sz * A[r.kz], bz = r.sz * B[r.kz], cz = r.sz * C[r.kz];
    const float t = u * az + v * bz + w * cz;
    const float rcp = 1.0f / det;
    const float lambda = t * rcp;
    if (!(lambda >= lambdaMin && lambda <= lambdaMax)) return false;
    hit = {lambda, u * rcp, v * rcp, w * rcp};
    return true;
}

}  // namespace patchsim
