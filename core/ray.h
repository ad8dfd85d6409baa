#pragma once
// Camera-space rays of visibility samples.
//
// A sample's ray starts at its lens point (x, y, 0) and passes through the sample's point on the
// plane in focus (depth F); without defocus it starts at the pinhole with direction (sx, sy, -1),
// where (sx, sy) is the sample's position on the z = -1 plane. Depth along the view axis is then
// `lambda * depthPerLambda`, so a z-buffer depth converts to a ray parameter with one divide. A
// ray carries the range of its parameter it may hit in, [lambdaMin, lambdaMax] (Embree's tnear
// and tfar), which z culling and nearer hits shrink.

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/camera.h"
#include "core/lbbox.h"
#include "core/math.h"

namespace patchsim {

struct Ray {
    Vec3 origin{0.0f};
    Vec3 direction{0.0f, 0.0f, -1.0f};
    float time = 0;
    float depthPerLambda = 1;  // -direction.z
    float lambdaMin = 0;
    float lambdaMax = std::numeric_limits<float>::infinity();
};

struct LensModel {
    float radius = 0;  // 0: pinhole
    float focusDistance = 1;
};

// Raster position (pixels, y down) to the z = -1 image plane (x right, y up).
inline Vec2 rasterToScreen(const Camera& camera, Vec2 raster) {
    const float sx =
        (2.0f * raster.x / float(camera.width()) - 1.0f) * camera.tanHalfFovY() * camera.aspect();
    const float sy = (1.0f - 2.0f * raster.y / float(camera.height())) * camera.tanHalfFovY();
    return {sx, sy};
}

// `lensDisk` is the lens sample already mapped to the unit disk. The ray's range is the camera's
// near to far plane.
inline Ray makeCameraRay(const Camera& camera, Vec2 screen, Vec2 lensDisk, float time,
                         const LensModel& lens) {
    Ray ray;
    ray.time = time;
    if (lens.radius > 0) {
        const Vec3 focus(screen.x * lens.focusDistance, screen.y * lens.focusDistance,
                         -lens.focusDistance);
        ray.origin = Vec3(lens.radius * lensDisk, 0.0f);
        ray.direction = focus - ray.origin;
        ray.depthPerLambda = lens.focusDistance;
    } else {
        ray.origin = Vec3(0);
        ray.direction = Vec3(screen, -1.0f);
        ray.depthPerLambda = 1.0f;
    }
    ray.lambdaMin = camera.nearPlane() / ray.depthPerLambda;
    ray.lambdaMax = camera.farPlane() / ray.depthPerLambda;
    return ray;
}

// The ray against a static box over [lambdaMin, lambdaMax] (slab test; an axis the ray runs
// parallel to is decided by the origin). Each slab is widened by `slack` of its distance, for
// callers that must not lose a grazing hit to rounding. `entry` gets the parameter it enters at.
inline bool rayHitsBox(const Ray& r, const Box3& b, float lambdaMin, float lambdaMax, float& entry,
                       float slack = 0.0f) {
    float lo = lambdaMin, hi = lambdaMax;
    for (int k = 0; k < 3; ++k) {
        if (r.direction[k] == 0.0f) {
            if (r.origin[k] < b.lower[k] || r.origin[k] > b.upper[k]) return false;
            continue;
        }
        const float inv = 1.0f / r.direction[k];
        float a = (b.lower[k] - r.origin[k]) * inv, c = (b.upper[k] - r.origin[k]) * inv;
        if (a > c) std::swap(a, c);
        lo = std::max(lo, a - slack * std::abs(a));
        hi = std::min(hi, c + slack * std::abs(c));
    }
    entry = lo;
    return lo <= hi;
}

}  // namespace patchsim
