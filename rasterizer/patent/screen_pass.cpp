// The edge-function kernel, compiled once per SIMD target (Highway's foreach_target re-includes
// this file).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "rasterizer/patent/screen_pass.cpp"
#include "rasterizer/patent/screen_pass.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <bit>
#include <cstdint>

#include "rasterizer/common/conservative_margins.h"
#include "rasterizer/common/screen_triangle.h"
#include "rasterizer/common/watertight_triangle_rounded.h"
#include "rasterizer/common/z_culling.h"

HWY_BEFORE_NAMESPACE();
namespace patchsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// A small triangle's edge functions are exact in float: 16 samples a vector. A larger one's in
// double: 8, their floats loaded and widened.
using DF = hn::CappedTag<float, 16>;
using VF = hn::Vec<DF>;
using MF = hn::Mask<DF>;
using DD = hn::CappedTag<double, 8>;
using VD = hn::Vec<DD>;
using MD = hn::Mask<DD>;
using DF8 = hn::Rebind<float, DD>;

// The bits of a mask of at most 16 lanes.
template <class D>
HWY_INLINE unsigned bitsOf(D d, hn::Mask<D> m) {
    std::uint8_t bytes[8] = {};
    hn::StoreMaskBits(d, m, bytes);
    return unsigned(bytes[0]) | unsigned(bytes[1]) << 8;
}

template <bool kEveryHit, bool kCount>
class ScreenPass {
  public:
    ScreenPass(TileRays& rays, const StreamPass& pass, const Camera& camera, const LensModel& lens,
               RasterWork& work)
        : rays_(rays),
          pass_(pass),
          camera_(camera),
          lens_(lens),
          mesh_(*pass.mesh),
          work_(work),
          spp_(rays.samplesPerPixel()),
          near_(rays.lambdaMin() * rays.depthPerLambda()) {}

    void run() {
        const TileTraversal& traversal = *pass_.traversal;
        const PatchHierarchy& h = *pass_.hierarchy;
        work_.branchDepthSum += h.levelOf(pass_.branchNode);
        startSamples();
        for (std::uint64_t leaves = traversal.leafMask; leaves; leaves &= leaves - 1) {
            const int leaf = std::countr_zero(leaves);
            std::size_t count = 0;
            const std::uint32_t* triangles = h.leafTriangles(leaf, count);
            const std::uint8_t* corners = h.leafCorners(leaf);
            if (rays_.screenX != nullptr) {
                const LensVertex* vertices = pass_.lensVertices + h.leafVertexOffset(leaf);
                for (std::size_t k = 0; k < count; ++k)
                    lensTriangle(triangles[k], vertices[corners[3 * k]],
                                 vertices[corners[3 * k + 1]], vertices[corners[3 * k + 2]]);
                continue;
            }
            const ScreenVertex* vertices = pass_.screenVertices + h.leafVertexOffset(leaf);
            for (std::size_t k = 0; k < count; ++k)
                triangle(triangles[k], vertices[corners[3 * k]], vertices[corners[3 * k + 1]],
                         vertices[corners[3 * k + 2]]);
        }
        work_.edgeTests += edgeTests_;
        work_.lensEdgeTests += lensEdgeTests_;
        finish();
    }

  private:
    // Every sample of the tile is considered (there is one time); without z culling each ends at
    // the far plane, or at its depth bound when every hit is kept (ray_stream.cpp's rule).
    void startSamples() {
        const int n = rays_.count();
        work_.samplesTested += n;
        std::fill(rays_.passImproved(), rays_.passImproved() + rays_.padded() / kMaxLanes,
                  std::uint16_t(0));
        if (!pass_.zCulling) {
            const float far = rays_.farDepth(), perLambda = rays_.depthPerLambda();
            for (int i = 0; i < n; ++i) {
                const float bound =
                    kEveryHit && rays_.bestDepth[i] < far ? rays_.bestDepth[i] : far;
                rays_.rayEnd[i] = rayEndAtDepth(bound, perLambda);
            }
        }
        if (kCount)
            for (int i = 0; i < n; ++i) ++rays_.work[std::size_t(SampleWork::Tested)][i];
    }

    void triangle(std::uint32_t tri, const ScreenVertex& a, const ScreenVertex& b,
                  const ScreenVertex& c) {
        ++work_.screenTriangleSetups;
        const ScreenTriangle t = setupScreenTriangle(camera_, a, b, c);
        if (t.kind == ScreenTriangle::Kind::NeedsRay) return withRays(tri);
        if (t.kind == ScreenTriangle::Kind::Empty) return;
        const TileRect& tile = rays_.rect();
        const int x0 = std::max(t.pixelX0, tile.x0), x1 = std::min(t.pixelX1, tile.x1);
        const int y0 = std::max(t.pixelY0, tile.y0), y1 = std::min(t.pixelY1, tile.y1);
        if (x0 >= x1 || y0 >= y1) return;
        if (t.small) {
            const Edges<DF> e(DF(), t);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) smallPixel(e, t, tri, rays_.firstSampleOf(x, y));
        } else {
            const Edges<DD> e(DD(), t);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) largePixel(e, t, tri, rays_.firstSampleOf(x, y));
        }
    }

    // The triangle's constants as vectors of lane type T.
    template <class D>
    struct Edges {
        hn::Vec<D> a[3], b[3], x0[3], y0[3];
        bool owns[3];
        Edges(D d, const ScreenTriangle& t) {
            using T = hn::TFromD<D>;
            for (int i = 0; i < 3; ++i) {
                a[i] = hn::Set(d, T(t.a[i]));
                b[i] = hn::Set(d, T(t.b[i]));
                x0[i] = hn::Set(d, T(t.x0[i]));
                y0[i] = hn::Set(d, T(t.y0[i]));
                owns[i] = t.ownsTies[i];
            }
        }
        // The three edge functions at (x, y) and whether the sample is inside.
        hn::Mask<D> inside(D d, hn::Vec<D> x, hn::Vec<D> y, hn::Vec<D>* edge) const {
            hn::Mask<D> in = hn::Not(hn::FirstN(d, 0));
            for (int k = 0; k < 3; ++k) {
                edge[k] =
                    hn::Add(hn::Mul(a[k], hn::Sub(x, x0[k])), hn::Mul(b[k], hn::Sub(y, y0[k])));
                in = hn::And(in,
                             owns[k] ? hn::Ge(edge[k], hn::Zero(d)) : hn::Gt(edge[k], hn::Zero(d)));
            }
            return in;
        }
    };

    // coverSample (screen_triangle.h) for samples [first, first + spp) of a small triangle, 16
    // at a time: exact edge functions, then interpolateScreenHit's float operations.
    void smallPixel(const Edges<DF>& e, const ScreenTriangle& t, std::uint32_t tri, int first) {
        const DF d;
        const int lanes = int(hn::Lanes(d));
        edgeTests_ += spp_;
        const VF inverseDepth[3] = {hn::Set(d, t.inverseDepth[0]), hn::Set(d, t.inverseDepth[1]),
                                    hn::Set(d, t.inverseDepth[2])};
        for (int i = 0; i < spp_; i += lanes) {
            const MF valid = hn::FirstN(d, std::size_t(std::min(lanes, spp_ - i)));
            if (kCount) countTests(first + i, bitsOf(d, valid));
            VF edge[3];
            const MF inside =
                hn::And(valid, e.inside(d, hn::LoadU(d, rays_.subpixelX + first + i),
                                        hn::LoadU(d, rays_.subpixelY + first + i), edge));
            if (hn::AllFalse(d, inside)) continue;
            const VF w0 = hn::Mul(edge[0], inverseDepth[0]);
            const VF w1 = hn::Mul(edge[1], inverseDepth[1]);
            const VF w2 = hn::Mul(edge[2], inverseDepth[2]);
            const VF inverseSum = hn::Div(hn::Set(d, 1.0f), hn::Add(hn::Add(w0, w1), w2));
            alignas(64) float depth[16], b1[16], b2[16];
            hn::Store(hn::Mul(hn::Set(d, t.area), inverseSum), d, depth);
            hn::Store(hn::Mul(w1, inverseSum), d, b1);
            hn::Store(hn::Mul(w2, inverseSum), d, b2);
            for (unsigned rest = bitsOf(d, inside); rest; rest &= rest - 1) {
                const int lane = std::countr_zero(rest);
                offer(first + i + lane, tri, {depth[lane], b1[lane], b2[lane]});
            }
        }
    }

    // The same for a larger triangle, 8 samples at a time in double; a covered sample's hit from
    // its edge functions rounded to float.
    void largePixel(const Edges<DD>& e, const ScreenTriangle& t, std::uint32_t tri, int first) {
        const DD d;
        const DF8 df;
        const int lanes = int(hn::Lanes(d));
        edgeTests_ += spp_;
        for (int i = 0; i < spp_; i += lanes) {
            const MD valid = hn::FirstN(d, std::size_t(std::min(lanes, spp_ - i)));
            if (kCount) countTests(first + i, bitsOf(d, valid));
            VD edge[3];
            const MD inside = hn::And(
                valid,
                e.inside(d, hn::PromoteTo(d, hn::LoadU(df, rays_.subpixelX + first + i)),
                         hn::PromoteTo(d, hn::LoadU(df, rays_.subpixelY + first + i)), edge));
            if (hn::AllFalse(d, inside)) continue;
            alignas(64) double e0[8], e1[8], e2[8];
            hn::Store(edge[0], d, e0);
            hn::Store(edge[1], d, e1);
            hn::Store(edge[2], d, e2);
            for (unsigned rest = bitsOf(d, inside); rest; rest &= rest - 1) {
                const int lane = std::countr_zero(rest);
                offer(first + i + lane, tri,
                      interpolateScreenHit(t, float(e0[lane]), float(e1[lane]), float(e2[lane])));
            }
        }
    }

    // A defocus-only frame's triangle: set up for the lens edge test, then the samples of the
    // pixels it can cover from the lens, within the tile.
    void lensTriangle(std::uint32_t tri, const LensVertex& a, const LensVertex& b,
                      const LensVertex& c) {
        ++work_.lensTriangleSetups;
        const LensTriangle t = setupLensTriangle(camera_, lens_, a, b, c);
        if (t.kind == LensTriangle::Kind::NeedsRay) return withRays(tri);
        if (t.kind == LensTriangle::Kind::Empty) return;
        const TileRect& tile = rays_.rect();
        const int x0 = std::max(t.pixels.x0, tile.x0), x1 = std::min(t.pixels.x1, tile.x1);
        const int y0 = std::max(t.pixels.y0, tile.y0), y1 = std::min(t.pixels.y1, tile.y1);
        if (x0 >= x1 || y0 >= y1) return;
        const LensEdges e(t);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) lensPixel(e, tri, rays_.firstSampleOf(x, y));
    }

    // A lens triangle's constants as float vectors (lens_triangle.h's names).
    struct LensEdges {
        VF x[3], y[3], blur[3], dx[3], dy[3], dblur[3], inverseDepth[3];
        bool flipped[3];
        explicit LensEdges(const LensTriangle& t) {
            const DF d;
            for (int i = 0; i < 3; ++i) {
                const int from = t.from[i];
                x[i] = hn::Set(d, t.x[from]);
                y[i] = hn::Set(d, t.y[from]);
                blur[i] = hn::Set(d, t.blur[from]);
                dx[i] = hn::Set(d, t.dx[i]);
                dy[i] = hn::Set(d, t.dy[i]);
                dblur[i] = hn::Set(d, t.dblur[i]);
                inverseDepth[i] = hn::Set(d, t.inverseDepth[i]);
                flipped[i] = t.flipped[i];
            }
        }
        // lensEdgeFunction's operations, in its order: edge i oriented (negated when flipped),
        // and whether it is positive at the moved sample, oriented.
        VF oriented(DF d, int i, VF sx, VF sy, VF lx, VF ly, MF& positive) const {
            const VF rx = hn::Sub(sx, x[i]), ry = hn::Sub(sy, y[i]);
            const VF ex = hn::Neg(hn::Add(dy[i], hn::Mul(dblur[i], ly)));
            const VF ey = hn::Add(dx[i], hn::Mul(dblur[i], lx));
            const VF offset = hn::Mul(blur[i], hn::Sub(hn::Mul(lx, dy[i]), hn::Mul(ly, dx[i])));
            const VF e = hn::Add(hn::Add(hn::Mul(rx, ex), hn::Mul(ry, ey)), offset);
            // LensEdgeValue::positive: the sign at the sample moved by (eps, eps^2); a lane
            // exactly on the edge is rare, so its derivatives are read only then.
            const VF zero = hn::Zero(d);
            MF up = hn::Gt(e, zero);
            const MF tie = hn::Eq(e, zero);
            if (!hn::AllFalse(d, tie))
                up = hn::Or(up, hn::And(tie, hn::Or(hn::Gt(ex, zero),
                                                    hn::And(hn::Eq(ex, zero), hn::Gt(ey, zero)))));
            positive = flipped[i] ? hn::Not(up) : up;
            return flipped[i] ? hn::Neg(e) : e;
        }
    };

    // coverLensSample (lens_triangle.h) for samples [first, first + spp), 16 at a time.
    void lensPixel(const LensEdges& e, std::uint32_t tri, int first) {
        const DF d;
        const int lanes = int(hn::Lanes(d));
        lensEdgeTests_ += spp_;
        for (int i = 0; i < spp_; i += lanes) {
            const int at = first + i;
            const MF valid = hn::FirstN(d, std::size_t(std::min(lanes, spp_ - i)));
            if (kCount) countTests(at, bitsOf(d, valid));
            const VF sx = hn::LoadU(d, rays_.screenX + at), sy = hn::LoadU(d, rays_.screenY + at);
            const VF lx = hn::LoadU(d, rays_.originX + at), ly = hn::LoadU(d, rays_.originY + at);
            MF positive[3];
            VF f[3];
            for (int k = 0; k < 3; ++k) f[k] = e.oriented(d, k, sx, sy, lx, ly, positive[k]);
            const MF all = hn::And(hn::And(positive[0], positive[1]), positive[2]);
            const MF none = hn::Not(hn::Or(hn::Or(positive[0], positive[1]), positive[2]));
            const MF inside = hn::And(valid, hn::Or(all, none));
            if (hn::AllFalse(d, inside)) continue;
            const VF w0 = hn::Mul(f[0], e.inverseDepth[0]);
            const VF w1 = hn::Mul(f[1], e.inverseDepth[1]);
            const VF w2 = hn::Mul(f[2], e.inverseDepth[2]);
            const VF inverseSum = hn::Div(hn::Set(d, 1.0f), hn::Add(hn::Add(w0, w1), w2));
            alignas(64) float depth[16], b1[16], b2[16];
            hn::Store(hn::Mul(hn::Add(hn::Add(f[0], f[1]), f[2]), inverseSum), d, depth);
            hn::Store(hn::Mul(w1, inverseSum), d, b1);
            hn::Store(hn::Mul(w2, inverseSum), d, b2);
            for (unsigned rest = bitsOf(d, inside); rest; rest &= rest - 1) {
                const int lane = std::countr_zero(rest);
                offer(at + lane, tri, {depth[lane], b1[lane], b2[lane]});
            }
        }
    }

    // A covered sample's hit, kept if within its ray's range (the depth range of coverSample).
    void offer(int sample, std::uint32_t tri, const ScreenHit& hit) {
        if (rays_.trace != nullptr) rays_.trace->read(rays_.record[sample]);
        if (!(hit.depth >= near_ && hit.depth <= rays_.rayEnd[sample] * rays_.depthPerLambda()))
            return;
        accept(sample, tri, hit.depth, hit.b1, hit.b2);
    }

    void countTests(int first, unsigned valid) {
        for (unsigned rest = valid; rest; rest &= rest - 1)
            ++rays_.work[std::size_t(SampleWork::TriangleTests)][first + std::countr_zero(rest)];
    }

    // A triangle with no screen form: the tile's rays, as the reference tests it.
    void withRays(std::uint32_t tri) {
        const std::uint32_t* v = &mesh_.indices[3 * std::size_t(tri)];
        const int n = rays_.count();
        const NumberFormat& triangleFormat =
            pass_.triangleFormat ? *pass_.triangleFormat : NumberFormat::fp32();
        work_.raysCast += n;
        work_.rayTriangleTests += n;
        if (rays_.trace != nullptr) rays_.traceReads(0, n, TimeRange::shutter());
        for (int i = 0; i < n; ++i) {
            const Ray ray = rays_.ray(i);
            TriangleHit hit;
            if (intersectTriangleIn(triangleFormat, shearRay(ray), mesh_.vertexAt(v[0], ray.time),
                                    mesh_.vertexAt(v[1], ray.time), mesh_.vertexAt(v[2], ray.time),
                                    rays_.lambdaMin(), rays_.rayEnd[i], hit))
                accept(i, tri, hit.lambda * rays_.depthPerLambda(), hit.b1, hit.b2);
        }
    }

    // A hit of sample i within its ray's range: offered to the layers, or kept when nearest.
    void accept(int i, std::uint32_t tri, float depth, float b1, float b2) {
        VisibilityRecord hit;
        hit.depth = depth;
        hit.patch = mesh_.patchOf(tri);
        hit.triangle = mesh_.triangleInPatchOf(tri);
        hit.b1 = b1;
        hit.b2 = b2;
        const auto at = std::size_t(i);
        if constexpr (kEveryHit) {
            hit.time = rays_.time[at];
            hit.lens = {rays_.lensU[at], rays_.lensV[at]};
            ++work_.transparentFragments;
            if (kCount) ++rays_.work[std::size_t(SampleWork::Visible)][at];
            if (!offerToLayers(*pass_.transparent, rays_.record[at], pass_.pool,
                               LayerFragment{hit, mesh_.objectId}, rays_.trace))
                ++work_.transparentOverflow;
        } else {
            VisibilityRecord best;
            best.depth = rays_.bestDepth[at];
            best.patch = rays_.bestPatch[at];
            best.triangle = rays_.bestTriangle[at];
            if (!hit.nearerThan(best)) return;
            rays_.bestDepth[at] = hit.depth;
            rays_.bestPatch[at] = hit.patch;
            rays_.bestTriangle[at] = hit.triangle;
            rays_.bestB1[at] = b1;
            rays_.bestB2[at] = b2;
            // The ray path's rule (TileRays::rayEnd): the nearest hit's end, or the far plane's.
            rays_.rayEnd[at] =
                std::min(rays_.rayEnd[at], rayEndAtDepth(depth, rays_.depthPerLambda()));
            rays_.passImproved()[at / kMaxLanes] |= std::uint16_t(1u << (at % kMaxLanes));
        }
    }

    // Samples whose nearest hit changed in this pass are visibility samples.
    void finish() { work_.visibilitySamples += rays_.commitPass(0, rays_.padded()); }

    TileRays& rays_;
    const StreamPass& pass_;
    const Camera& camera_;
    const LensModel& lens_;
    const MovingMesh& mesh_;
    RasterWork& work_;
    const int spp_;
    const float near_;
    std::int64_t edgeTests_ = 0;
    std::int64_t lensEdgeTests_ = 0;
};

void RasterizeImpl(TileRays& rays, const StreamPass& pass, const Camera& camera,
                   const LensModel& lens, RasterWork& work) {
    const bool everyHit = pass.transparent != nullptr;
    const bool counting = rays.work[0] != nullptr;
    if (everyHit && counting)
        ScreenPass<true, true>(rays, pass, camera, lens, work).run();
    else if (everyHit)
        ScreenPass<true, false>(rays, pass, camera, lens, work).run();
    else if (counting)
        ScreenPass<false, true>(rays, pass, camera, lens, work).run();
    else
        ScreenPass<false, false>(rays, pass, camera, lens, work).run();
}

}  // namespace HWY_NAMESPACE
}  // namespace patchsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace patchsim {

HWY_EXPORT(RasterizeImpl);

void rasterizeScreenPass(TileRays& rays, const StreamPass& pass, const Camera& camera,
                         RasterWork& work) {
    HWY_DYNAMIC_DISPATCH(RasterizeImpl)(rays, pass, camera, LensModel{}, work);
}

void rasterizeLensPass(TileRays& rays, const StreamPass& pass, const Camera& camera,
                       const LensModel& lens, RasterWork& work) {
    HWY_DYNAMIC_DISPATCH(RasterizeImpl)(rays, pass, camera, lens, work);
}

}  // namespace patchsim
#endif
