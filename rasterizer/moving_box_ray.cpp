#include "rasterizer/moving_box_ray.h"

#include <algorithm>
#include <cmath>

#include "rasterizer/conservative_margins.h"

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

bool hitsMovingBox(const SlabRay& r, const LBBox& box) {
    if (box.empty()) return false;
    float nearest = r.lambdaMin, farthest = r.lambdaMax;
    for (int k = 0; k < 3; ++k) {
        if (r.parallel[k]) {
            const float lo = lerp(box.bounds0.lower, box.bounds1.lower, r.time)[k];
            const float hi = lerp(box.bounds0.upper, box.bounds1.upper, r.time)[k];
            if (r.origin[k] < lo || r.origin[k] > hi) return false;
            continue;
        }
        const float e0 = box.bounds0.lower[k] * r.a[k] + box.bounds1.lower[k] * r.b[k] + r.c[k];
        const float e1 = box.bounds0.upper[k] * r.a[k] + box.bounds1.upper[k] * r.b[k] + r.c[k];
        nearest = std::max(nearest, std::min(e0, e1));
        farthest = std::min(farthest, std::max(e0, e1));
    }
    return nearest <= farthest + kRayBoxRelativeSlack * (std::abs(nearest) + std::abs(farthest)) +
                          kRayBoxAbsoluteSlack;
}

}  // namespace patchsim
