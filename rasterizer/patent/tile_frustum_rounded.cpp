#include "rasterizer/patent/tile_frustum_rounded.h"

#include <algorithm>
#include <cmath>

#include "rasterizer/common/conservative_margins.h"

namespace patchsim {

namespace {

RoundedValue distanceIn(const RoundedArithmetic& a, const Plane& pl, const Vec3& p) {
    const RoundedValue x = a.multiply(a.input(pl.n.x), a.input(p.x));
    const RoundedValue y = a.multiply(a.input(pl.n.y), a.input(p.y));
    const RoundedValue z = a.multiply(a.input(pl.n.z), a.input(p.z));
    return a.add(a.add(a.add(x, y), z), a.input(pl.d));
}

// A time of the format as a float, rounded as asked (fixed point may hold more bits).
float timeAsFloat(double t, Rounding rounding) {
    return float(roundDoubleTo(t, NumberFormat::fp32(), rounding));
}

struct Rounder {
    const RoundedArithmetic& arithmetic;
    bool bounded;
    Rounding down() const { return bounded ? Rounding::Down : Rounding::Nearest; }
    Rounding up() const { return bounded ? Rounding::Up : Rounding::Nearest; }
};

// The distance's value (naive) or its certain lower bound (bounded; minus infinity when it has
// none).
double distanceFor(const Rounder& r, const Plane& pl, const Vec3& p) {
    const RoundedValue d = distanceIn(r.arithmetic, pl, p);
    return r.bounded ? r.arithmetic.certainLowerBound(d) : d.value;
}

// The times the n-vertex may be inside the plane; false if never. As tile_frustum.cpp's
// insideInterval, on the distances' lower bounds (bounded) or their values (naive).
bool insideInterval(const Plane& pl, const LBBox& box, const Rounder& r, TimeRange& inside,
                    RasterWork& work) {
    work.planeTests += 2;
    const RoundedArithmetic& a = r.arithmetic;
    const double d0 = distanceFor(r, pl, nVertex(box.bounds0, pl.n));
    const double d1 = distanceFor(r, pl, nVertex(box.bounds1, pl.n));
    inside = TimeRange::shutter();
    if (r.bounded && !(std::isfinite(d0) && std::isfinite(d1))) return true;  // beyond the range
    if (d0 > 0 && d1 > 0) return false;
    if (d0 > 0) {  // moves from outside to inside: the entry time, rounded down
        ++work.timeIntervals;
        const double entry = a.divide(d0, a.add(d0, -d1, r.up()), r.down());
        const double guarded = a.add(entry, -double(kTimeGuard), r.down());
        inside.lower = std::max(0.0f, timeAsFloat(guarded, r.down()));
    } else if (d1 > 0) {  // moves from inside to outside: the exit time, rounded up
        ++work.timeIntervals;
        const double exit = a.divide(-d0, a.add(d1, -d0, r.down()), r.up());
        const double guarded = a.add(exit, double(kTimeGuard), r.up());
        inside.upper = std::min(1.0f, timeAsFloat(guarded, r.up()));
    }
    return true;
}

bool outsideAtBothEnds(const Plane& pl, const LBBox& box, const Rounder& r, bool motion,
                       RasterWork& work) {
    ++work.planeTests;
    if (!(distanceFor(r, pl, nVertex(box.bounds0, pl.n)) > 0)) return false;
    if (!motion) return true;
    ++work.planeTests;
    return distanceFor(r, pl, nVertex(box.bounds1, pl.n)) > 0;
}

bool narrow(const Plane* planes, int count, const LBBox& box, const Rounder& r, TimeRange& times,
            RasterWork& work) {
    TimeRange side = TimeRange::empty();
    for (int k = 0; k < count; ++k) {
        TimeRange inside;
        if (insideInterval(planes[k], box, r, inside, work)) side.extend(inside);
    }
    times.intersect(side);
    return !times.isEmpty();
}

}  // namespace

bool overlapsFrustumRounded(const TileFrustum& f, const LBBox& box,
                            const RoundedArithmetic& arithmetic, PlaneErrorHandling handling,
                            bool motion, RasterWork& work) {
    if (box.empty()) return false;
    const Rounder r{arithmetic, handling == PlaneErrorHandling::Bounded};
    for (int side = 0; side < 4; ++side) {
        bool outside = true;
        for (int k = 0; k < f.planesPerSide && outside; ++k)
            outside = outsideAtBothEnds(f.sides[side][k], box, r, motion, work);
        if (outside) return false;
    }
    if (!f.testNearFar) return true;
    return !(outsideAtBothEnds(f.nearPlane, box, r, motion, work) ||
             outsideAtBothEnds(f.farPlane, box, r, motion, work));
}

bool leafTimeIntervalRounded(const TileFrustum& f, const LBBox& box,
                             const RoundedArithmetic& arithmetic, PlaneErrorHandling handling,
                             TimeRange& times, RasterWork& work) {
    if (box.empty()) return false;
    const Rounder r{arithmetic, handling == PlaneErrorHandling::Bounded};
    for (int side = 0; side < 4; ++side)
        if (!narrow(f.sides[side], f.planesPerSide, box, r, times, work)) return false;
    if (!f.testNearFar) return true;
    return narrow(&f.nearPlane, 1, box, r, times, work) &&
           narrow(&f.farPlane, 1, box, r, times, work);
}

}  // namespace patchsim
