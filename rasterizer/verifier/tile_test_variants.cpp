// The patent's tile tests (US 8,791,945) as verifier variants: each bounds space (3D camera
// space, 2D homogeneous, 2D screen space), with and without the leaf time refinement. With a lens
// each side is bounded through the lens extremes; without, one plane (line, edge) per side. These
// call the same functions the patch rasterizer's traversal does.

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

}  // namespace

void addPatentTileTests(std::vector<std::unique_ptr<TileTestVariant>>& out) {
    for (BoundsSpace space :
         {BoundsSpace::Camera3D, BoundsSpace::Homogeneous2D, BoundsSpace::Screen2D})
        for (bool refine : {false, true})
            out.push_back(std::make_unique<PatentTest>(space, refine));
}

}  // namespace patchsim
