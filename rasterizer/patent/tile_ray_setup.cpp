// The vector part of making a tile's rays (tile_rays.h), compiled once per SIMD target. Each lane
// performs the float operations of rasterToScreen, makeCameraRay, makeSlabRay and shearRay
// (core/ray.h, moving_box_ray.cpp, watertight_triangle.cpp) in the same order, so the
// rays equal those the reference method makes one at a time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "rasterizer/patent/tile_ray_setup.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "rasterizer/common/conservative_margins.h"
#include "rasterizer/patent/tile_rays.h"

HWY_BEFORE_NAMESPACE();
namespace patchsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::CappedTag<float, kMaxLanes>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;
using MF = hn::Mask<DF>;

// 1 / d, or 0 where the ray runs parallel to the axis (|d| < kParallelDirection).
HWY_INLINE VF inverseOrZero(DF d, VF direction, MF parallel) {
    return hn::IfThenZeroElse(parallel, hn::Div(hn::Set(d, 1.0f), direction));
}

void SetupImpl(TileRays& r, const RayCameraConstants& c) {
    const DF d;
    const DI di;
    const int lanes = int(hn::Lanes(d));
    const VF one = hn::Set(d, 1.0f), two = hn::Set(d, 2.0f);
    const VF width = hn::Set(d, c.width), height = hn::Set(d, c.height);
    const VF tanHalf = hn::Set(d, c.tanHalfFovY), aspect = hn::Set(d, c.aspect);
    const VF focus = hn::Set(d, c.focusDistance), radius = hn::Set(d, c.lensRadius);
    const VF tiny = hn::Set(d, kParallelDirection);
    const float dirZ = c.lensRadius > 0 ? -c.focusDistance : -1.0f;
    const VF directionZ = hn::Set(d, dirZ);
    const VF absZ = hn::Set(d, dirZ < 0 ? -dirZ : dirZ);
    const bool parallelZ = (dirZ < 0 ? -dirZ : dirZ) < kParallelDirection;
    for (int i = 0; i < r.count(); i += lanes) {
        // Staged by TileRays::load: raster position in directionX/Y, lens disk in originX/Y.
        const VF rasterX = hn::Load(d, r.directionX + i), rasterY = hn::Load(d, r.directionY + i);
        const VF diskX = hn::Load(d, r.originX + i), diskY = hn::Load(d, r.originY + i);
        const VF sx =
            hn::Mul(hn::Mul(hn::Sub(hn::Div(hn::Mul(two, rasterX), width), one), tanHalf), aspect);
        const VF sy = hn::Mul(hn::Sub(one, hn::Div(hn::Mul(two, rasterY), height)), tanHalf);
        if (r.screenX != nullptr) {
            hn::Store(sx, d, r.screenX + i);
            hn::Store(sy, d, r.screenY + i);
        }
        VF ox = hn::Zero(d), oy = hn::Zero(d), dx = sx, dy = sy;
        if (c.lensRadius > 0) {
            ox = hn::Mul(radius, diskX);
            oy = hn::Mul(radius, diskY);
            dx = hn::Sub(hn::Mul(sx, focus), ox);
            dy = hn::Sub(hn::Mul(sy, focus), oy);
        }
        hn::Store(ox, d, r.originX + i);
        hn::Store(oy, d, r.originY + i);
        hn::Store(dx, d, r.directionX + i);
        hn::Store(dy, d, r.directionY + i);
        // Slab test: 1/d (a = (1 - t) / d and b = t / d follow) and c = -o / d (makeSlabRay).
        const MF parallelX = hn::Lt(hn::Abs(dx), tiny), parallelY = hn::Lt(hn::Abs(dy), tiny);
        const VF inverseX = inverseOrZero(d, dx, parallelX),
                 inverseY = inverseOrZero(d, dy, parallelY);
        hn::Store(inverseX, d, r.inverseX + i);
        hn::Store(inverseY, d, r.inverseY + i);
        hn::Store(hn::Mul(hn::Neg(ox), inverseX), d, r.slabC[0] + i);
        hn::Store(hn::Mul(hn::Neg(oy), inverseY), d, r.slabC[1] + i);
        const VI parallelBits =
            hn::Or(hn::IfThenElseZero(hn::RebindMask(di, parallelX), hn::Set(di, 1)),
                   hn::IfThenElseZero(hn::RebindMask(di, parallelY), hn::Set(di, 2)));
        hn::Store(parallelZ ? hn::Or(parallelBits, hn::Set(di, 4)) : parallelBits, di,
                  r.parallelAxes + i);
        // Shear (shearRay): kz is the largest |d| (ties to the later axis), kx and ky follow it,
        // swapped when d[kz] < 0 to keep the winding.
        const VF ax = hn::Abs(dx), ay = hn::Abs(dy);
        const MF zIs0 = hn::And(hn::Gt(ax, ay), hn::Gt(ax, absZ));
        const MF zIs1 = hn::AndNot(hn::Gt(ax, ay), hn::Gt(ay, absZ));
        const VI kz = hn::IfThenElse(
            hn::RebindMask(di, zIs0), hn::Zero(di),
            hn::IfThenElse(hn::RebindMask(di, zIs1), hn::Set(di, 1), hn::Set(di, 2)));
        const VF dkz = hn::IfThenElse(zIs0, dx, hn::IfThenElse(zIs1, dy, directionZ));
        const MF swap = hn::Lt(dkz, hn::Zero(d));
        // Unswapped: kz 0 -> (1, 2), 1 -> (2, 0), 2 -> (0, 1).
        VI kx =
            hn::IfThenElse(hn::RebindMask(di, zIs0), hn::Set(di, 1),
                           hn::IfThenElse(hn::RebindMask(di, zIs1), hn::Set(di, 2), hn::Zero(di)));
        VI ky =
            hn::IfThenElse(hn::RebindMask(di, zIs0), hn::Set(di, 2),
                           hn::IfThenElse(hn::RebindMask(di, zIs1), hn::Zero(di), hn::Set(di, 1)));
        const VI swappedX = ky;
        ky = hn::IfThenElse(hn::RebindMask(di, swap), kx, ky);
        kx = hn::IfThenElse(hn::RebindMask(di, swap), swappedX, kx);
        const VF dkx = hn::IfThenElse(
            hn::RebindMask(d, hn::Eq(kx, hn::Zero(di))), dx,
            hn::IfThenElse(hn::RebindMask(d, hn::Eq(kx, hn::Set(di, 1))), dy, directionZ));
        const VF dky = hn::IfThenElse(
            hn::RebindMask(d, hn::Eq(ky, hn::Zero(di))), dx,
            hn::IfThenElse(hn::RebindMask(d, hn::Eq(ky, hn::Set(di, 1))), dy, directionZ));
        hn::Store(kx, di, r.axisX + i);
        hn::Store(ky, di, r.axisY + i);
        hn::Store(kz, di, r.axisZ + i);
        hn::Store(hn::Div(dkx, dkz), d, r.shearX + i);
        hn::Store(hn::Div(dky, dkz), d, r.shearY + i);
        hn::Store(hn::Div(one, dkz), d, r.shearZ + i);
    }
}

}  // namespace HWY_NAMESPACE
}  // namespace patchsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace patchsim {

HWY_EXPORT(SetupImpl);

void computeRayConstants(TileRays& rays, const RayCameraConstants& camera) {
    HWY_DYNAMIC_DISPATCH(SetupImpl)(rays, camera);
}

}  // namespace patchsim
#endif
