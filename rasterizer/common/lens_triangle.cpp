#include "rasterizer/common/lens_triangle.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "rasterizer/common/conservative_margins.h"

namespace patchsim {

namespace {

// Screen-plane bounds grown point by point, in double.
struct ScreenSpan {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    void add(double sx, double sy, double spread) {
        lo[0] = std::min(lo[0], sx - spread);
        hi[0] = std::max(hi[0], sx + spread);
        lo[1] = std::min(lo[1], sy - spread);
        hi[1] = std::max(hi[1], sy + spread);
    }
};

// The pixels whose samples may fall in `span`, with the screen bounds' margin; `inGuardBand`
// false when the span reaches beyond the guard band (no edge-function form).
LensPixels pixelsOf(const Camera& camera, const ScreenSpan& span, bool& inGuardBand) {
    const double w = camera.width(), h = camera.height();
    const double tanY = camera.tanHalfFovY(), tanX = tanY * double(camera.aspect());
    const double margin = kScreenBoundsMarginPixels;
    const double x0 = (span.lo[0] / tanX + 1.0) * 0.5 * w - margin;
    const double x1 = (span.hi[0] / tanX + 1.0) * 0.5 * w + margin;
    const double y0 = (1.0 - span.hi[1] / tanY) * 0.5 * h - margin;
    const double y1 = (1.0 - span.lo[1] / tanY) * 0.5 * h + margin;
    inGuardBand = std::abs(x0) < kGuardBandPixels && std::abs(x1) < kGuardBandPixels &&
                  std::abs(y0) < kGuardBandPixels && std::abs(y1) < kGuardBandPixels;
    if (!inGuardBand) return {};
    LensPixels p;
    p.x0 = std::clamp(int(std::floor(x0)), 0, camera.width());
    p.x1 = std::clamp(int(std::floor(x1)) + 1, 0, camera.width());
    p.y0 = std::clamp(int(std::floor(y0)), 0, camera.height());
    p.y1 = std::clamp(int(std::floor(y1)) + 1, 0, camera.height());
    return p;
}

}  // namespace

LensVertex projectThroughLens(const LensModel& lens, const Vec3& p) {
    LensVertex v;
    const float depth = -p.z;
    if (!(depth > 0.0f) || !std::isfinite(depth) || !std::isfinite(p.x) || !std::isfinite(p.y))
        return v;
    v.inverseDepth = 1.0f / depth;
    v.x = p.x * v.inverseDepth;
    v.y = p.y * v.inverseDepth;
    v.blur = 1.0f / lens.focusDistance - v.inverseDepth;
    v.valid = std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.blur);
    return v;
}

LensTriangle setupLensTriangle(const Camera& camera, const LensModel& lens, const LensVertex& v0,
                               const LensVertex& v1, const LensVertex& v2) {
    LensTriangle t{};
    if (!v0.valid || !v1.valid || !v2.valid) {
        t.kind = LensTriangle::Kind::NeedsRay;
        return t;
    }
    const LensVertex* v[3] = {&v0, &v1, &v2};
    ScreenSpan span;
    for (int i = 0; i < 3; ++i) {
        t.x[i] = v[i]->x;
        t.y[i] = v[i]->y;
        t.blur[i] = v[i]->blur;
        t.inverseDepth[i] = v[i]->inverseDepth;
        span.add(t.x[i], t.y[i], std::abs(double(t.blur[i])) * double(lens.radius));
    }
    // Edge i runs from vertex i+1 to vertex i+2, or the other way when that is the canonical
    // order, so a neighbour sharing the edge computes the same function.
    for (int i = 0; i < 3; ++i) {
        int a = (i + 1) % 3, b = (i + 2) % 3;
        t.flipped[i] = std::tie(t.x[b], t.y[b], t.blur[b]) < std::tie(t.x[a], t.y[a], t.blur[a]);
        if (t.flipped[i]) std::swap(a, b);
        t.from[i] = std::uint8_t(a);
        t.dx[i] = t.x[b] - t.x[a];
        t.dy[i] = t.y[b] - t.y[a];
        t.dblur[i] = t.blur[b] - t.blur[a];
    }
    bool inGuardBand = false;
    t.pixels = pixelsOf(camera, span, inGuardBand);
    if (!inGuardBand) {
        t.kind = LensTriangle::Kind::NeedsRay;
        return t;
    }
    t.kind = t.pixels.empty() ? LensTriangle::Kind::Empty : LensTriangle::Kind::Covers;
    return t;
}

LensPixels lensPixelsFrom(const Camera& camera, const LensTriangle& t, float lensX, float lensY) {
    ScreenSpan span;
    for (int i = 0; i < 3; ++i)
        span.add(double(t.x[i]) + double(t.blur[i]) * lensX,
                 double(t.y[i]) + double(t.blur[i]) * lensY, 0.0);
    bool inGuardBand = false;
    return pixelsOf(camera, span, inGuardBand);
}

}  // namespace patchsim
