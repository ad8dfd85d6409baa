#include "rasterizer/verifier/tile_test_truth.h"

#include <gtest/gtest.h>

#include "rasterizer/verifier/tile_test_cases.h"

namespace patchsim {
namespace {

// A flat box at depth d sliding along x at speed v: it overlaps the tile's screen columns [a, b]
// (on the z = -1 plane) exactly while its x range meets [a d, b d].
TEST(TileTestTruth, SlidingFlatBoxOverlapsForTheTimesItCrossesTheTile) {
    const Camera& camera = verifierCamera();
    const TileRect tile{60, 60, 68, 68};
    const double tanX = camera.tanHalfFovY() * camera.aspect();
    const double a = (2.0 * 60 / 128 - 1) * tanX, b = (2.0 * 68 / 128 - 1) * tanX;
    const float d = 4.0f, h = 0.05f, x0 = -2.0f, v = 4.0f;
    LBBox box;
    box.bounds0 = {{x0 - h, -0.1f, -d}, {x0 + h, 0.1f, -d}};
    box.bounds1 = {{x0 + v - h, -0.1f, -d}, {x0 + v + h, 0.1f, -d}};
    const TileTruth truth = exactTileTruth(camera, {}, tile, box);
    ASSERT_TRUE(truth.hit);
    EXPECT_NEAR(truth.times.lower, (a * d - h - x0) / v, 1e-6);
    EXPECT_NEAR(truth.times.upper, (b * d + h - x0) / v, 1e-6);
    // Moved up out of the tile's rows: never.
    for (Box3* end : {&box.bounds0, &box.bounds1}) end->lower.y = 1.0f, end->upper.y = 1.2f;
    EXPECT_FALSE(exactTileTruth(camera, {}, tile, box).hit);
}

// In focus a lens changes nothing; out of focus it spreads the box over more tiles.
TEST(TileTestTruth, ALensSpreadsOnlyWhatIsOutOfFocus) {
    const Camera& camera = verifierCamera();
    const TileRect tile{60, 60, 68, 68};
    const double tanX = camera.tanHalfFovY() * camera.aspect();
    const float right = float((2.0 * 68 / 128 - 1) * tanX);  // the tile's right edge on z = -1
    auto boxAt = [&](float depth) {
        // Just right of the tile at this depth (by 2% of its width), static.
        LBBox box;
        const float x = depth * (right + 0.02f * 8.0f / 128.0f);
        box.bounds0 = box.bounds1 = {{x, -0.05f, -depth}, {x + 0.1f, 0.05f, -depth}};
        return box;
    };
    const LensModel lens{0.3f, 5.0f};
    EXPECT_FALSE(exactTileTruth(camera, {}, tile, boxAt(5.0f)).hit);
    EXPECT_FALSE(exactTileTruth(camera, lens, tile, boxAt(5.0f)).hit);  // in focus
    EXPECT_FALSE(exactTileTruth(camera, {}, tile, boxAt(9.0f)).hit);
    EXPECT_TRUE(exactTileTruth(camera, lens, tile, boxAt(9.0f)).hit);  // behind focus: blurred
    EXPECT_TRUE(exactTileTruth(camera, lens, tile, boxAt(2.0f)).hit);  // in front: blurred
    // Only rays from the lens's left half (u < 0) see past the tile's right edge behind focus.
    EXPECT_TRUE(exactTileTruth(camera, lens, tile, boxAt(9.0f), {-1, 0, -1, 1}).hit);
    EXPECT_FALSE(exactTileTruth(camera, lens, tile, boxAt(9.0f), {0.1f, 1, -1, 1}).hit);
}

// The sampled witness and the exact truth agree from both sides on random cases: every sampled
// hit lies in the exact interval, and the exact truth is never far wider than the samples show.
TEST(TileTestTruth, SampledHitsLieInsideTheExactTruth) {
    int hits = 0;
    for (CaseModel model : {CaseModel::Pinhole, CaseModel::Lens}) {
        for (int n = 0; n < 300; ++n) {
            const TileTestInput in = makeBoxCase(9, model, n).input;
            const TileTruth truth = exactTileTruth(*in.camera, in.lens, in.tile, in.box);
            const std::vector<WitnessHit> witness =
                sampledWitness(*in.camera, in.lens, in.tile, in.box, 9, 5, 65);
            if (witness.empty()) continue;
            ++hits;
            ASSERT_TRUE(truth.hit) << caseName(model, n);
            float lo = 1, hi = 0;
            for (const WitnessHit& w : witness) {
                EXPECT_GE(w.time, truth.times.lower - 1e-4f) << caseName(model, n);
                EXPECT_LE(w.time, truth.times.upper + 1e-4f) << caseName(model, n);
                lo = std::min(lo, w.time);
                hi = std::max(hi, w.time);
            }
            // Samples 1/64 apart in time: the exact ends lie within a step of the sampled ones,
            // unless the true overlap is a sliver between samples of the tile or lens.
            if (model == CaseModel::Pinhole) {
                EXPECT_LT(lo - truth.times.lower, 0.2f) << caseName(model, n);
                EXPECT_LT(truth.times.upper - hi, 0.2f) << caseName(model, n);
            }
        }
    }
    EXPECT_GT(hits, 150);
}

}  // namespace
}  // namespace patchsim
