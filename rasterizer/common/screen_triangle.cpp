#include "rasterizer/common/screen_triangle.h"

#include <algorithm>

namespace patchsim {

namespace {

// The pixel of an integer sub-pixel coordinate (an arithmetic shift floors negatives too).
int floorPixel(double subpixels) {
    return int(std::int64_t(subpixels) >> kSubpixelBits);
}

}  // namespace

// rasterToScreen inverted, in double.
ScreenVertex projectToScreen(const Camera& camera, const Vec3& p) {
    ScreenVertex v;
    const double depth = -double(p.z);
    if (!(depth > 0.0) || !std::isfinite(depth) || !std::isfinite(p.x) || !std::isfinite(p.y))
        return v;
    const double tanY = camera.tanHalfFovY(), tanX = tanY * double(camera.aspect());
    const double rasterX = (double(p.x) / depth / tanX + 1.0) * 0.5 * camera.width();
    const double rasterY = (1.0 - double(p.y) / depth / tanY) * 0.5 * camera.height();
    if (!(std::abs(rasterX) < kGuardBandPixels && std::abs(rasterY) < kGuardBandPixels)) return v;
    v.x = roundToInteger(rasterX * kSubpixelsPerPixel);
    v.y = roundToInteger(rasterY * kSubpixelsPerPixel);
    v.inverseDepth = float(1.0 / depth);
    v.valid = true;
    return v;
}

ScreenTriangle setupScreenTriangle(const Camera& camera, const ScreenVertex& v0,
                                   const ScreenVertex& v1, const ScreenVertex& v2) {
    ScreenTriangle t{};
    if (!v0.valid || !v1.valid || !v2.valid) {
        t.kind = ScreenTriangle::Kind::NeedsRay;
        return t;
    }
    const double x[3] = {v0.x, v1.x, v2.x}, y[3] = {v0.y, v1.y, v2.y};
    t.inverseDepth[0] = v0.inverseDepth;
    t.inverseDepth[1] = v1.inverseDepth;
    t.inverseDepth[2] = v2.inverseDepth;
    // Edge i runs from vertex i+1 to vertex i+2; its function at vertex i is twice the area.
    double edgeA[3], edgeB[3];
    for (int i = 0; i < 3; ++i) {
        const int from = (i + 1) % 3, to = (i + 2) % 3;
        edgeA[i] = -(y[to] - y[from]);
        edgeB[i] = x[to] - x[from];
        t.x0[i] = x[from];
        t.y0[i] = y[from];
    }
    const double area = edgeA[0] * (x[0] - t.x0[0]) + edgeB[0] * (y[0] - t.y0[0]);
    if (area == 0.0) return t;  // no area on the sub-pixel grid: covers nothing
    const double sign = area > 0.0 ? 1.0 : -1.0;
    for (int i = 0; i < 3; ++i) {
        t.a[i] = sign * edgeA[i];
        t.b[i] = sign * edgeB[i];
        t.ownsTies[i] = t.a[i] > 0.0 || (t.a[i] == 0.0 && t.b[i] > 0.0);
    }
    t.area = float(sign * area);
    // Pixel p's samples lie in [256 p, 256 p + 255] sub-pixels (sampleSubpixel).
    const double minX = std::min({x[0], x[1], x[2]}), maxX = std::max({x[0], x[1], x[2]});
    const double minY = std::min({y[0], y[1], y[2]}), maxY = std::max({y[0], y[1], y[2]});
    t.small = maxX - minX <= kSmallExtent && maxY - minY <= kSmallExtent;
    t.pixelX0 = std::max(0, floorPixel(minX));
    t.pixelX1 = std::min(camera.width(), floorPixel(maxX) + 1);
    t.pixelY0 = std::max(0, floorPixel(minY));
    t.pixelY1 = std::min(camera.height(), floorPixel(maxY) + 1);
    t.kind = t.pixelX0 < t.pixelX1 && t.pixelY0 < t.pixelY1 ? ScreenTriangle::Kind::Covers
                                                            : ScreenTriangle::Kind::Empty;
    return t;
}

}  // namespace patchsim
