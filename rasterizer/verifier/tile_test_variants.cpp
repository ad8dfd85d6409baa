// The patent's tile tests (US 8,791,945) as verifier variants: each bounds space (3D camera
// space, 2D homogeneous, 2D screen space), with and without the leaf time refinement. With a lens
// each side is bounded through the lens extremes; without, one plane (line, edge) per side. These
// call the same functions the patch rasterizer's traversal does.

#include <cmath>

#include "core/number_format.h"
#include "rasterizer/patent/patch_hierarchy.h"
#include "rasterizer/patent/projected_bounds.h"
#include "rasterizer/patent/projected_bounds_rounded.h"
#include "rasterizer/patent/tile_frustum.h"
#include "rasterizer/patent/tile_frustum_rounded.h"
#include "rasterizer/verifier/tile_test_variant.h"

namespace patchsim {

namespace {

class PatentTest : public TileTestVariant {
  public:
    PatentTest(BoundsSpace space, bool refineTime) : space_(space), refine_(refineTime) {}
    std::string name() const override {
        return std::string("patent-") + boundsSpaceName(space_) + (refine_ ? "-time" : "");
    }
    TileTestOutput run(const TileTestInput& in) const override {
        RasterWork work;
        TileTestOutput out;
        const float far = in.camera->farPlane();
        switch (space_) {
            case BoundsSpace::Camera3D: {
                const TileFrustum f = makeTileFrustum(*in.camera, in.lens, in.tile, far);
                out.accept = refine_ ? leafTimeInterval(f, in.box, out.times, work)
                                     : overlapsFrustum(f, in.box, true, work);
                break;
            }
            case BoundsSpace::Homogeneous2D: {
                const HomogeneousFrustum f =
                    makeHomogeneousFrustum(*in.camera, in.lens, in.tile, far);
                const LBBox clip = toHomogeneous(in.box);
                out.accept = refine_ ? homogeneousTimeInterval(f, clip, out.times, work)
                                     : overlapsHomogeneous(f, clip, true, work);
                break;
            }
            case BoundsSpace::Screen2D: {
                const ScreenTile t = makeScreenTile(*in.camera, in.tile, far);
                const ScreenMovingBox b = projectMovingBox(in.box, *in.camera, in.lens);
                out.accept = refine_ ? screenTileTimes(t, b, out.times, work)
                                     : overlapsScreenTile(t, b, true, work);
                break;
            }
        }
        return out;
    }

  private:
    BoundsSpace space_;
    bool refine_;
};

// The 2D screen-space test with the moving box's screen bounds stored in `format`
// (projected_bounds_rounded.h, the render's rasterizer.screen_bounds_format): outward, it cannot
// reject falsely, only accept more; rounded to nearest (`outward` false), the naive variant, it
// can shrink the box and reject falsely.
class ReducedScreenTest : public TileTestVariant {
  public:
    ReducedScreenTest(NumberFormat format, bool outward) : format_(format), outward_(outward) {}
    std::string name() const override {
        return "patent-2d-time-" + formatName(format_) + (outward_ ? "" : "-naive");
    }
    TileTestOutput run(const TileTestInput& in) const override {
        RasterWork work;
        TileTestOutput out;
        const ScreenTile t = makeScreenTile(*in.camera, in.tile, in.camera->farPlane());
        const ScreenMovingBox b =
            storedIn(projectMovingBox(in.box, *in.camera, in.lens), format_, outward_, *in.camera);
        out.accept = screenTileTimes(t, b, out.times, work);
        return out;
    }

    bool lossy() const override { return !outward_; }

  private:
    NumberFormat format_;
    bool outward_;
};

// The render's node_format site (issue 35): the box stored in `format` as PatchHierarchy stores
// its nodes, then the fp32 3D test with time refinement. Rounded outward the stored box holds the
// exact one at every time, and the test is monotone in the box: no false reject.
class StoredNodeTest : public TileTestVariant {
  public:
    StoredNodeTest(NumberFormat format, bool outward) : format_(format), outward_(outward) {}
    std::string name() const override {
        return "patent-3d-time-nodes-" + formatName(format_) + (outward_ ? "" : "-naive");
    }
    TileTestOutput run(const TileTestInput& in) const override {
        RasterWork work;
        TileTestOutput out;
        const TileFrustum f = makeTileFrustum(*in.camera, in.lens, in.tile, in.camera->farPlane());
        const LBBox stored =
            storedIn(in.box, format_, outward_ ? Rounding::Down : Rounding::Nearest);
        out.accept = leafTimeInterval(f, stored, out.times, work);
        return out;
    }
    bool lossy() const override { return !outward_; }

  private:
    NumberFormat format_;
    bool outward_;
};

// The tile planes and the leaf time intervals computed in `format` (tile_frustum_rounded.h): the
// fp32 box and frustum enter the format's datapath, bounded by running error analysis or naive.
class PlaneArithmeticTest : public TileTestVariant {
  public:
    PlaneArithmeticTest(NumberFormat format, PlaneErrorHandling handling)
        : arithmetic_(format), handling_(handling) {}
    std::string name() const override {
        return "patent-3d-time-planes-" + formatName(arithmetic_.format()) +
               (lossy() ? "-naive" : "");
    }
    TileTestOutput run(const TileTestInput& in) const override {
        RasterWork work;
        TileTestOutput out;
        const TileFrustum f = makeTileFrustum(*in.camera, in.lens, in.tile, in.camera->farPlane());
        out.accept = leafTimeIntervalRounded(f, in.box, arithmetic_, handling_, out.times, work);
        return out;
    }
    bool lossy() const override { return handling_ == PlaneErrorHandling::Naive; }

  private:
    RoundedArithmetic arithmetic_;
    PlaneErrorHandling handling_;
};

}  // namespace

void addPatentTileTests(std::vector<std::unique_ptr<TileTestVariant>>& out) {
    for (BoundsSpace space :
         {BoundsSpace::Camera3D, BoundsSpace::Homogeneous2D, BoundsSpace::Screen2D})
        for (bool refine : {false, true})
            out.push_back(std::make_unique<PatentTest>(space, refine));
    for (const NumberFormat& format : {NumberFormat::fp16(), NumberFormat::bf16()})
        out.push_back(std::make_unique<ReducedScreenTest>(format, true));
}

std::unique_ptr<TileTestVariant> makeReducedScreenTileTest(const NumberFormat& format,
                                                           bool outward) {
    return std::make_unique<ReducedScreenTest>(format, outward);
}

std::unique_ptr<TileTestVariant> makeStoredNodeTileTest(const NumberFormat& format, bool outward) {
    return std::make_unique<StoredNodeTest>(format, outward);
}

std::unique_ptr<TileTestVariant> makePlaneArithmeticTileTest(const NumberFormat& format,
                                                             bool bounded) {
    return std::make_unique<PlaneArithmeticTest>(
        format, bounded ? PlaneErrorHandling::Bounded : PlaneErrorHandling::Naive);
}

std::vector<std::unique_ptr<TileTestVariant>> formatTileTests(const NumberFormat& format) {
    std::vector<std::unique_ptr<TileTestVariant>> out;
    if (format == NumberFormat::fp32()) return out;
    for (bool outward : {true, false}) {
        out.push_back(makeReducedScreenTileTest(format, outward));
        out.push_back(makeStoredNodeTileTest(format, outward));
        out.push_back(makePlaneArithmeticTileTest(format, outward));
    }
    return out;
}

}  // namespace patchsim
