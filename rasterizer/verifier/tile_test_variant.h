#pragma once
// The interface of a tile test under verification, and the registry of them (docs/TILE_TESTS.md).
//
// Representation
// --------------
// A variant takes one case (a moving box in camera space, a tile, a camera and a lens) and answers
// whether the box may overlap the tile, when, and from where on the lens. Variants are objects
// registered once: the built-ins by the registry on its first use (the patent's in
// tile_test_variants.cpp, the literature's in tile_test_literature.cpp), a user's or a test's
// with ScopedTileTest. The verifier (tile_test_verifier.h) runs every registered variant on every
// case; the cases (tile_test_cases.h) are made per model.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/lbbox.h"
#include "core/number_format.h"
#include "core/ray.h"
#include "core/time_range.h"
#include "rasterizer/common/tile_grid.h"
#include "rasterizer/verifier/tile_test_truth.h"

namespace patchsim {

struct TileTestInput {
    const Camera* camera;
    LensModel lens;  // radius 0 for pinhole cases
    TileRect tile;
    LBBox box;  // camera space
};

struct TileTestOutput {
    bool accept = true;
    TimeRange times = TimeRange::shutter();  // when the box may overlap the tile (if accepted)
    LensRect lens = LensRect::whole();       // where on the lens (units of its radius)
};

// A tile test under verification.
class TileTestVariant {
  public:
    virtual ~TileTestVariant() = default;
    virtual std::string name() const = 0;
    virtual bool handlesPinhole() const { return true; }
    virtual bool handlesLens() const { return true; }
    // A naive variant kept to show what goes wrong without a rule (rounding to nearest): its
    // false rejects are reported, and do not fail the run.
    virtual bool lossy() const { return false; }
    virtual TileTestOutput run(const TileTestInput& input) const = 0;
};

void registerTileTest(std::unique_ptr<TileTestVariant> variant);
void unregisterTileTest(const std::string& name);
const std::vector<std::unique_ptr<TileTestVariant>>& registeredTileTests();

// Registered for the lifetime of this object (e.g. a deliberately broken variant in a test).
class ScopedTileTest {
  public:
    explicit ScopedTileTest(std::unique_ptr<TileTestVariant> variant) : name_(variant->name()) {
        registerTileTest(std::move(variant));
    }
    ~ScopedTileTest() { unregisterTileTest(name_); }
    ScopedTileTest(const ScopedTileTest&) = delete;
    ScopedTileTest& operator=(const ScopedTileTest&) = delete;

  private:
    std::string name_;
};

// The built-in variants, added to the registry on its first use (patent variants in
// tile_test_variants.cpp, the literature's in tile_test_literature.cpp).
void addPatentTileTests(std::vector<std::unique_ptr<TileTestVariant>>& out);
void addLiteratureTileTests(std::vector<std::unique_ptr<TileTestVariant>>& out);

// The 2D screen-space test with the moving box's screen bounds stored in `format`, rounded
// outward (registered for fp16 and bf16) or, when not `outward`, to nearest (the naive variant,
// for tests).
std::unique_ptr<TileTestVariant> makeReducedScreenTileTest(const NumberFormat& format,
                                                           bool outward);
// The 3D camera-space test with time refinement on the moving box as the render stores it with
// `rasterizer.node_format` = `format` (storedIn): rounded outward, or to nearest (lossy).
std::unique_ptr<TileTestVariant> makeStoredNodeTileTest(const NumberFormat& format, bool outward);
// The 3D test with time refinement computed in `format`'s arithmetic (tile_frustum_rounded.h):
// each plane distance bounded by running error analysis, or (not `bounded`) naive (lossy).
std::unique_ptr<TileTestVariant> makePlaneArithmeticTileTest(const NumberFormat& format,
                                                             bool bounded);
// For `verify-tiles --format`: every site's variants in `format`, outward and naive (fixed point
// at the screen bounds stores pixels, as D3D11's 16.8 snap does).
std::vector<std::unique_ptr<TileTestVariant>> formatTileTests(const NumberFormat& format);

enum class CaseModel : std::uint8_t { Pinhole, Lens, Hierarchy };
const char* caseModelName(CaseModel model);
bool parseCaseModel(const std::string& name, CaseModel& out);

}  // namespace patchsim
