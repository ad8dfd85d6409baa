#include "rasterizer/patent/moving_box_ray_rounded.h"

#include <algorithm>
#include <cmath>

namespace patchsim {

namespace {

RoundedValue slabDistance(const RoundedArithmetic& a, float x0, float x1, const SlabRay& r, int k) {
    const RoundedValue at0 = a.multiply(a.input(x0), a.input(r.a[k]));
    const RoundedValue at1 = a.multiply(a.input(x1), a.input(r.b[k]));
    return a.add(a.add(at0, at1), a.input(r.c[k]));
}

bool outsideParallelSlab(const SlabRay& r, const LBBox& box, int k) {
    const float lo = lerp(box.bounds0.lower, box.bounds1.lower, r.time)[k];
    const float hi = lerp(box.bounds0.upper, box.bounds1.upper, r.time)[k];
    return r.origin[k] < lo || r.origin[k] > hi;
}

}  // namespace

bool hitsMovingBoxRounded(const SlabRay& r, const LBBox& box, const RoundedArithmetic& a,
                          PlaneErrorHandling handling) {
    if (box.empty()) return false;
    const bool bounded = handling == PlaneErrorHandling::Bounded;
    // The entry and the exit, each between a lower and an upper bound.
    double entryLow = r.lambdaMin, entryHigh = r.lambdaMin;
    double exitLow = r.lambdaMax, exitHigh = r.lambdaMax;
    for (int k = 0; k < 3; ++k) {
        if (r.parallel[k]) {
            if (outsideParallelSlab(r, box, k)) return false;
            continue;
        }
        const RoundedValue e0 = slabDistance(a, box.bounds0.lower[k], box.bounds1.lower[k], r, k);
        const RoundedValue e1 = slabDistance(a, box.bounds0.upper[k], box.bounds1.upper[k], r, k);
        if (bounded && !(e0.inRange && e1.inRange)) continue;
        const double low0 = bounded ? a.certainLowerBound(e0) : e0.value;
        const double low1 = bounded ? a.certainLowerBound(e1) : e1.value;
        const double high0 = bounded ? a.certainUpperBound(e0) : e0.value;
        const double high1 = bounded ? a.certainUpperBound(e1) : e1.value;
        entryLow = std::max(entryLow, std::min(low0, low1));
        entryHigh = std::max(entryHigh, std::min(high0, high1));
        exitLow = std::min(exitLow, std::max(low0, low1));
        exitHigh = std::min(exitHigh, std::max(high0, high1));
    }
    const double largest = std::max(std::abs(entryLow), std::abs(entryHigh)) +
                           std::max(std::abs(exitLow), std::abs(exitHigh));
    return entryLow <=
           exitHigh + double(kRayBoxRelativeSlack) * largest + double(kRayBoxAbsoluteSlack);
}

}  // namespace patchsim
