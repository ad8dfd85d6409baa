// The vector sample test, compiled once per SIMD target (Highway's foreach_target re-includes this
// file); the band's set-up below it, once.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "rasterizer/baselines/band_samples.cpp"
#include "rasterizer/baselines/band_samples.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <bit>
#include <tuple>
#include <utility>

HWY_BEFORE_NAMESPACE();
namespace patchsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::CappedTag<float, kSampleLanes>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;
using MF = hn::Mask<DF>;

// A vertex blended to each lane's time, moved to the ray origin and sheared along z
// (kx = 1, ky = 0, kz = 2): A[kx] - sx A[kz], A[ky] - sy A[kz], sz A[kz], with
// A = lerp(p0, p1, t) - origin, as intersectTriangle computes it.
struct Sheared {
    VF x, y, z;
};

struct LaneRays {
    VF time, weight0, originX, originY, originZ, shearX, shearY, shearZ;
};

HWY_INLINE Sheared shear(const LaneRays& r, const Vec3& p0, const Vec3& p1) {
    const DF d;
    const VF x =
        hn::Sub(hn::Add(hn::Mul(r.weight0, hn::Set(d, p0.x)), hn::Mul(r.time, hn::Set(d, p1.x))),
                r.originX);
    const VF y =
        hn::Sub(hn::Add(hn::Mul(r.weight0, hn::Set(d, p0.y)), hn::Mul(r.time, hn::Set(d, p1.y))),
                r.originY);
    const VF z =
        hn::Sub(hn::Add(hn::Mul(r.weight0, hn::Set(d, p0.z)), hn::Mul(r.time, hn::Set(d, p1.z))),
                r.originZ);
    return {hn::Sub(y, hn::Mul(r.shearX, z)), hn::Sub(x, hn::Mul(r.shearY, z)),
            hn::Mul(r.shearZ, z)};
}

// Lanes with an edge function exactly zero: all three again in double precision.
HWY_NOINLINE void inDouble(MF lanes, const Sheared& a, const Sheared& b, const Sheared& c, VF& u,
                           VF& v, VF& w) {
    const DF d;
    alignas(64) float s[9][kSampleLanes];
    const VF in[9] = {a.x, a.y, b.x, b.y, c.x, c.y, u, v, w};
    for (int k = 0; k < 9; ++k) hn::Store(in[k], d, s[k]);
    alignas(64) std::uint8_t bits[8] = {};
    hn::StoreMaskBits(d, lanes, bits);
    for (unsigned rest = unsigned(bits[0]) | unsigned(bits[1]) << 8; rest; rest &= rest - 1) {
        const int i = std::countr_zero(rest);
        const double ax = s[0][i], ay = s[1][i], bx = s[2][i], by = s[3][i], cx = s[4][i],
                     cy = s[5][i];
        s[6][i] = float(cx * by - cy * bx);
        s[7][i] = float(ax * cy - ay * cx);
        s[8][i] = float(bx * ay - by * ax);
    }
    u = hn::Load(d, s[6]);
    v = hn::Load(d, s[7]);
    w = hn::Load(d, s[8]);
}

template <typename T>
HWY_INLINE VF fetch(DF d, const T* array, VI index, bool contiguous, std::int32_t first) {
    return contiguous ? hn::LoadU(d, array + first) : hn::GatherIndex(d, array, index);
}

int TestImpl(const BandSamples::Lanes& rays, const std::int32_t* indices, const float* lambdaMax,
             int count, const MovingTriangle& tri, CandidateHit* out) {
    const std::int64_t samples = rays.count;
    const DF d;
    const DI di;
    const int lanes = int(hn::Lanes(d));
    const VF zero = hn::Zero(d), one = hn::Set(d, 1.0f);
    int hits = 0;
    for (int i = 0; i < count; i += lanes) {
        const MF active = hn::FirstN(d, std::size_t(count - i));
        const VI index = hn::LoadU(di, indices + i);
        const std::int32_t first = indices[i];
        // Most lists are runs of a pixel's samples and of a row's pixels: a load, not a gather,
        // when every lane (the tail's too: they hold earlier entries) continues the run inside
        // the band's arrays.
        const bool contiguous =
            std::int64_t(first) + lanes <= samples &&
            hn::AllTrue(di, hn::Eq(index, hn::Add(hn::Iota(di, 0), hn::Set(di, first))));
        LaneRays r;
        r.time = fetch(d, rays.time, index, contiguous, first);
        r.weight0 = hn::Sub(one, r.time);  // 1 - t, as lerp blends
        r.originX = fetch(d, rays.originX, index, contiguous, first);
        r.originY = fetch(d, rays.originY, index, contiguous, first);
        r.originZ = fetch(d, rays.originZ, index, contiguous, first);
        r.shearX = fetch(d, rays.shearX, index, contiguous, first);
        r.shearY = fetch(d, rays.shearY, index, contiguous, first);
        r.shearZ = fetch(d, rays.shearZ, index, contiguous, first);
        const Sheared a = shear(r, tri.open[0], tri.close[0]);
        const Sheared b = shear(r, tri.open[1], tri.close[1]);
        const Sheared c = shear(r, tri.open[2], tri.close[2]);
        VF u = hn::Sub(hn::Mul(c.x, b.y), hn::Mul(c.y, b.x));
        VF v = hn::Sub(hn::Mul(a.x, c.y), hn::Mul(a.y, c.x));
        VF w = hn::Sub(hn::Mul(b.x, a.y), hn::Mul(b.y, a.x));
        const MF onEdge =
            hn::And(active, hn::Or(hn::Or(hn::Eq(u, zero), hn::Eq(v, zero)), hn::Eq(w, zero)));
        if (!hn::AllFalse(d, onEdge)) inDouble(onEdge, a, b, c, u, v, w);
        const MF negative = hn::Or(hn::Or(hn::Lt(u, zero), hn::Lt(v, zero)), hn::Lt(w, zero));
        const MF positive = hn::Or(hn::Or(hn::Gt(u, zero), hn::Gt(v, zero)), hn::Gt(w, zero));
        const MF inside = hn::AndNot(hn::And(negative, positive), active);
        // Most samples lie outside an edge: the depth and its division only for those inside.
        if (hn::AllFalse(d, inside)) continue;
        const VF det = hn::Add(hn::Add(u, v), w);
        const VF t = hn::Add(hn::Add(hn::Mul(u, a.z), hn::Mul(v, b.z)), hn::Mul(w, c.z));
        const VF rcp = hn::Div(one, det);
        const VF lambda = hn::Mul(t, rcp);
        const MF inRange =
            hn::And(hn::Ge(lambda, fetch(d, rays.lambdaMin, index, contiguous, first)),
                    hn::Le(lambda, hn::LoadU(d, lambdaMax + i)));
        const MF valid = hn::AndNot(hn::Eq(det, zero), hn::IsFinite(det));
        const MF hit = hn::And(inside, hn::And(valid, inRange));
        if (hn::AllFalse(d, hit)) continue;
        alignas(64) float lambdas[kSampleLanes], b1[kSampleLanes], b2[kSampleLanes];
        hn::Store(lambda, d, lambdas);
        hn::Store(hn::Mul(v, rcp), d, b1);
        hn::Store(hn::Mul(w, rcp), d, b2);
        alignas(64) std::uint8_t bits[8] = {};
        hn::StoreMaskBits(d, hit, bits);
        for (unsigned rest = unsigned(bits[0]) | unsigned(bits[1]) << 8; rest; rest &= rest - 1) {
            const int lane = std::countr_zero(rest);
            out[hits++] = {i + lane, lambdas[lane], b1[lane], b2[lane]};
        }
    }
    return hits;
}

}  // namespace HWY_NAMESPACE
}  // namespace patchsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace patchsim {

HWY_EXPORT(TestImpl);

BandSamples::BandSamples(const RayCaster& c, int width, int spp, int y0, int y1, int strata)
    : width_(width), spp_(spp) {
    const std::size_t n = std::size_t(y1 - y0) * std::size_t(width) * std::size_t(spp);
    const std::array floats{&originX_, &originY_, &originZ_,   &shearX_,         &shearY_,
                            &shearZ_,  &time_,    &lambdaMin_, &depthPerLambda_, &screenX_,
                            &screenY_, &lensU_,   &lensV_};
    static_assert(std::tuple_size_v<decltype(floats)> == kFloatArrays);
    for (std::vector<float>* array : floats) array->resize(n);
    axes_.resize(n);
    const bool screenPlane = c.screenPlane();
    if (screenPlane) {
        subpixelX_.resize(n);
        subpixelY_.resize(n);
    }
    const bool lensPlane = c.lensPlane();
    if (lensPlane) {
        lensPointX_.resize(n);
        lensPointY_.resize(n);
    }
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < width; ++x)
            for (int s = 0; s < spp; ++s) {
                const Sample smp = c.samples.sample(x, y, s);
                const Vec2 raster = Vec2(float(x), float(y)) + smp.pixelOffset;
                const Vec2 screen = rasterToScreen(c.camera, raster);
                const Ray ray =
                    makeCameraRay(c.camera, screen, concentricDisk(smp.lens), smp.time, c.lens);
                const ShearedRay sheared = shearRay(ray);
                const std::size_t i = index(y - y0, x, s);
                originX_[i] = sheared.origin.x;
                originY_[i] = sheared.origin.y;
                originZ_[i] = sheared.origin.z;
                shearX_[i] = sheared.sx;
                shearY_[i] = sheared.sy;
                shearZ_[i] = sheared.sz;
                axes_[i] = std::uint8_t(sheared.kx | sheared.ky << 2 | sheared.kz << 4);
                time_[i] = smp.time;
                lambdaMin_[i] = ray.lambdaMin;
                depthPerLambda_[i] = ray.depthPerLambda;
                screenX_[i] = screen.x;
                screenY_[i] = screen.y;
                lensU_[i] = smp.lens.x;
                lensV_[i] = smp.lens.y;
                if (screenPlane) {
                    subpixelX_[i] = float(sampleSubpixel(x, smp.pixelOffset.x));
                    subpixelY_[i] = float(sampleSubpixel(y, smp.pixelOffset.y));
                }
                if (lensPlane) {
                    lensPointX_[i] = ray.origin.x;
                    lensPointY_[i] = ray.origin.y;
                }
            }
    if (strata > 0) orderByStratum(strata);
}

std::uint64_t BandSamples::bytesPerSample(bool strata, bool planeSamples) {
    return kFloatArrays * sizeof(float) + sizeof(std::uint8_t) +
           (strata ? 2 * sizeof(std::uint16_t) : 0) + (planeSamples ? 2 * sizeof(float) : 0);
}

ShearedRay BandSamples::shearedRay(std::size_t i) const {
    ShearedRay r;
    r.origin = {originX_[i], originY_[i], originZ_[i]};
    r.kx = axes_[i] & 3;
    r.ky = axes_[i] >> 2 & 3;
    r.kz = axes_[i] >> 4 & 3;
    r.sx = shearX_[i];
    r.sy = shearY_[i];
    r.sz = shearZ_[i];
    return r;
}

void BandSamples::stratumRange(int row, int x, int stratum, std::size_t& first,
                               std::size_t& last) const {
    const std::size_t base = index(row, x, 0);
    const auto begin = stratum_.begin() + std::ptrdiff_t(base);
    const auto [lo, hi] = std::equal_range(begin, begin + spp_, std::uint16_t(stratum));
    first = base + std::size_t(lo - begin);
    last = base + std::size_t(hi - begin);
}

void BandSamples::orderByStratum(int strata) {
    byStratum_.resize(time_.size());
    stratum_.resize(time_.size());
    std::vector<std::pair<std::uint16_t, std::uint16_t>> pixel(static_cast<std::size_t>(spp_));
    for (std::size_t base = 0; base < time_.size(); base += std::size_t(spp_)) {
        for (int s = 0; s < spp_; ++s) {
            const float t = time_[base + std::size_t(s)];
            const int k = std::min(int(t * float(strata)), strata - 1);
            pixel[std::size_t(s)] = {std::uint16_t(k), std::uint16_t(s)};
        }
        std::sort(pixel.begin(), pixel.end());
        for (int s = 0; s < spp_; ++s) {
            stratum_[base + std::size_t(s)] = pixel[std::size_t(s)].first;
            byStratum_[base + std::size_t(s)] = pixel[std::size_t(s)].second;
        }
    }
}

CandidateList::CandidateList(std::size_t capacity)
    : index_(capacity + kSampleLanes, 0),
      lambdaMax_(capacity + kSampleLanes, 0.0f),
      hits_(capacity) {}

int CandidateList::test(const BandSamples& samples, const MovingTriangle& triangle) {
    if (count_ == 0) return 0;
    return HWY_DYNAMIC_DISPATCH(TestImpl)(samples.lanes(), index_.data(), lambdaMax_.data(),
                                          int(count_), triangle, hits_.data());
}

}  // namespace patchsim
#endif
