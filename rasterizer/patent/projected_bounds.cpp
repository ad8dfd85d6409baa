#include "rasterizer/patent/projected_bounds.h"

#include <algorithm>
#include <cmath>

#include "rasterizer/common/conservative_margins.h"

namespace patchsim {

namespace {

// The tile's edges on the z = -1 plane, widened by the tile guard: left, right, bottom, top.
void tileEdges(const Camera& camera, const TileRect& tile, float edges[4]) {
    const Vec2 lo = rasterToScreen(
        camera, {float(tile.x0) - kTileGuardPixels, float(tile.y1) + kTileGuardPixels});
    const Vec2 hi = rasterToScreen(
        camera, {float(tile.x1) + kTileGuardPixels, float(tile.y0) - kTileGuardPixels});
    edges[0] = lo.x;
    edges[1] = hi.x;
    edges[2] = lo.y;
    edges[3] = hi.y;
}

// Where g0 + (g1 - g0) s <= 0 for s in [0, 1], as [lower, upper]; false when nowhere.
bool nonPositiveRange(float g0, float g1, float& lower, float& upper) {
    lower = 0.0f;
    upper = 1.0f;
    if (g0 > 0 && g1 > 0) return false;
    if (g0 > 0) lower = g0 / (g0 - g1);
    if (g1 > 0) upper = g0 / (g0 - g1);
    return true;
}

// ---- 2DH ----

float lineDistance(const HomogeneousLine& l, const Box3& clip, bool pVertex) {
    const bool aLow = (l.a > 0) != pVertex, bLow = (l.b > 0) != pVertex;
    const float coordinate = l.axis < 2 ? (aLow ? clip.lower[l.axis] : clip.upper[l.axis]) : 0.0f;
    const float w = bLow ? clip.lower.z : clip.upper.z;
    return l.a * coordinate + l.b * w + l.c;
}

bool outsideLineAtBothEnds(const HomogeneousLine& l, const LBBox& clip, bool motion,
                           RasterWork& work) {
    ++work.planeTests;
    if (!(lineDistance(l, clip.bounds0, false) > 0)) return false;
    if (!motion) return true;
    ++work.planeTests;
    return lineDistance(l, clip.bounds1, false) > 0;
}

bool insideLineInterval(const HomogeneousLine& l, const LBBox& clip, TimeRange& inside,
                        RasterWork& work) {
    work.planeTests += 2;
    const float d0 = lineDistance(l, clip.bounds0, false),
                d1 = lineDistance(l, clip.bounds1, false);
    inside = TimeRange::shutter();
    if (d0 > 0 && d1 > 0) return false;
    if (d0 > 0 || d1 > 0) ++work.timeIntervals;
    if (d0 > 0) inside.lower = std::max(0.0f, d0 / (d0 - d1) - kTimeGuard);
    if (d1 > 0) inside.upper = std::min(1.0f, d0 / (d0 - d1) + kTimeGuard);
    return true;
}

// Outside when sign * ((A - o) / W + o / F - edge) > 0, times W > 0.
HomogeneousLine sideLine(int axis, float sign, float edge, float lensOffset, float focus) {
    HomogeneousLine l;
    l.axis = axis;
    l.a = sign;
    l.b = sign * ((focus > 0 ? lensOffset / focus : 0.0f) - edge);
    l.c = -sign * lensOffset;
    return l;
}

// ---- 2D ----

// The shutter time at which a corner with depth ratio r reaches blend parameter tau.
float timeOfBlend(float tau, float r) {
    if (!(tau > 0.0f)) return 0.0f;
    if (!(tau < 1.0f)) return 1.0f;
    return tau / (r * (1.0f - tau) + tau);
}

}  // namespace

LBBox toHomogeneous(const LBBox& b) {
    LBBox clip;
    for (int end = 0; end < 2; ++end) {
        const Box3& in = end == 0 ? b.bounds0 : b.bounds1;
        Box3& out = end == 0 ? clip.bounds0 : clip.bounds1;
        out.lower = {in.lower.x, in.lower.y, -in.upper.z};
        out.upper = {in.upper.x, in.upper.y, -in.lower.z};
    }
    return clip;
}

HomogeneousFrustum makeHomogeneousFrustum(const Camera& camera, const LensModel& lens,
                                          const TileRect& tile, float farDepth) {
    HomogeneousFrustum f;
    float edges[4];
    tileEdges(camera, tile, edges);
    const float signs[4] = {-1, 1, -1, 1};
    const float focus = lens.radius > 0 ? lens.focusDistance : 0.0f;
    f.planesPerSide = lens.radius > 0 ? 2 : 1;
    for (int side = 0; side < 4; ++side) {
        const int axis = side / 2;
        if (lens.radius > 0) {
            f.sides[side][0] = sideLine(axis, signs[side], edges[side], -lens.radius, focus);
            f.sides[side][1] = sideLine(axis, signs[side], edges[side], lens.radius, focus);
        } else {
            f.sides[side][0] = sideLine(axis, signs[side], edges[side], 0.0f, 0.0f);
        }
    }
    f.nearLine = {2, 0.0f, -1.0f, camera.nearPlane()};  // W < near
    f.farLine = {2, 0.0f, 1.0f, -farDepth};             // W > far
    return f;
}

bool overlapsHomogeneous(const HomogeneousFrustum& f, const LBBox& clip, bool motion,
                         RasterWork& work) {
    if (clip.empty()) return false;
    for (int side = 0; side < 4; ++side) {
        bool outside = true;
        for (int k = 0; k < f.planesPerSide && outside; ++k)
            outside = outsideLineAtBothEnds(f.sides[side][k], clip, motion, work);
        if (outside) return false;
    }
    if (f.testNearFar) {
        if (outsideLineAtBothEnds(f.nearLine, clip, motion, work)) return false;
        if (outsideLineAtBothEnds(f.farLine, clip, motion, work)) return false;
    }
    return true;
}

bool homogeneousTimeInterval(const HomogeneousFrustum& f, const LBBox& clip, TimeRange& times,
                             RasterWork& work) {
    if (clip.empty()) return false;
    auto narrow = [&](const HomogeneousLine* lines, int count) {
        TimeRange side = TimeRange::empty();
        for (int k = 0; k < count; ++k) {
            TimeRange inside;
            if (insideLineInterval(lines[k], clip, inside, work)) side.extend(inside);
        }
        times.intersect(side);
        return !times.isEmpty();
    };
    for (int side = 0; side < 4; ++side)
        if (!narrow(f.sides[side], f.planesPerSide)) return false;
    if (f.testNearFar) {
        if (!narrow(&f.nearLine, 1)) return false;
        if (!narrow(&f.farLine, 1)) return false;
    }
    return true;
}

bool insideNearFarHomogeneous(const HomogeneousFrustum& f, const LBBox& clip, RasterWork& work) {
    work.planeTests += 4;
    for (const HomogeneousLine* l : {&f.nearLine, &f.farLine}) {
        if (lineDistance(*l, clip.bounds0, true) > 0) return false;
        if (lineDistance(*l, clip.bounds1, true) > 0) return false;
    }
    return true;
}

ScreenMovingBox projectMovingBox(const LBBox& b, const Camera& camera, const LensModel& lens) {
    ScreenMovingBox s;
    if (b.empty()) return s;
    s.empty = false;
    float nearDepth[2], farDepth[2];
    for (int end = 0; end < 2; ++end) {
        const Box3& box = end == 0 ? b.bounds0 : b.bounds1;
        nearDepth[end] = -box.upper.z;
        farDepth[end] = -box.lower.z;
        if (!(nearDepth[end] >= camera.nearPlane()) || !std::isfinite(farDepth[end])) return s;
        // The circle of confusion is largest at an end of the depth range (1/depth is monotone).
        const float inverseFocus = lens.radius > 0 ? 1.0f / lens.focusDistance : 0.0f;
        const float blur = lens.radius * std::max(std::abs(1.0f / nearDepth[end] - inverseFocus),
                                                  std::abs(1.0f / farDepth[end] - inverseFocus));
        Vec2 lo(1e30f), hi(-1e30f);
        for (int c = 0; c < 8; ++c) {
            const Vec3 p = box.corner(c);
            const Vec2 q(p.x / -p.z, p.y / -p.z);
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        (end == 0 ? s.lower0 : s.lower1) = lo - blur;
        (end == 0 ? s.upper0 : s.upper1) = hi + blur;
    }
    // Corners keep their depth face: the nearest face at t=0 is the nearest at t=1.
    const float rNear = nearDepth[1] / nearDepth[0], rFar = farDepth[1] / farDepth[0];
    s.ratioMin = std::min(rNear, rFar);
    s.ratioMax = std::max(rNear, rFar);
    s.nearDepth0 = nearDepth[0];
    s.nearDepth1 = nearDepth[1];
    s.bounded = true;
    return s;
}

ScreenTile makeScreenTile(const Camera& camera, const TileRect& tile, float farDepth) {
    float edges[4];
    tileEdges(camera, tile, edges);
    return {edges[0], edges[1], edges[2], edges[3], farDepth};
}

bool overlapsScreenTile(const ScreenTile& t, const ScreenMovingBox& b, bool motion,
                        RasterWork& work) {
    if (b.empty) return false;
    if (!b.bounded) return true;
    work.planeTests += motion ? 10 : 5;
    const bool left = b.upper0.x < t.x0 && (!motion || b.upper1.x < t.x0);
    const bool right = b.lower0.x > t.x1 && (!motion || b.lower1.x > t.x1);
    const bool bottom = b.upper0.y < t.y0 && (!motion || b.upper1.y < t.y0);
    const bool top = b.lower0.y > t.y1 && (!motion || b.lower1.y > t.y1);
    const bool far = b.nearDepth0 > t.farDepth && (!motion || b.nearDepth1 > t.farDepth);
    return !(left || right || bottom || top || far);
}

bool screenTileTimes(const ScreenTile& t, const ScreenMovingBox& b, TimeRange& times,
                     RasterWork& work) {
    if (b.empty) return false;
    if (!b.bounded) return true;
    work.planeTests += 10;
    // Each side bounds the blend parameter tau from one end; a side never met rejects.
    const float g[4][2] = {{t.x0 - b.upper0.x, t.x0 - b.upper1.x},
                           {b.lower0.x - t.x1, b.lower1.x - t.x1},
                           {t.y0 - b.upper0.y, t.y0 - b.upper1.y},
                           {b.lower0.y - t.y1, b.lower1.y - t.y1}};
    float tauLower = 0.0f, tauUpper = 1.0f;
    for (const auto& side : g) {
        float lo, hi;
        if (!nonPositiveRange(side[0], side[1], lo, hi)) return false;
        if (lo > 0 || hi < 1) ++work.timeIntervals;
        tauLower = std::max(tauLower, lo);
        tauUpper = std::min(tauUpper, hi);
    }
    TimeRange seen{std::max(0.0f, timeOfBlend(tauLower, b.ratioMax) - kTimeGuard),
                   std::min(1.0f, timeOfBlend(tauUpper, b.ratioMin) + kTimeGuard)};
    float lo, hi;
    if (!nonPositiveRange(b.nearDepth0 - t.farDepth, b.nearDepth1 - t.farDepth, lo, hi))
        return false;
    seen.intersect({std::max(0.0f, lo - kTimeGuard), std::min(1.0f, hi + kTimeGuard)});
    times.intersect(seen);
    return !times.isEmpty();
}

}  // namespace patchsim
