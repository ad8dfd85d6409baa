#pragma once
// Verifies tile tests against ground truth (docs/TILE_TESTS.md).
//
// A case is a random linearly moving box, a random tile and (for defocus variants) a random thin
// lens. Ground truth comes from dense sampling: rays through a grid of points on the tile (edges
// included), from a grid of lens points (extremes included), at a grid of times (0 and 1
// included), each tested exactly (in double precision) against the box blended to its time. A
// sampled hit proves the tile overlaps the box at that time, so a variant that rejects it, or whose
// time interval excludes that time, made a false reject. A variant that accepts a case where no
// sample hit made a false accept (a measure of tightness; sampling may miss a sliver of overlap,
// so false accepts are an upper bound).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "pipeline/core/camera.h"
#include "pipeline/core/lbbox.h"
#include "pipeline/core/ray.h"
#include "pipeline/core/time_range.h"
#include "rasterizer/tile_frustum.h"

namespace patchsim {

struct TileTestInput {
    const Camera* camera;
    LensModel lens;  // radius 0 for pinhole cases
    TileRect tile;
    LBBox box;
};

struct TileTestOutput {
    bool accept = true;
    TimeRange times = TimeRange::shutter();  // when the box may overlap the tile (if accepted)
};

// A tile test under verification. Variants register themselves with
// PATCHSIM_REGISTER_TILE_TEST; the verifier runs every registered variant.
class TileTestVariant {
  public:
    virtual ~TileTestVariant() = default;
    virtual std::string name() const = 0;
    virtual bool handlesDefocus() const = 0;  // false: pinhole cases only
    virtual TileTestOutput run(const TileTestInput& input) const = 0;
};

void registerTileTest(std::unique_ptr<TileTestVariant> variant);
void unregisterTileTest(const std::string& name);

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
const std::vector<std::unique_ptr<TileTestVariant>>& registeredTileTests();

struct TileTestReport {
    std::string name;
    std::int64_t cases = 0, falseRejects = 0, falseAccepts = 0, trueRejects = 0;
    double falseAcceptPercent() const {
        return cases ? 100.0 * double(falseAccepts) / double(cases) : 0.0;
    }
};

// Runs `cases` pinhole cases and `cases` defocus cases (for variants that handle defocus).
std::vector<TileTestReport> verifyTileTests(int cases, std::uint64_t seed);

}  // namespace patchsim

#define PATCHSIM_REGISTER_TILE_TEST(TYPE)                       \
    static const bool TYPE##Registered = [] {                   \
        ::patchsim::registerTileTest(std::make_unique<TYPE>()); \
        return true;                                            \
    }()
