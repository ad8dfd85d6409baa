#include "rasterizer/patent/projected_bounds_rounded.h"

#include <cmath>

namespace patchsim {

namespace {

// A z = -1 plane coordinate (axis 0: x, 1: y) as stored (see the header).
float storedOnPlane(float v, int axis, Rounding rounding, const NumberFormat& format,
                    const Camera& camera) {
    if (format.kind != NumberFormat::Kind::Fixed) return roundTo(v, format, rounding);
    const double half = 0.5 * (axis == 0 ? camera.width() : camera.height());
    const double tangent =
        axis == 0 ? double(camera.tanHalfFovY()) * camera.aspect() : double(camera.tanHalfFovY());
    const double scale = (axis == 0 ? half : -half) / tangent;
    const double toPlane = 1.0 / scale;
    const double direction = rounding == Rounding::Down ? -1 : rounding == Rounding::Up ? 1 : 0;
    const double inPixels = axis == 0 ? direction : -direction;  // y's direction flips
    constexpr double kError = 0x1p-50;  // relative, more than a few double roundings
    double pixel = double(v) * scale + half;
    pixel += inPixels * kError * (std::abs(double(v) * scale) + half);
    const double grid = std::ldexp(1.0, -format.fractionBits);
    const double limit = std::ldexp(1.0, format.integerBits - 1);
    if (!std::isfinite(pixel) || pixel < -limit || pixel >= limit) return v;
    const double snapped = inPixels < 0   ? std::floor(pixel / grid) * grid
                           : inPixels > 0 ? std::ceil(pixel / grid) * grid
                                          : std::nearbyint(pixel / grid) * grid;
    double back = (snapped - half) * toPlane;
    back += direction * kError * std::abs(back);
    float result = float(back);
    if (direction < 0 && double(result) > back) result = std::nextafter(result, -INFINITY);
    if (direction > 0 && double(result) < back) result = std::nextafter(result, INFINITY);
    return result;
}

}  // namespace

ScreenMovingBox storedIn(const ScreenMovingBox& box, const NumberFormat& format, bool outward,
                         const Camera& camera) {
    ScreenMovingBox b = box;
    if (format == NumberFormat::fp32() || b.empty || !b.bounded) return b;
    const Rounding down = outward ? Rounding::Down : Rounding::Nearest;
    const Rounding up = outward ? Rounding::Up : Rounding::Nearest;
    for (Vec2* lower : {&b.lower0, &b.lower1})
        for (int axis = 0; axis < 2; ++axis)
            (*lower)[axis] = storedOnPlane((*lower)[axis], axis, down, format, camera);
    for (Vec2* upper : {&b.upper0, &b.upper1})
        for (int axis = 0; axis < 2; ++axis)
            (*upper)[axis] = storedOnPlane((*upper)[axis], axis, up, format, camera);
    if (format.kind != NumberFormat::Kind::Fixed) {  // depths stay float in fixed point
        b.ratioMin = roundTo(b.ratioMin, format, down);
        b.ratioMax = roundTo(b.ratioMax, format, up);
        b.nearDepth0 = roundTo(b.nearDepth0, format, down);
        b.nearDepth1 = roundTo(b.nearDepth1, format, down);
    }
    return b;
}

}  // namespace patchsim
