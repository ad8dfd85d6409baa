#pragma once
// A ray against a linearly moving box at the ray's time (US 8,791,945, step 7): 12 multiply-adds.
//
// The box at time t is B(t) = (1-t) B0 + t B1. Along axis k the ray enters the slab of a face at
// lambda = ((1-t) x0 + t x1 - o) / d = x0 A + x1 B + C, with A = (1-t)/d, B = t/d and C = -o/d
// computed once per ray; two faces on three axes make the 12 multiply-adds. An axis the ray runs
// parallel to (a +0 or -0 component) is decided by whether the origin lies in the slab at time t,
// blended exactly as the vertices are, so a ray lying on a box face still meets it. The test is
// conservative by a relative slack (conservative_margins.h): flat boxes are never missed.

#include <algorithm>
#include <cmath>

#include "core/lbbox.h"
#include "core/ray.h"
#include "rasterizer/common/conservative_margins.h"

namespace patchsim {

struct SlabRay {
    Vec3 a, b, c;  // entry along axis k: x0 * a[k] + x1 * b[k] + c[k]
    float lambdaMin, lambdaMax;
    bool parallel[3];
    Vec3 origin;
    float time;
};

SlabRay makeSlabRay(const Ray& ray);

// Does the ray, at its time, meet the moving box within its [lambdaMin, lambdaMax]? `entry` gets
// where it enters (for visiting nearer boxes first). Inline: it is the innermost loop of every
// ray, called across translation units.
inline bool hitsMovingBox(const SlabRay& r, const LBBox& box, float& entry) {
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
    entry = nearest;
    return nearest <= farthest + kRayBoxRelativeSlack * (std::abs(nearest) + std::abs(farthest)) +
                          kRayBoxAbsoluteSlack;
}
inline bool hitsMovingBox(const SlabRay& ray, const LBBox& box) {
    float entry;
    return hitsMovingBox(ray, box, entry);
}

inline bool rayMeetsMovingBox(const Ray& ray, const LBBox& box) {
    return hitsMovingBox(makeSlabRay(ray), box);
}

}  // namespace patchsim
