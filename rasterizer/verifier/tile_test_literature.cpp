// Tile tests from the literature, as verifier variants beside the patent's, on the same cases.
//
// - triangle-bbox (Akenine-Moller et al. 2007; McGuire et al. 2010): the primitive's screen box
//   over the whole shutter and lens; a tile inside it is accepted at every time.
// - triangle-hull (McGuire et al. 2010): the convex hull of the primitive's vertices at both
//   shutter ends, each widened by its circle of confusion (rasterizer/common/screen_hull.h, the
//   bound the triangle-bbox method uses by default), against the tile by separating axes.
// - triangle-oriented-box: the least-area rectangle, in any orientation, that holds that hull
//   (triangle-bbox's --bbox-bound oriented), against the tile by separating axes.
// - interval-K (Fatahalian et al. 2009): the shutter in K strata, a screen box per stratum; the
//   tile's time range is the hull of the strata whose box it overlaps.
// - dual-space (Laine et al. 2011, "Clipless dual-space bounds for faster stochastic
//   rasterization"): time bounds from each vertex's distance to a tile edge line through the eye
//   in clip space, x - gamma w, which is linear in t for linear motion and needs no clipping; lens
//   bounds from the vertex's screen position, which is linear in the lens coordinate. Here the
//   primitive is the box and its vertices are its eight corners.
//
// Bounds over a time span: a corner moving linearly projects, from one lens point, to a point
// moving linearly in tau = t d1 / d(t), and 1/depth is linear in tau too; so its screen position
// plus or minus its circle of confusion R |1/depth - 1/F| is convex (concave) in tau, bounded by
// its values at the ends of the span.

#include <algorithm>
#include <cmath>

#include "rasterizer/common/conservative_margins.h"
#include "rasterizer/common/screen_hull.h"
#include "rasterizer/patent/projected_bounds.h"
#include "rasterizer/verifier/tile_test_variant.h"

namespace patchsim {

namespace {

// Does the box's screen footprint over [ta, tb] and the whole lens meet the tile?
bool spanOverlapsTile(const TileTestInput& in, const ScreenTile& tile, float ta, float tb) {
    Vec2 lo(1e30f), hi(-1e30f);
    const float inverseFocus = in.lens.radius > 0 ? 1.0f / in.lens.focusDistance : 0.0f;
    for (float t : {ta, tb}) {
        const Box3 box = in.box.at(t);
        for (int c = 0; c < 8; ++c) {
            const Vec3 p = box.corner(c);
            const float depth = -p.z;
            if (!(depth >= in.camera->nearPlane())) return true;  // no finite projection
            const float blur = in.lens.radius * std::abs(1.0f / depth - inverseFocus);
            const Vec2 q(p.x / depth, p.y / depth);
            lo = glm::min(lo, q - blur);
            hi = glm::max(hi, q + blur);
        }
    }
    return lo.x <= tile.x1 && hi.x >= tile.x0 && lo.y <= tile.y1 && hi.y >= tile.y0;
}

class TriangleBBox : public TileTestVariant {
  public:
    std::string name() const override { return "triangle-bbox"; }
    TileTestOutput run(const TileTestInput& in) const override {
        const ScreenTile tile = makeScreenTile(*in.camera, in.tile, in.camera->farPlane());
        return {spanOverlapsTile(in, tile, 0.0f, 1.0f)};
    }
};

class TriangleHull : public TileTestVariant {
  public:
    explicit TriangleHull(bool orientedBox) : orientedBox_(orientedBox) {}
    std::string name() const override {
        return orientedBox_ ? "triangle-oriented-box" : "triangle-hull";
    }
    TileTestOutput run(const TileTestInput& in) const override {
        const ScreenTile tile = makeScreenTile(*in.camera, in.tile, in.camera->farPlane());
        const float inverseFocus = in.lens.radius > 0 ? 1.0f / in.lens.focusDistance : 0.0f;
        ScreenHull hull;
        for (const Box3* box : {&in.box.bounds0, &in.box.bounds1})
            for (int c = 0; c < 8; ++c) {
                const Vec3 p = box->corner(c);
                const float depth = -p.z;
                if (!(depth >= in.camera->nearPlane())) return {true};  // no finite projection
                hull.addBlurredPoint(
                    double(p.x / depth), double(p.y / depth),
                    double(in.lens.radius * std::abs(1.0f / depth - inverseFocus)));
            }
        const double margin = double(kScreenBoundsMarginPixels) * screenUnitsPerPixel(*in.camera);
        if (!(orientedBox_ ? hull.buildOrientedBox(margin) : hull.build(margin)))
            return {spanOverlapsTile(in, tile, 0.0f, 1.0f)};
        return {hull.overlapsRect(tile.x0, tile.y0, tile.x1, tile.y1)};
    }

  private:
    bool orientedBox_;
};

class IntervalBounds : public TileTestVariant {
  public:
    explicit IntervalBounds(int strata) : strata_(strata) {}
    std::string name() const override { return "interval-" + std::to_string(strata_); }
    TileTestOutput run(const TileTestInput& in) const override {
        const ScreenTile tile = makeScreenTile(*in.camera, in.tile, in.camera->farPlane());
        TileTestOutput out;
        out.times = TimeRange::empty();
        for (int k = 0; k < strata_; ++k) {
            const float ta = std::max(0.0f, float(k) / float(strata_) - kTimeGuard);
            const float tb = std::min(1.0f, float(k + 1) / float(strata_) + kTimeGuard);
            if (spanOverlapsTile(in, tile, ta, tb)) out.times.extend({ta, tb});
        }
        out.accept = !out.times.isEmpty();
        return out;
    }

  private:
    int strata_;
};

class DualSpaceBounds : public TileTestVariant {
  public:
    std::string name() const override { return "dual-space"; }
    TileTestOutput run(const TileTestInput& in) const override {
        TileTestOutput out;
        out.accept = timeBounds(in, out.times) && lensBounds(in, out.lens);
        return out;
    }

  private:
    // Per edge line (through each lens extreme with a lens), the times some corner is inside:
    // each corner's distance is linear in t, so its inside times are an interval; their hull.
    static bool timeBounds(const TileTestInput& in, TimeRange& times) {
        const HomogeneousFrustum f =
            makeHomogeneousFrustum(*in.camera, in.lens, in.tile, in.camera->farPlane());
        const LBBox clip = toHomogeneous(in.box);
        auto insideTimes = [&](const HomogeneousLine& l) {
            TimeRange any = TimeRange::empty();
            for (int c = 0; c < 8; ++c) {
                const Vec3 p0 = clip.bounds0.corner(c), p1 = clip.bounds1.corner(c);
                const float d0 = (l.axis < 2 ? l.a * p0[l.axis] : 0.0f) + l.b * p0.z + l.c;
                const float d1 = (l.axis < 2 ? l.a * p1[l.axis] : 0.0f) + l.b * p1.z + l.c;
                if (d0 > 0 && d1 > 0) continue;
                TimeRange inside = TimeRange::shutter();
                if (d0 > 0) inside.lower = std::max(0.0f, d0 / (d0 - d1) - kTimeGuard);
                if (d1 > 0) inside.upper = std::min(1.0f, d0 / (d0 - d1) + kTimeGuard);
                any.extend(inside);
            }
            return any;
        };
        for (int side = 0; side < 4; ++side) {
            TimeRange sideTimes = TimeRange::empty();
            for (int k = 0; k < f.planesPerSide; ++k)
                sideTimes.extend(insideTimes(f.sides[side][k]));
            times.intersect(sideTimes);
        }
        times.intersect(insideTimes(f.nearLine));
        times.intersect(insideTimes(f.farLine));
        return !times.isEmpty();
    }

    // Per axis, the lens coordinates from which some corner, at either end of the shutter, is
    // seen right of the tile's left edge, and those from which one is seen left of its right edge.
    static bool lensBounds(const TileTestInput& in, LensRect& lens) {
        if (in.lens.radius <= 0) return true;
        const ScreenTile tile = makeScreenTile(*in.camera, in.tile, in.camera->farPlane());
        const double edges[2][2] = {{tile.x0, tile.x1}, {tile.y0, tile.y1}};
        double range[2][2];
        for (int axis = 0; axis < 2; ++axis) {
            double aboveLow[2] = {INFINITY, -INFINITY}, belowHigh[2] = {INFINITY, -INFINITY};
            for (const Box3* box : {&in.box.bounds0, &in.box.bounds1}) {
                for (int c = 0; c < 8; ++c) {
                    const Vec3 p = box->corner(c);
                    const double depth = -double(p.z);
                    if (!(depth >= in.camera->nearPlane())) return true;  // whole lens
                    // Seen at a + b u from lens coordinate u (units of the radius).
                    const double a = double(p[axis]) / depth;
                    const double b = double(in.lens.radius) *
                                     (1.0 / double(in.lens.focusDistance) - 1.0 / depth);
                    extendHalfLine(a, b, edges[axis][0], +1, aboveLow);
                    extendHalfLine(a, b, edges[axis][1], -1, belowHigh);
                }
            }
            range[axis][0] = std::max({-1.0, aboveLow[0], belowHigh[0]}) - kLensGuard;
            range[axis][1] = std::min({1.0, aboveLow[1], belowHigh[1]}) + kLensGuard;
        }
        lens = {float(range[0][0]), float(range[0][1]), float(range[1][0]), float(range[1][1])};
        return !lens.isEmpty();
    }

    // Extends hull [lo, hi] by the u with sign * (a + b u - edge) >= 0.
    static void extendHalfLine(double a, double b, double edge, int sign, double hull[2]) {
        const double g = sign * (a - edge), slope = sign * b;
        if (slope == 0.0) {
            if (g >= 0.0) hull[0] = -INFINITY, hull[1] = INFINITY;
            return;
        }
        const double root = -g / slope;
        if (slope > 0.0) {  // u >= root
            hull[0] = std::min(hull[0], root);
            hull[1] = INFINITY;
        } else {  // u <= root
            hull[0] = -INFINITY;
            hull[1] = std::max(hull[1], root);
        }
    }

    // Lens coordinates (units of the radius) are widened by this for rounding.
    static constexpr double kLensGuard = 1e-4;
};

}  // namespace

void addLiteratureTileTests(std::vector<std::unique_ptr<TileTestVariant>>& out) {
    out.push_back(std::make_unique<TriangleBBox>());
    out.push_back(std::make_unique<TriangleHull>(false));
    out.push_back(std::make_unique<TriangleHull>(true));
    out.push_back(std::make_unique<IntervalBounds>(4));
    out.push_back(std::make_unique<IntervalBounds>(16));
    out.push_back(std::make_unique<DualSpaceBounds>());
}

}  // namespace patchsim
