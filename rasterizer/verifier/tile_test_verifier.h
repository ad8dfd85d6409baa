#pragma once
// Verifies tile tests against exact ground truth (docs/TILE_TESTS.md).
//
// A box case is a random linearly moving box (sometimes still, sometimes moving only in depth,
// sometimes still in the world but seen from a moving camera), a random tile near where it is
// seen, and for lens cases a random thin lens. Ground truth is exact (tile_test_truth): the hull
// of the times at which some ray through the tile, from anywhere on the square that holds the
// lens, meets the box. A variant that rejects a case the truth hits, or whose time interval or
// lens rectangle leaves out a time or lens point that hits, made a false reject; a variant that
// accepts a case the truth misses made a false accept, counted over the true misses. Accepted
// hits add their time-interval excess (width beyond the true interval) to a distribution. A
// sampled witness on every Nth case checks the exact truth itself.
//
// A hierarchy case is a random moving triangle sheet with its hierarchy, and a tile: each bounds
// space's traversal must keep every leaf the truth hits and cover its times, each branch method's
// node must lie above all those leaves, and each level's screen bounds must cover the tile.
//
// Representation
// --------------
// Variants are objects behind a small interface (tile_test_variant.h); each case runs every
// registered variant, so the per-case cost is one exact truth and a virtual call per variant.
// Cases are numbered per model and made from (seed, model, number) alone (tile_test_cases.h), so
// any case can be replayed by its name ("lens:1234") and the report does not depend on the thread
// count.

#include <array>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/lbbox.h"
#include "core/ray.h"
#include "core/time_range.h"
#include "rasterizer/common/tile_grid.h"
#include "rasterizer/verifier/tile_test_cases.h"
#include "rasterizer/verifier/tile_test_truth.h"
#include "rasterizer/verifier/tile_test_variant.h"

namespace patchsim {

// Excess beyond the truth (time-interval width in shutter fractions, or branch-node levels) in
// 1000 bins of `binWidth`.
struct ExcessHistogram {
    static constexpr int kBins = 1000;
    double binWidth = 0.001;
    std::array<std::int64_t, kBins + 1> bins{};  // the last holds everything beyond
    std::int64_t count = 0;
    void add(double excess);
    void merge(const ExcessHistogram& o);
    double quantile(double q) const;  // its bin's lower edge; 0 when empty
};

struct TileTestReport {
    std::string name;
    CaseModel model = CaseModel::Pinhole;
    std::int64_t cases = 0, trueHits = 0, trueMisses = 0;
    std::int64_t falseRejects = 0, falseAccepts = 0;
    ExcessHistogram excess;
    const char* excessUnit = "shutter";  // "shutter" (time interval) or "levels" (branch node)
    std::string firstFailure;            // the first falsely rejected case ("lens:1234"), if any
    bool lossy = false;  // a naive variant: its false rejects are reported, not a failure
    double falseAcceptPercent() const {  // of the true misses
        return trueMisses ? 100.0 * double(falseAccepts) / double(trueMisses) : 0.0;
    }
};

struct TileVerifierOptions {
    std::int64_t cases = 2000;  // per model
    std::uint64_t seed = 1;
    int threads = 0;
    int witnessEvery = 64;                  // a sampled witness on every Nth case (0: none)
    CaseFamily family = CaseFamily::Mixed;  // of the box cases (hierarchy cases are the mix's)
    std::ostream* csv = nullptr;            // one row per case and variant, when set
};

struct TileVerifierResult {
    std::vector<TileTestReport> reports;
    std::int64_t witnessCases = 0, witnessHits = 0;
    std::int64_t witnessOutsideTruth = 0;  // sampled hits the exact truth misses: must be 0
    bool anyFalseReject() const;           // of a variant that is not lossy, or a witness
};

TileVerifierResult verifyTileTests(const TileVerifierOptions& options);

// Everything about one case ("pinhole:17", "lens:3", "hierarchy:9"): inputs in hexadecimal
// floats, the truth, and every variant's answer. False when the name is not a case.
bool replayTileCase(const std::string& name, std::uint64_t seed, std::ostream& out,
                    CaseFamily family = CaseFamily::Mixed);

}  // namespace patchsim

#define PATCHSIM_REGISTER_TILE_TEST(TYPE)                       \
    static const bool TYPE##Registered = [] {                   \
        ::patchsim::registerTileTest(std::make_unique<TYPE>()); \
        return true;                                            \
    }()
