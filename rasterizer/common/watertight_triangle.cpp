#include "rasterizer/common/watertight_triangle.h"

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

}  // namespace patchsim
