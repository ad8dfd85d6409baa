#include "rasterizer/patent/moving_box_ray.h"

#include <cmath>

namespace patchsim {

SlabRay makeSlabRay(const Ray& ray) {
    SlabRay s;
    for (int k = 0; k < 3; ++k) {
        s.parallel[k] = std::abs(ray.direction[k]) < kParallelDirection;
        const float inv = s.parallel[k] ? 0.0f : 1.0f / ray.direction[k];
        s.a[k] = (1.0f - ray.time) * inv;
        s.b[k] = ray.time * inv;
        s.c[k] = -ray.origin[k] * inv;
    }
    s.origin = ray.origin;
    s.time = ray.time;
    s.lambdaMin = ray.lambdaMin;
    s.lambdaMax = ray.lambdaMax;
    return s;
}

}  // namespace patchsim
