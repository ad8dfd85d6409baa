#include "rasterizer/baselines/bounding_rasterizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>

#include "core/counters.h"
#include "core/parallel.h"
#include "rasterizer/baselines/band_samples.h"
#include "rasterizer/common/conservative_margins.h"
#include "rasterizer/common/lens_triangle.h"
#include "rasterizer/common/screen_hull.h"
#include "rasterizer/common/watertight_triangle.h"
#include "rasterizer/common/z_culling.h"

namespace patchsim {

namespace {

// Three sets of counters from the one list, named by each method's prefix.
#define PATCHSIM_BOUNDING_COUNTER(prefix, field, name, unit, kind, definition, ...) \
    const Counter prefix##_##field{#prefix "/" name, unit, definition, CounterKind::kind};
#define PATCHSIM_BB(...) PATCHSIM_BOUNDING_COUNTER(BB, __VA_ARGS__)
#define PATCHSIM_IV(...) PATCHSIM_BOUNDING_COUNTER(IV, __VA_ARGS__)
#define PATCHSIM_IL(...) PATCHSIM_BOUNDING_COUNTER(IL, __VA_ARGS__)
PATCHSIM_BOUNDING_WORK(PATCHSIM_BB)
PATCHSIM_BOUNDING_WORK(PATCHSIM_IV)
PATCHSIM_BOUNDING_WORK(PATCHSIM_IL)
#define PATCHSIM_BB_REF(field, ...) BB_##field,
#define PATCHSIM_IV_REF(field, ...) IV_##field,
#define PATCHSIM_IL_REF(field, ...) IL_##field,
const BoundingCounters kTriangleBBox{PATCHSIM_BOUNDING_WORK(PATCHSIM_BB_REF)};
const BoundingCounters kInterval{PATCHSIM_BOUNDING_WORK(PATCHSIM_IV_REF)};
const BoundingCounters kInterleaved{PATCHSIM_BOUNDING_WORK(PATCHSIM_IL_REF)};
// Registered with the others at start-up, so every process lists the counters in one order.
const Counter kIntervalTimeStrata{"IV/Time strata", "strata",
                                  "The interval method's K: shutter strata, each with its own "
                                  "bounds per triangle (the largest of the process's renders)",
                                  CounterKind::Max};

}  // namespace

int intervalTimeStrata(int requested, int samplesPerPixel, bool motion) {
    if (!motion) return 1;
    return requested > 0 ? requested : std::max(samplesPerPixel, 1);
}

const Counter& intervalTimeStrataCounter() {
    return kIntervalTimeStrata;
}

const char* triangleBoundName(TriangleBound bound) {
    switch (bound) {
        case TriangleBound::Hull:
            return "hull";
        case TriangleBound::OrientedBox:
            return "oriented";
        case TriangleBound::Box:
            return "box";
    }
    return "";
}

bool parseTriangleBound(const std::string& name, TriangleBound& out) {
    for (TriangleBound b : {TriangleBound::Hull, TriangleBound::OrientedBox, TriangleBound::Box})
        if (name == triangleBoundName(b)) {
            out = b;
            return true;
        }
    return false;
}

const BoundingCounters& boundingCounters(Bounding m) {
    return m == Bounding::TriangleBBox ? kTriangleBBox
           : m == Bounding::Interval   ? kInterval
                                       : kInterleaved;
}

namespace {

// Pixels [x0, x1) x [y0, y1).
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// Screen-plane (z = -1) bounds, grown point by point.
struct ScreenBox {
    float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
    bool fullScreen = false;

    // A point seen through the whole lens: its image spread by its circle of confusion.
    void addAcrossLens(const Vec3& p, const Camera& camera, const LensModel& lens) {
        const float depth = -p.z;
        if (!(depth >= camera.nearPlane()) || !std::isfinite(depth)) {
            fullScreen = true;
            return;
        }
        const float blur = lens.radius * std::abs(1.0f / depth - 1.0f / lens.focusDistance);
        add(p.x / depth, p.y / depth, blur);
    }
    // A point seen from one lens point (radius-scaled disk position `l`).
    void addFromLensPoint(const Vec3& p, Vec2 l, const Camera& camera, const LensModel& lens) {
        const float depth = -p.z;
        if (!(depth >= camera.nearPlane()) || !std::isfinite(depth)) {
            fullScreen = true;
            return;
        }
        const float focus = lens.radius > 0 ? 1.0f / lens.focusDistance : 0.0f;
        add((p.x - l.x) / depth + l.x * focus, (p.y - l.y) / depth + l.y * focus, 0.0f);
    }
    void add(float sx, float sy, float r) {
        lo[0] = std::min(lo[0], sx - r);
        hi[0] = std::max(hi[0], sx + r);
        lo[1] = std::min(lo[1], sy - r);
        hi[1] = std::max(hi[1], sy + r);
    }

    // The pixels whose samples may fall inside (one pixel of slack: samples reach the far edge).
    PixelRect pixels(const Camera& camera) const {
        const int w = camera.width(), h = camera.height();
        if (fullScreen) return {0, 0, w, h};
        const float tanX = camera.tanHalfFovY() * camera.aspect(), tanY = camera.tanHalfFovY();
        const float x0 = (lo[0] / tanX + 1.0f) * 0.5f * float(w) - kScreenBoundsMarginPixels;
        const float x1 = (hi[0] / tanX + 1.0f) * 0.5f * float(w) + kScreenBoundsMarginPixels;
        const float y0 = (1.0f - hi[1] / tanY) * 0.5f * float(h) - kScreenBoundsMarginPixels;
        const float y1 = (1.0f - lo[1] / tanY) * 0.5f * float(h) + kScreenBoundsMarginPixels;
        if (!(x0 <= x1) || !(y0 <= y1) || x1 < 0 || y1 < 0 || x0 > float(w) || y0 > float(h))
            return {};
        return {std::clamp(int(std::floor(x0)), 0, w), std::clamp(int(std::floor(y0)), 0, h),
                std::clamp(int(std::floor(x1)) + 1, 0, w),
                std::clamp(int(std::floor(y1)) + 1, 0, h)};
    }
};

class BandRasterizer {
  public:
    BandRasterizer(const RayCaster& caster, const VisibilityTargets& targets,
                   const BoundingOptions& options, int y0, int y1,
                   RegionTraceWriter* trace = nullptr)
        : trace_(trace),
          c_(caster),
          t_(targets),
          o_(options),
          y0_(y0),
          y1_(y1),
          width_(targets.opaque->width()),
          spp_(targets.opaque->samplesPerPixel()),
          bandOffset_(std::size_t(y0) * std::size_t(width_) * std::size_t(spp_)),
          samples_(caster, width_, spp_, y0, y1,
                   options.method == Bounding::Interval ? options.timeStrata : 0),
          candidates_(std::size_t(width_) * std::size_t(spp_)) {}

    void triangle(const MovingMesh& mesh, std::uint32_t tri, BoundingWork& work) {
        const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
        if (behindNearPlane(mesh, v)) {
            ++work.triangleSetups;  // the six depths read and compared
            ++work.trianglesCulled;
            return;
        }
        const int spp = t_.opaque->samplesPerPixel();
        if (samples_.hasSubpixels() && screenTriangle(mesh, tri, work)) return;
        if (samples_.hasLensPoints() && lensTriangle(mesh, tri, work)) return;
        switch (o_.method) {
            case Bounding::TriangleBBox:
                if (o_.bound != TriangleBound::Box)
                    hullBounds(mesh, tri, spp, work);
                else
                    testRect(mesh, tri, spanBounds(mesh, v, 0.0f, 1.0f, work), 0, spp, -1, work);
                break;
            case Bounding::Interval:
                for (int k = 0; k < o_.timeStrata; ++k) {
                    const float ta = std::max(0.0f, float(k) / float(o_.timeStrata) - kTimeGuard);
                    const float tb =
                        std::min(1.0f, float(k + 1) / float(o_.timeStrata) + kTimeGuard);
                    testRect(mesh, tri, spanBounds(mesh, v, ta, tb, work), 0, spp, k, work);
                }
                break;
            case Bounding::Interleaved:
                for (int s = 0; s < spp; ++s) {
                    const Sample pass = c_.samples.sample(0, 0, s);  // the same in every pixel
                    ScreenBox box;
                    const Vec2 l = c_.lens.radius * concentricDisk(pass.lens);
                    for (int k = 0; k < 3; ++k)
                        box.addFromLensPoint(mesh.vertexAt(v[k], pass.time), l, c_.camera, c_.lens);
                    ++work.triangleSetups;
                    work.fullScreenBounds += box.fullScreen;
                    testRect(mesh, tri, box.pixels(c_.camera), s, s + 1, -1, work);
                }
                break;
        }
    }

  private:
    // A static frame: every method's bound is the triangle's pixel box, and its samples are
    // tested with edge functions (screen_triangle.h), as the patch method and the reference test
    // them; the interleaved method's accumulation buffer sets the triangle up once per pass (the
    // simulator computes it once) and tests that pass's sample. False when the triangle has no
    // screen form: it then takes the method's rays.
    bool screenTriangle(const MovingMesh& mesh, std::uint32_t tri, BoundingWork& work) {
        const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
        const ScreenTriangle t = setupScreenTriangle(c_.camera, mesh.position0[v[0]],
                                                     mesh.position0[v[1]], mesh.position0[v[2]]);
        if (t.kind == ScreenTriangle::Kind::NeedsRay) return false;
        const bool perPass = o_.method == Bounding::Interleaved;
        for (int pass = 0; pass < (perPass ? spp_ : 1); ++pass) {
            ++work.screenTriangleSetups;
            if (t.kind == ScreenTriangle::Kind::Covers)
                screenSamples(mesh, tri, t, perPass ? pass : 0, perPass ? pass + 1 : spp_, work);
        }
        return true;
    }

    // Samples [s0, s1) of the pixels of the triangle's box in this band.
    void screenSamples(const MovingMesh& mesh, std::uint32_t tri, const ScreenTriangle& t, int s0,
                       int s1, BoundingWork& work) {
        const auto cover = [&](std::size_t i, float nearPlane, float depthMax, ScreenHit& hit) {
            return coverSample(t, samples_.subpixelX(i), samples_.subpixelY(i), nearPlane, depthMax,
                               hit);
        };
        work.edgeTests += edgeSamples(mesh, tri, {t.pixelX0, t.pixelY0, t.pixelX1, t.pixelY1}, s0,
                                      s1, cover, work);
    }

    // Samples [s0, s1) of `pixels` in this band (of each row's pixels `hull` reaches, if given),
    // each tested by `cover(i, near, depthMax, hit)`; returns how many.
    template <class Cover>
    std::int64_t edgeSamples(const MovingMesh& mesh, std::uint32_t tri, const PixelRect& pixels,
                             int s0, int s1, const Cover& cover, BoundingWork& work,
                             const ScreenHull* hull = nullptr) {
        std::int64_t tested = 0;
        for (int y = std::max(pixels.y0, y0_); y < std::min(pixels.y1, y1_); ++y) {
            int xBegin = pixels.x0, xEnd = pixels.x1;
            if (hull != nullptr && !hullRow(*hull, y, xBegin, xEnd)) continue;
            for (int x = xBegin; x < xEnd; ++x)
                for (int s = s0; s < s1; ++s) {
                    const std::size_t i = samples_.index(y - y0_, x, s);
                    ++tested;
                    if (trace_) trace_->read(bandOffset_ + i);
                    const float perLambda = samples_.depthPerLambda(i);
                    const float depthMax =
                        rayEndAtDepth(t_.opaque->depthBound(t_.opaque->records()[bandOffset_ + i]),
                                      perLambda) *
                        perLambda;
                    ScreenHit hit;
                    if (cover(i, samples_.lambdaMin(i) * perLambda, depthMax, hit))
                        recordDepth(mesh, tri, i, hit.depth, hit.b1, hit.b2, work);
                }
        }
        work.samplesTested += tested;
        return tested;
    }

    // A defocus-only frame: every method's bound is the triangle's pixels across the lens (the
    // interleaved method's, those seen from its pass's lens point; triangle-bbox's, with its hull
    // or oriented-box bound, the rows' pixels that bound reaches), and its samples are tested
    // with the lens edge functions (lens_triangle.h), as the patch method and the reference test
    // them. False when the triangle has no lens form: it then takes the method's rays.
    bool lensTriangle(const MovingMesh& mesh, std::uint32_t tri, BoundingWork& work) {
        const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
        const LensTriangle t = setupLensTriangle(c_.camera, c_.lens, mesh.position0[v[0]],
                                                 mesh.position0[v[1]], mesh.position0[v[2]]);
        if (t.kind == LensTriangle::Kind::NeedsRay) return false;
        if (o_.method != Bounding::Interleaved) {
            ++work.lensTriangleSetups;
            if (t.kind != LensTriangle::Kind::Covers) return true;
            ScreenHull hull;
            const bool useHull = o_.method == Bounding::TriangleBBox &&
                                 o_.bound != TriangleBound::Box && hullAcrossLens(t, hull);
            lensSamples(mesh, tri, t, t.pixels, 0, spp_, work, useHull ? &hull : nullptr);
            return true;
        }
        for (int pass = 0; pass < spp_; ++pass) {
            ++work.lensTriangleSetups;
            if (t.kind != LensTriangle::Kind::Covers) continue;
            const Vec2 l = c_.lens.radius * concentricDisk(c_.samples.sample(0, 0, pass).lens);
            lensSamples(mesh, tri, t, lensPixelsFrom(c_.camera, t, l.x, l.y), pass, pass + 1, work);
        }
        return true;
    }

    // The hull (or least-area rectangle) of the lens triangle's vertices' circles of confusion,
    // which holds its image from every lens point; false when it cannot be built.
    bool hullAcrossLens(const LensTriangle& t, ScreenHull& hull) const {
        for (int k = 0; k < 3; ++k)
            hull.addBlurredPoint(double(t.x[k]), double(t.y[k]),
                                 double(c_.lens.radius) * std::abs(double(t.blur[k])));
        return buildBound(hull);
    }

    // The hull of the points added, or with the oriented-box bound the least-area rectangle
    // holding it, grown by the screen bounds' margin; false when it cannot be built.
    bool buildBound(ScreenHull& hull) const {
        const double margin = double(kScreenBoundsMarginPixels) * screenUnitsPerPixel(c_.camera);
        return o_.bound == TriangleBound::OrientedBox ? hull.buildOrientedBox(margin)
                                                      : hull.build(margin);
    }

    // Samples [s0, s1) of `pixels` in this band (of each row's pixels `hull` reaches, if given).
    void lensSamples(const MovingMesh& mesh, std::uint32_t tri, const LensTriangle& t,
                     const LensPixels& pixels, int s0, int s1, BoundingWork& work,
                     const ScreenHull* hull = nullptr) {
        const auto cover = [&](std::size_t i, float nearPlane, float depthMax, ScreenHit& hit) {
            const Vec2 screen = samples_.screen(i), lensPoint = samples_.lensPoint(i);
            return coverLensSample(t, screen.x, screen.y, lensPoint.x, lensPoint.y, nearPlane,
                                   depthMax, hit);
        };
        work.lensEdgeTests += edgeSamples(mesh, tri, {pixels.x0, pixels.y0, pixels.x1, pixels.y1},
                                          s0, s1, cover, work, hull);
    }

    // Every vertex nearer than the near plane (depth < near) at t=0 and at t=1. Each vertex moves
    // on a segment and the triangle is the convex hull of its vertices, so the triangle stays in
    // that half-space for the whole shutter: no ray meets it at lambda >= lambdaMin. Without this
    // its bounds are the whole screen and every sample is tested for nothing. The test is the patch
    // rasterizer's near-plane test (tile_frustum.cpp: z + near > 0 is outside), so the two
    // methods cull alike.
    bool behindNearPlane(const MovingMesh& mesh, const std::uint32_t* v) const {
        const float nearPlane = c_.camera.nearPlane();
        for (int k = 0; k < 3; ++k)
            if (!(mesh.position0[v[k]].z + nearPlane > 0) ||
                !(mesh.position1[v[k]].z + nearPlane > 0))
                return false;
        return true;
    }

    // The screen box of the six vertex positions across the whole lens: one triangle set-up.
    ScreenBox boxAcrossLens(const std::array<Vec3, 6>& points, BoundingWork& work) const {
        ScreenBox box;
        for (const Vec3& p : points) box.addAcrossLens(p, c_.camera, c_.lens);
        ++work.triangleSetups;
        work.fullScreenBounds += box.fullScreen;
        return box;
    }

    PixelRect spanBounds(const MovingMesh& mesh, const std::uint32_t* v, float ta, float tb,
                         BoundingWork& work) const {
        return boxAcrossLens(
                   {mesh.vertexAt(v[0], ta), mesh.vertexAt(v[0], tb), mesh.vertexAt(v[1], ta),
                    mesh.vertexAt(v[1], tb), mesh.vertexAt(v[2], ta), mesh.vertexAt(v[2], tb)},
                   work)
            .pixels(c_.camera);
    }

    // McGuire et al.'s bound: the hull of the vertices' circles of confusion at both shutter ends
    // (or the least-area rectangle that holds it), walked row by row; a sample of the pixels it
    // reaches is ray-tested only inside it. A triangle reaching in front of the near plane, or
    // whose hull has no area (seen edge-on), keeps the box.
    void hullBounds(const MovingMesh& mesh, std::uint32_t tri, int spp, BoundingWork& work) {
        const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
        const ScreenBox box =
            boxAcrossLens({mesh.position0[v[0]], mesh.position1[v[0]], mesh.position0[v[1]],
                           mesh.position1[v[1]], mesh.position0[v[2]], mesh.position1[v[2]]},
                          work);
        // Every band meets every triangle: the hull only where the box reaches this band's rows.
        const PixelRect rect = box.pixels(c_.camera);
        if (rect.y1 <= y0_ || rect.y0 >= y1_) return;
        ScreenHull hull;
        bool useHull = !box.fullScreen;  // else some vertex has no finite projection
        const float inverseFocus = c_.lens.radius > 0 ? 1.0f / c_.lens.focusDistance : 0.0f;
        for (int k = 0; k < 3 && useHull; ++k)
            for (const Vec3& p : {mesh.position0[v[k]], mesh.position1[v[k]]}) {
                const float depth = -p.z;
                hull.addBlurredPoint(
                    double(p.x / depth), double(p.y / depth),
                    double(c_.lens.radius * std::abs(1.0f / depth - inverseFocus)));
            }
        useHull = useHull && buildBound(hull);
        testRect(mesh, tri, rect, 0, spp, -1, work, useHull ? &hull : nullptr);
    }

    // Samples [s0, s1) of every pixel of `rect` in this band (of time stratum `stratum` if >= 0;
    // inside `hull` if given), a row's candidates tested together.
    void testRect(const MovingMesh& mesh, std::uint32_t tri, const PixelRect& rect, int s0, int s1,
                  int stratum, BoundingWork& work, const ScreenHull* hull = nullptr) {
        const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
        const MovingTriangle moving{
            {mesh.position0[v[0]], mesh.position0[v[1]], mesh.position0[v[2]]},
            {mesh.position1[v[0]], mesh.position1[v[1]], mesh.position1[v[2]]}};
        for (int y = std::max(rect.y0, y0_); y < std::min(rect.y1, y1_); ++y) {
            int xBegin = rect.x0, xEnd = rect.x1;
            if (hull != nullptr && !hullRow(*hull, y, xBegin, xEnd)) continue;
            const int row = y - y0_;
            candidates_.clear();
            for (int x = xBegin; x < xEnd; ++x) {
                if (stratum < 0) {
                    for (int s = s0; s < s1; ++s)
                        consider(mesh, tri, samples_.index(row, x, s), hull, work);
                    continue;
                }
                std::size_t first = 0, last = 0;
                samples_.stratumRange(row, x, stratum, first, last);
                for (std::size_t p = first; p < last; ++p)
                    consider(mesh, tri, samples_.index(row, x, samples_.stratumSample(p)), hull,
                             work);
            }
            const int hits = candidates_.test(samples_, moving);
            for (int h = 0; h < hits; ++h) {
                const CandidateHit& hit = candidates_.hits()[h];
                record(mesh, tri, std::size_t(candidates_.sample(hit.candidate)), hit.lambda,
                       hit.b1, hit.b2, work);
            }
        }
    }

    // Band sample i against the triangle (if inside `hull`, when given): listed for the vector
    // test, or tested here when its ray does not shear along z.
    void consider(const MovingMesh& mesh, std::uint32_t tri, std::size_t i, const ScreenHull* hull,
                  BoundingWork& work) {
        if (hull != nullptr && !hull->contains(samples_.screen(i))) {
            ++work.samplesOutsideHull;
            return;
        }
        ++work.samplesTested;
        ++work.rayTriangleTests;
        if (trace_) trace_->read(bandOffset_ + i);
        const float lambdaMax =
            rayEndAtDepth(t_.opaque->depthBound(t_.opaque->records()[bandOffset_ + i]),
                          samples_.depthPerLambda(i));
        if (samples_.alongZ(i)) {
            candidates_.add(std::int32_t(i), lambdaMax);
            return;
        }
        const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
        const float time = samples_.time(i);
        TriangleHit hit;
        if (intersectTriangle(samples_.shearedRay(i), mesh.vertexAt(v[0], time),
                              mesh.vertexAt(v[1], time), mesh.vertexAt(v[2], time),
                              samples_.lambdaMin(i), lambdaMax, hit))
            record(mesh, tri, i, hit.lambda, hit.b1, hit.b2, work);
    }

    // A hit of band sample i: to its layers (a transparent mesh) or its nearest so far.
    void record(const MovingMesh& mesh, std::uint32_t tri, std::size_t i, float lambda, float b1,
                float b2, BoundingWork& work) {
        recordDepth(mesh, tri, i, lambda * samples_.depthPerLambda(i), b1, b2, work);
    }

    void recordDepth(const MovingMesh& mesh, std::uint32_t tri, std::size_t i, float depth,
                     float b1, float b2, BoundingWork& work) {
        const VisibilityRecord hit{depth,           mesh.patchId, tri, b1, b2, samples_.time(i),
                                   samples_.lens(i)};
        const std::size_t at = bandOffset_ + i;
        if (!mesh.opaque && t_.transparent != nullptr) {
            ++work.transparentFragments;
            if (!offerToLayers(*t_.transparent, at, t_.pool, {hit, mesh.objectId}, trace_))
                ++work.transparentOverflow;
            return;
        }
        VisibilityRecord& nearest = t_.opaque->mutableRecords()[at];
        if (hit.nearerThan(nearest)) {
            ++work.visibilitySamples;
            nearest = hit;
            if (trace_) trace_->wrote(at);
        }
    }

    // Narrows [xBegin, xEnd) to the pixels of row y that the hull reaches, as a rasterizer walks a
    // polygon row by row; false when it reaches none.
    bool hullRow(const ScreenHull& hull, int y, int& xBegin, int& xEnd) const {
        const Camera& camera = c_.camera;
        const double tanY = camera.tanHalfFovY(), tanX = tanY * camera.aspect();
        const double w = camera.width(), h = camera.height();
        const double top = (1.0 - 2.0 * y / h) * tanY, bottom = (1.0 - 2.0 * (y + 1) / h) * tanY;
        double xa = 0, xb = 0;
        if (!hull.xRangeInStrip(bottom, top, xa, xb)) return false;
        const double rasterA = (xa / tanX + 1.0) * 0.5 * w, rasterB = (xb / tanX + 1.0) * 0.5 * w;
        xBegin = std::max(xBegin, int(std::clamp(std::floor(rasterA), -1.0, w)));
        xEnd = std::min(xEnd, int(std::clamp(std::floor(rasterB), -1.0, w)) + 1);
        return xBegin < xEnd;
    }

    RegionTraceWriter* trace_;  // when the hardware models memory
    const RayCaster& c_;
    const VisibilityTargets& t_;
    const BoundingOptions& o_;
    int y0_, y1_;
    int width_, spp_;
    std::size_t bandOffset_;  // the band's first sample in the visibility buffer
    BandSamples samples_;
    CandidateList candidates_;  // a row's samples to test against the current triangle
};

}  // namespace

const RatioCounter& boundingSampleTestEfficiency(Bounding method) {
    static const RatioCounter ratios[3] = {
        {"BB/Sample test efficiency", "Visibility samples per sample tested",
         kTriangleBBox.visibilitySamples, kTriangleBBox.samplesTested},
        {"IV/Sample test efficiency", "Visibility samples per sample tested",
         kInterval.visibilitySamples, kInterval.samplesTested},
        {"IL/Sample test efficiency", "Visibility samples per sample tested",
         kInterleaved.visibilitySamples, kInterleaved.samplesTested}};
    return ratios[int(method)];
}

void BoundingWork::add(const BoundingWork& other) {
    PATCHSIM_BOUNDING_WORK(PATCHSIM_WORK_ADD)
}

void BoundingWork::flush(Bounding method) const {
    const BoundingCounters& c = boundingCounters(method);
#define PATCHSIM_BOUNDING_FLUSH(field, ...) c.field += field;
    PATCHSIM_BOUNDING_WORK(PATCHSIM_BOUNDING_FLUSH)
#undef PATCHSIM_BOUNDING_FLUSH
}

void BoundingWork::charge(PatchOps& ops) const {PATCHSIM_BOUNDING_WORK(PATCHSIM_WORK_CHARGE)}

std::uint64_t boundingBandScratchBytes(int width, int height, int samplesPerPixel, Bounding method,
                                       int threads) {
    constexpr int kBands = FramePartition::kClasses;
    int tallest = 0;
    for (int band = 0; band < kBands; ++band)
        tallest = std::max(tallest, FramePartition::bandBegin(band + 1, height) -
                                        FramePartition::bandBegin(band, height));
    // Checked before the frame's effects are known: counted with a static frame's sub-pixel
    // positions (or a defocus-only frame's lens points), the larger.
    const std::uint64_t perSample =
        BandSamples::bytesPerSample(method == Bounding::Interval, /*planeSamples=*/true);
    const auto atOnce = std::uint64_t(std::clamp(threads, 1, kBands));
    const std::uint64_t rowSamples = std::uint64_t(width) * std::uint64_t(samplesPerPixel);
    return atOnce *
           (std::uint64_t(tallest) * rowSamples * perSample + CandidateList::bytesFor(rowSamples));
}

std::vector<BoundingWork> rasterizeByBounds(const std::vector<MovingMesh>& meshes,
                                            const RayCaster& caster,
                                            const VisibilityTargets& targets,
                                            const BoundingOptions& options) {
    const VisibilityBuffer& buffer = *targets.opaque;
    // Bands of rows in fixed slots, like the patch method's row classes: the same work and image
    // for any thread count. Each band sets its triangles up again; only band 0 counts the setups.
    constexpr int kBands = FramePartition::kClasses;
    std::vector<std::vector<BoundingWork>> bandWork(kBands,
                                                    std::vector<BoundingWork>(meshes.size()));
    const int height = buffer.height();
    parallelFor(kBands, options.threads, [&](int, std::size_t band) {
        if (!options.partition.ownsClass(int(band))) return;
        const int y0 = FramePartition::bandBegin(int(band), height),
                  y1 = FramePartition::bandBegin(int(band) + 1, height);
        VisibilityTargets mine = targets;
        mine.pool = int(band);
        std::optional<RegionTraceWriter> trace;
        if (options.memoryTrace) {
            trace.emplace(*options.memoryTrace);
            trace->beginRegion(band);
        }
        BandRasterizer rasterizer(caster, mine, options, y0, y1, trace ? &*trace : nullptr);
        for (std::size_t i = 0; i < meshes.size(); ++i) {
            BoundingWork& work = bandWork[band][i];
            for (std::uint32_t tri = 0; tri < meshes[i].triangleCount(); ++tri) {
                if (trace) trace->beginPass(std::uint32_t(i));
                rasterizer.triangle(meshes[i], tri, work);
                if (trace) trace->endPass();
            }
            if (band != 0)  // counted once
                work.triangleSetups = work.screenTriangleSetups = work.lensTriangleSetups =
                    work.fullScreenBounds = work.trianglesCulled = 0;
        }
    });
    std::vector<BoundingWork> perMesh(meshes.size());
    for (const auto& band : bandWork)
        for (std::size_t i = 0; i < meshes.size(); ++i) perMesh[i].add(band[i]);
    return perMesh;
}

}  // namespace patchsim
