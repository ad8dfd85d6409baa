// The patent's tile tests (US 8,791,945) as verifier variants: each bounds space (3D camera
// space, 2D homogeneous, 2D screen space), with and without the leaf time refinement. With a lens
// each side is bounded through the lens extremes; without, one plane (line, edge) per side. These
// call the same functions the patch rasterizer's traversal does.

#include "core/number_format.h"
#include "rasterizer/patent/patch_hierarchy.h"
#include "rasterizer/patent/projected_bounds.h"
#include "rasterizer/patent/tile_frustum.h"
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

// The 2D screen-space test with the moving box's screen bounds stored in a smaller float format
// (issue 35), rounded outward: lower corners down, upper corners up, the depth ratios' range
// widened and the near depths brought nearer. The stored box then holds the fp32 box at every
// blend of its two ends, and the test is monotone in the box, so whatever the fp32 test accepts
// it accepts too: it cannot reject falsely, only accept more.
// Rounded to nearest instead (`outward` false), the naive variant, it can shrink the box and
// reject falsely: kept for the tests to show what the outward rounding prevents.
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
        ScreenMovingBox b = projectMovingBox(in.box, *in.camera, in.lens);
        const auto down = [&](float& v) {
            v = roundTo(v, format_, outward_ ? Rounding::Down : Rounding::Nearest);
        };
        const auto up = [&](float& v) {
            v = roundTo(v, format_, outward_ ? Rounding::Up : Rounding::Nearest);
        };
        for (Vec2* lower : {&b.lower0, &b.lower1}) {
            down(lower->x);
            down(lower->y);
        }
        for (Vec2* upper : {&b.upper0, &b.upper1}) {
            up(upper->x);
            up(upper->y);
        }
        down(b.ratioMin);
        up(b.ratioMax);
        down(b.nearDepth0);
        down(b.nearDepth1);
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

std::vector<std::unique_ptr<TileTestVariant>> formatTileTests(const NumberFormat& format) {
    std::vector<std::unique_ptr<TileTestVariant>> out;
    if (format == NumberFormat::fp32()) return out;
    for (bool outward : {true, false}) {
        if (format.kind != NumberFormat::Kind::Fixed)
            out.push_back(makeReducedScreenTileTest(format, outward));
        out.push_back(makeStoredNodeTileTest(format, outward));
    }
    return out;
}

}  // namespace patchsim
