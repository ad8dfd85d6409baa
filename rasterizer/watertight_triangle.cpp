#include "rasterizer/watertight_triangle.h"

#include <cmath>
#include <utility>

namespace patchsim {

ShearedRay shearRay(const Ray& ray) {
    ShearedRay s;
    s.origin = ray.origin;
    const Vec3 a = glm::abs(ray.direction);
    s.kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    s.kx = (s.kz + 1) % 3;
    s.ky = (s.kx + 1) % 3;
    if (ray.direction[s.kz] < 0.0f) std::swap(s.kx, s.ky);  // keep the winding
    s.sx = ray.direction[s.kx] / ray.direction[s.kz];
    s.sy = ray.direction[s.ky] / ray.direction[s.kz];
    s.sz = 1.0f / ray.direction[s.kz];
    return s;
}

bool intersectTriangle(const ShearedRay& r, const Vec3& a, const Vec3& b, const Vec3& c,
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
