#include "rasterizer/verifier/tile_test_truth.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace patchsim {

namespace {

using DVec3 = glm::dvec3;

// The tile's rays between two depths on one side of the focal plane: eight vertices, two
// rectangles (at depth da and db) joined corner to corner.
struct RaySolid {
    std::array<DVec3, 8> vertex;  // [depth index * 4 + corner], corner bit 0: x high, bit 1: y high
};

struct ScreenRect {
    double x0, x1, y0, y1;  // on the z = -1 plane
};

RaySolid raySolid(const ScreenRect& s, const LensRect& l, double radius, double focus, double da,
                  double db) {
    RaySolid solid;
    for (int k = 0; k < 2; ++k) {
        const double d = k == 0 ? da : db;
        // Lens point o seen at depth d along its ray to the focal plane: (1 - d/F) o.
        const double w = radius > 0 ? 1.0 - d / focus : 0.0;
        const double lu0 = w * l.u0 * radius, lu1 = w * l.u1 * radius;
        const double lv0 = w * l.v0 * radius, lv1 = w * l.v1 * radius;
        const double xlo = d * s.x0 + std::min(lu0, lu1), xhi = d * s.x1 + std::max(lu0, lu1);
        const double ylo = d * s.y0 + std::min(lv0, lv1), yhi = d * s.y1 + std::max(lv0, lv1);
        for (int c = 0; c < 4; ++c)
            solid.vertex[std::size_t(4 * k + c)] = {(c & 1) ? xhi : xlo, (c & 2) ? yhi : ylo, -d};
    }
    return solid;
}

// [lower, upper] narrowed to where a + b t <= 0.
void keepNonPositive(double a, double b, double& lower, double& upper) {
    if (b == 0.0) {
        if (a > 0.0) upper = -1.0;  // never
        return;
    }
    const double root = -a / b;
    if (b > 0.0)
        upper = std::min(upper, root);
    else
        lower = std::max(lower, root);
}

// The box's extent along n at t=0 and t=1: [lo0 + (lo1 - lo0) t, hi0 + (hi1 - hi0) t].
void boxExtent(const LBBox& box, const DVec3& n, double lo[2], double hi[2]) {
    for (int end = 0; end < 2; ++end) {
        const Box3& b = end == 0 ? box.bounds0 : box.bounds1;
        lo[end] = hi[end] = 0.0;
        for (int k = 0; k < 3; ++k) {
            const double a = n[k] * double(b.lower[k]), c = n[k] * double(b.upper[k]);
            lo[end] += std::min(a, c);
            hi[end] += std::max(a, c);
        }
    }
}

// The exact interval of t in [0, 1] at which the box overlaps the solid (empty when never).
TimeRange overlapTimes(const RaySolid& solid, const LBBox& box) {
    std::array<DVec3, 15> axes;
    int count = 0;
    const DVec3 unit[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const DVec3& e : unit) axes[std::size_t(count++)] = e;
    for (int c = 0; c < 4; ++c) {
        const DVec3 lateral = solid.vertex[std::size_t(4 + c)] - solid.vertex[std::size_t(c)];
        for (const DVec3& e : unit) {
            const DVec3 n = glm::cross(e, lateral);
            if (glm::dot(n, n) > 1e-24 * glm::dot(lateral, lateral)) axes[std::size_t(count++)] = n;
        }
    }
    double lower = 0.0, upper = 1.0;
    for (int i = 0; i < count && lower <= upper; ++i) {
        const DVec3& n = axes[std::size_t(i)];
        double pmin = INFINITY, pmax = -INFINITY;
        for (const DVec3& v : solid.vertex) {
            pmin = std::min(pmin, glm::dot(n, v));
            pmax = std::max(pmax, glm::dot(n, v));
        }
        double lo[2], hi[2];
        boxExtent(box, n, lo, hi);
        keepNonPositive(lo[0] - pmax, lo[1] - lo[0], lower, upper);  // lo(t) <= pmax
        keepNonPositive(pmin - hi[0], hi[0] - hi[1], lower, upper);  // hi(t) >= pmin
    }
    if (!(lower <= upper)) return TimeRange::empty();
    return {float(lower), float(upper)};
}

ScreenRect screenRect(const Camera& camera, const TileRect& tile) {
    const double tanY = camera.tanHalfFovY(), tanX = tanY * camera.aspect();
    const double w = camera.width(), h = camera.height();
    return {(2.0 * tile.x0 / w - 1.0) * tanX, (2.0 * tile.x1 / w - 1.0) * tanX,
            (1.0 - 2.0 * tile.y1 / h) * tanY, (1.0 - 2.0 * tile.y0 / h) * tanY};
}

bool rayHitsBox(const DVec3& o, const DVec3& d, const Box3& b, double lambdaMin, double lambdaMax) {
    double lo = lambdaMin, hi = lambdaMax;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (o[k] < b.lower[k] || o[k] > b.upper[k]) return false;
            continue;
        }
        double a = (double(b.lower[k]) - o[k]) / d[k], c = (double(b.upper[k]) - o[k]) / d[k];
        if (a > c) std::swap(a, c);
        lo = std::max(lo, a);
        hi = std::min(hi, c);
    }
    return lo <= hi;
}

}  // namespace

TileTruth exactTileTruth(const Camera& camera, const LensModel& lens, const TileRect& tile,
                         const LBBox& box, const LensRect& lensPart) {
    TileTruth truth;
    if (box.empty() || lensPart.isEmpty()) return truth;
    const ScreenRect s = screenRect(camera, tile);
    const double near = camera.nearPlane(), far = camera.farPlane();
    const double radius = lens.radius, focus = lens.focusDistance;
    // Split at the focal plane, where the lens term changes sign.
    double cuts[3] = {near, far, far};
    int solids = 1;
    if (radius > 0 && focus > near && focus < far) {
        cuts[1] = focus;
        solids = 2;
    }
    for (int k = 0; k < solids; ++k) {
        const TimeRange t =
            overlapTimes(raySolid(s, lensPart, radius, focus, cuts[k], cuts[k + 1]), box);
        if (t.isEmpty()) continue;
        truth.hit = true;
        truth.times.extend(t);
    }
    return truth;
}

std::vector<WitnessHit> sampledWitness(const Camera& camera, const LensModel& lens,
                                       const TileRect& tile, const LBBox& box, int screenSteps,
                                       int lensSteps, int timeSteps) {
    std::vector<WitnessHit> hits;
    const int lensCount = lens.radius > 0 ? lensSteps : 1;
    for (int ti = 0; ti < timeSteps; ++ti) {
        const float t = float(ti) / float(timeSteps - 1);
        const Box3 b = box.at(t);
        for (int ly = 0; ly < lensCount; ++ly) {
            for (int lx = 0; lx < lensCount; ++lx) {
                Vec2 l(0);
                if (lens.radius > 0) {
                    l = Vec2(-1.0f + 2.0f * float(lx) / float(lensSteps - 1),
                             -1.0f + 2.0f * float(ly) / float(lensSteps - 1));
                    if (glm::length(l) > 1.0f) l /= glm::length(l);
                }
                bool hit = false;
                for (int sy = 0; sy < screenSteps && !hit; ++sy) {
                    for (int sx = 0; sx < screenSteps && !hit; ++sx) {
                        const Vec2 raster(float(tile.x0) + float(tile.x1 - tile.x0) * float(sx) /
                                                               float(screenSteps - 1),
                                          float(tile.y0) + float(tile.y1 - tile.y0) * float(sy) /
                                                               float(screenSteps - 1));
                        const Ray ray =
                            makeCameraRay(camera, rasterToScreen(camera, raster), l, t, lens);
                        const double dpl = ray.depthPerLambda;
                        hit = rayHitsBox(DVec3(ray.origin), DVec3(ray.direction), b,
                                         camera.nearPlane() / dpl, camera.farPlane() / dpl);
                    }
                }
                if (hit) hits.push_back({t, l});
            }
        }
    }
    return hits;
}

}  // namespace patchsim
