#include "rasterizer/verifier/tile_test_verifier.h"

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "rasterizer/verifier/tile_test_cases.h"

namespace patchsim {
namespace {

TileVerifierResult verify(std::int64_t cases, std::uint64_t seed) {
    TileVerifierOptions o;
    o.cases = cases;
    o.seed = seed;
    o.witnessEvery = 8;
    return verifyTileTests(o);
}

// A moving box's screen bounds stored in fp16 or bf16: rounded outward the test never rejects
// falsely; rounded to nearest (the naive variant) it does.
TEST(TileTestVerifier, ReducedPrecisionBoundsRejectFalselyOnlyWhenRoundedToNearest) {
    const ScopedTileTest half(makeReducedScreenTileTest(NumberFormat::fp16(), false));
    const ScopedTileTest brain(makeReducedScreenTileTest(NumberFormat::bf16(), false));
    const TileVerifierResult result = verify(3000, 42);
    const auto find = [&](const std::string& name, CaseModel model) {
        for (const TileTestReport& r : result.reports)
            if (r.name == name && r.model == model) return r;
        ADD_FAILURE() << name;
        return TileTestReport{};
    };
    for (const CaseModel model : {CaseModel::Pinhole, CaseModel::Lens}) {
        EXPECT_EQ(find("patent-2d-time-fp16", model).falseRejects, 0);
        EXPECT_EQ(find("patent-2d-time-bf16", model).falseRejects, 0);
        const TileTestReport exact = find("patent-2d-time", model);
        const TileTestReport outward = find("patent-2d-time-bf16", model);
        EXPECT_GE(outward.falseAccepts, exact.falseAccepts);  // only ever accepts more
    }
    EXPECT_GT(find("patent-2d-time-bf16-naive", CaseModel::Pinhole).falseRejects +
                  find("patent-2d-time-bf16-naive", CaseModel::Lens).falseRejects,
              0);
}

// D3D11's 16.8 snap at the screen bounds, in pixels: rounded outward (in pixels, and back on the
// plane widened by the conversions' error bounds) no false reject at any width. Rounded to
// nearest, the error is half a step: within the tile guard (1/256 pixel) from 7 fraction bits,
// so 16.8 loses nothing here, and 16.4 (half a step is 1/32 pixel) rejects falsely.
TEST(TileTestVerifier, ScreenBoundsSnappedToPixelsRejectFalselyOnlyBeyondTheTileGuard) {
    std::vector<std::unique_ptr<ScopedTileTest>> scoped;
    for (const NumberFormat format : {kD3D11Snap, NumberFormat::fixed(16, 4)})
        for (bool outward : {true, false})
            scoped.push_back(
                std::make_unique<ScopedTileTest>(makeReducedScreenTileTest(format, outward)));
    const TileVerifierResult result = verify(3000, 42);
    std::map<std::string, std::int64_t> rejects, accepts;
    for (const TileTestReport& r : result.reports) {
        rejects[r.name] += r.falseRejects;
        accepts[r.name] += r.falseAccepts;
    }
    EXPECT_EQ(rejects["patent-2d-time-fixed16.8"], 0);
    EXPECT_EQ(rejects["patent-2d-time-fixed16.4"], 0);
    EXPECT_EQ(rejects["patent-2d-time-fixed16.8-naive"], 0);  // within the guard
    EXPECT_GT(rejects["patent-2d-time-fixed16.4-naive"], 0);
    EXPECT_GE(accepts["patent-2d-time-fixed16.4"], accepts["patent-2d-time-fixed16.8"]);
    EXPECT_GE(accepts["patent-2d-time-fixed16.8"], accepts["patent-2d-time"]);
}

// The render's node_format site: the box stored as the hierarchy stores its nodes. Rounded
// outward, no false reject in any format, fixed point included; rounded to nearest, false
// rejects that the run reports without failing (a lossy variant). verify-tiles --format makes
// both for each site.
TEST(TileTestVerifier, StoredNodeBoxesRejectFalselyOnlyWhenRoundedToNearest) {
    std::vector<std::unique_ptr<ScopedTileTest>> scoped;
    for (const NumberFormat format : {NumberFormat::fp16(), NumberFormat::fixed(16, 8)})
        for (auto& variant : formatTileTests(format))
            scoped.push_back(std::make_unique<ScopedTileTest>(std::move(variant)));
    const TileVerifierResult result = verify(3000, 42);
    std::int64_t naiveRejects = 0;
    int seen = 0;
    for (const TileTestReport& r : result.reports) {
        if (r.name.rfind("patent-3d-time-nodes-", 0) != 0) continue;
        ++seen;
        const bool naive = r.name.ends_with("-naive");
        EXPECT_EQ(r.lossy, naive) << r.name;
        if (naive)
            naiveRejects += r.falseRejects;
        else
            EXPECT_EQ(r.falseRejects, 0) << r.name << " " << caseModelName(r.model);
    }
    EXPECT_EQ(seen, 8);  // 2 formats x outward and naive x pinhole and lens
    EXPECT_GT(naiveRejects, 0);
    EXPECT_FALSE(result.anyFalseReject()) << "a lossy variant's rejects fail the run";
    EXPECT_EQ(formatTileTests(NumberFormat::fp16()).size(), 6u);  // three sites, both roundings
    EXPECT_EQ(formatTileTests(NumberFormat::fixed(16, 8)).size(), 6u);
}

// The tile planes and leaf time intervals computed in the format's arithmetic: bounded by
// running error analysis, no false reject in any format; naive (the rounded distances against
// zero, times rounded to nearest), false rejects in every one.
TEST(TileTestVerifier, PlaneArithmeticRejectsFalselyOnlyWithoutItsErrorBound) {
    std::vector<std::unique_ptr<ScopedTileTest>> scoped;
    const NumberFormat formats[] = {NumberFormat::fp16(), NumberFormat::bf16(),
                                    NumberFormat::fixed(16, 8)};
    for (const NumberFormat& format : formats)
        for (bool bounded : {true, false})
            scoped.push_back(
                std::make_unique<ScopedTileTest>(makePlaneArithmeticTileTest(format, bounded)));
    const TileVerifierResult result = verify(3000, 42);
    std::map<std::string, std::int64_t> rejects, accepts;
    for (const TileTestReport& r : result.reports) {
        if (r.name.rfind("patent-3d-time", 0) != 0) continue;
        rejects[r.name] += r.falseRejects;
        accepts[r.name] += r.falseAccepts;
        EXPECT_EQ(r.lossy, r.name.ends_with("-naive")) << r.name;
    }
    for (const NumberFormat& format : formats) {
        const std::string name = "patent-3d-time-planes-" + formatName(format);
        EXPECT_EQ(rejects[name], 0) << name;
        EXPECT_GT(rejects[name + "-naive"], 0) << name;
        EXPECT_GE(accepts[name], accepts["patent-3d-time"]) << name;
    }
    EXPECT_FALSE(result.anyFalseReject()) << "a lossy variant's rejects fail the run";
}

TEST(TileTestVerifier, EveryVariantAndCheckIsListedAndNeverRejectsFalsely) {
    const TileVerifierResult result = verify(3000, 42);
    std::set<std::string> names;
    for (const TileTestReport& r : result.reports) {
        names.insert(r.name);
        EXPECT_EQ(r.cases, 3000) << r.name;
        EXPECT_EQ(r.falseRejects, 0)
            << r.name << " " << caseModelName(r.model) << " " << r.firstFailure;
        // The cases mix overlapping and missing boxes; a test that accepts everything is useless.
        if (r.name.rfind("branch-", 0) != 0) {
            EXPECT_GT(r.trueMisses - r.falseAccepts, 100) << r.name;
        }
        EXPECT_GT(r.trueHits, 300) << r.name;
    }
    for (const char* name : {"patent-3d",       "patent-3d-time",     "patent-2dh",
                             "patent-2dh-time", "patent-2d",          "patent-2d-time",
                             "triangle-bbox",   "triangle-hull",      "triangle-oriented-box",
                             "interval-4",      "interval-16",        "dual-space",
                             "traversal-3d",    "traversal-2dh",      "traversal-2d",
                             "branch-root",     "branch-first-split", "branch-bitmask",
                             "bounds-level-0",  "bounds-level-3"})
        EXPECT_TRUE(names.count(name)) << name;
    // The sampled witness found hits, and every one lies inside the exact truth.
    EXPECT_GT(result.witnessHits, 1000);
    EXPECT_EQ(result.witnessOutsideTruth, 0);
    EXPECT_FALSE(result.anyFalseReject());
}

const TileTestReport& find(const TileVerifierResult& r, const std::string& name, CaseModel m) {
    for (const TileTestReport& report : r.reports)
        if (report.name == name && report.model == m) return report;
    throw std::runtime_error("no report " + name);
}

// What the literature and the patent lead one to expect, as orderings on the same cases.
TEST(TileTestVerifier, TighterTestsAcceptFewerMissesAndNarrowerTimes) {
    const TileVerifierResult r = verify(4000, 7);
    for (CaseModel m : {CaseModel::Pinhole, CaseModel::Lens}) {
        const auto& bbox = find(r, "triangle-bbox", m);
        const auto& hull = find(r, "triangle-hull", m);
        const auto& interval = find(r, "interval-16", m);
        const auto& oriented = find(r, "triangle-oriented-box", m);
        // The oriented box holds the hull and is the least-area rectangle: between the two.
        EXPECT_LT(hull.falseAccepts, oriented.falseAccepts) << caseModelName(m);
        EXPECT_LE(oriented.falseAccepts, bbox.falseAccepts) << caseModelName(m);
        const auto& patent = find(r, "patent-3d-time", m);
        const auto& spatial = find(r, "patent-3d", m);
        EXPECT_LT(interval.falseAccepts, bbox.falseAccepts) << caseModelName(m);
        EXPECT_LT(patent.falseAccepts, spatial.falseAccepts) << caseModelName(m);
        // Time refinement narrows the interval; the bounding box keeps the whole shutter.
        EXPECT_LT(patent.excess.quantile(0.95), bbox.excess.quantile(0.95)) << caseModelName(m);
        // 2DH is 3D in clip coordinates: the same answers.
        EXPECT_EQ(find(r, "patent-2dh-time", m).falseAccepts, patent.falseAccepts);
    }
    // The bitmask finds the lowest node above the overlapping leaves; the root is never lower.
    const auto& root = find(r, "branch-root", CaseModel::Hierarchy);
    const auto& bitmask = find(r, "branch-bitmask", CaseModel::Hierarchy);
    EXPECT_LT(bitmask.excess.quantile(0.95), root.excess.quantile(0.95));
    EXPECT_EQ(bitmask.excess.quantile(0.5), 0.0);
}

TEST(TileTestVerifier, ResultsDoNotDependOnTheThreadCount) {
    TileVerifierOptions o;
    o.cases = 5000;
    o.seed = 5;
    std::ostringstream one, two;
    o.threads = 1;
    o.csv = &one;
    verifyTileTests(o);
    o.threads = 2;
    o.csv = &two;
    verifyTileTests(o);
    EXPECT_EQ(one.str(), two.str());
    EXPECT_GT(one.str().size(), 100000u);
}

TEST(TileTestVerifier, ReplayPrintsTheCaseAndEveryAnswer) {
    std::ostringstream out;
    ASSERT_TRUE(replayTileCase("lens:17", 1, out));
    const std::string text = out.str();
    for (const char* part :
         {"case lens:17", "box at t=0", "truth: hit", "patent-3d-time:", "dual-space:", "lens u ["})
        EXPECT_NE(text.find(part), std::string::npos) << part << "\n" << text;
    std::ostringstream h;
    ASSERT_TRUE(replayTileCase("hierarchy:3", 1, h));
    EXPECT_NE(h.str().find("branch-bitmask:"), std::string::npos) << h.str();
    std::ostringstream bad;
    EXPECT_FALSE(replayTileCase("lens:x", 1, bad));
    EXPECT_FALSE(replayTileCase("fisheye:3", 1, bad));
}

// A deliberately broken variant: the verifier must catch it.
class AlwaysReject : public TileTestVariant {
  public:
    std::string name() const override { return "always-reject"; }
    bool handlesLens() const override { return false; }
    TileTestOutput run(const TileTestInput&) const override { return {false}; }
};

// Another: right in space but its time interval stops early.
class ShortTimes : public TileTestVariant {
  public:
    std::string name() const override { return "short-times"; }
    TileTestOutput run(const TileTestInput&) const override {
        TileTestOutput out;
        out.times = {0.0f, 0.9f};
        return out;
    }
};

TEST(TileTestVerifier, CatchesTestsThatRejectOverlapsOrCutTheirTimes) {
    const std::size_t before = registeredTileTests().size();
    {
        const ScopedTileTest broken(std::make_unique<AlwaysReject>());
        const ScopedTileTest shortTimes(std::make_unique<ShortTimes>());
        const TileVerifierResult r = verify(400, 3);
        EXPECT_GT(find(r, "always-reject", CaseModel::Pinhole).falseRejects, 0);
        EXPECT_FALSE(find(r, "always-reject", CaseModel::Pinhole).firstFailure.empty());
        EXPECT_GT(find(r, "short-times", CaseModel::Lens).falseRejects, 0);
        for (const TileTestReport& report : r.reports)
            EXPECT_FALSE(report.name == "always-reject" && report.model == CaseModel::Lens);
        EXPECT_TRUE(r.anyFalseReject());
    }
    // Gone again: the tests after this one see only the real variants.
    EXPECT_EQ(registeredTileTests().size(), before);
}

TEST(TileTestCases, NamesRoundTripAndCasesAreReproducible) {
    CaseModel m;
    std::int64_t n;
    ASSERT_TRUE(parseCaseName("hierarchy:123", m, n));
    EXPECT_EQ(m, CaseModel::Hierarchy);
    EXPECT_EQ(n, 123);
    EXPECT_EQ(caseName(CaseModel::Lens, 9), "lens:9");
    const BoxCase a = makeBoxCase(1, CaseModel::Lens, 77), b = makeBoxCase(1, CaseModel::Lens, 77);
    EXPECT_EQ(a.input.box.bounds1.upper, b.input.box.bounds1.upper);
    EXPECT_GT(a.input.lens.radius, 0.0f);
    std::set<int> kinds;
    for (int i = 0; i < 200; ++i) kinds.insert(int(makeBoxCase(1, CaseModel::Pinhole, i).kind));
    EXPECT_EQ(kinds.size(), 4u);  // still, depth-only, moving, camera motion
}

// The hard-case families: the mixed family is the default mix, case for case; each other family
// has its extreme (boxes across the near plane, near the far plane, moving tens of units, smaller
// than a pixel, larger than the view, an aperture as wide as the distance); and in every family
// the conservative variants, fixed16.8 at every site included, never reject falsely while the
// naive ones do somewhere.
TEST(TileTestCases, EveryFamilyHasItsExtremeAndNoConservativeVariantRejectsFalsely) {
    for (int i = 0; i < 50; ++i) {
        const BoxCase mixed = makeBoxCase(3, CaseModel::Lens, i, CaseFamily::Mixed);
        EXPECT_EQ(mixed.input.box.bounds1.lower,
                  makeBoxCase(3, CaseModel::Lens, i).input.box.bounds1.lower);
    }
    int acrossNear = 0, beyondSixty = 0, fast = 0, subPixel = 0, wide = 0, wideLens = 0;
    for (int i = 0; i < 200; ++i) {
        auto box = [&](CaseFamily f) { return makeBoxCase(3, CaseModel::Lens, i, f).input; };
        const LBBox nearBox = box(CaseFamily::NearPlane).box;
        acrossNear += nearBox.bounds0.upper.z > -0.1f || nearBox.bounds1.upper.z > -0.1f;
        beyondSixty += box(CaseFamily::FarDepth).box.bounds0.upper.z < -55.0f;
        const LBBox moving = box(CaseFamily::HugeMotion).box;
        fast += glm::length(moving.bounds1.lower - moving.bounds0.lower) > 10.0f;
        const LBBox tiny = box(CaseFamily::Tiny).box;
        const float depth = -tiny.bounds0.upper.z;
        subPixel += (tiny.bounds0.upper.x - tiny.bounds0.lower.x) < 0.009f * depth;
        const LBBox huge = box(CaseFamily::Huge).box;
        wide += (huge.bounds0.upper.x - huge.bounds0.lower.x) > 4.0f;
        const TileTestInput lens = box(CaseFamily::WideLens);
        wideLens += lens.lens.radius >
                    0.29f * -0.5f * (lens.box.bounds0.lower.z + lens.box.bounds0.upper.z);
    }
    EXPECT_GT(acrossNear, 50);
    EXPECT_EQ(beyondSixty, 200);
    EXPECT_GT(fast, 40);  // the moving kinds (still and camera motion keep theirs)
    EXPECT_GT(subPixel, 150);
    EXPECT_GT(wide, 150);
    EXPECT_EQ(wideLens, 200);

    std::vector<std::unique_ptr<ScopedTileTest>> scoped;
    for (auto& variant : formatTileTests(NumberFormat::fixed(16, 8)))
        scoped.push_back(std::make_unique<ScopedTileTest>(std::move(variant)));
    for (const CaseFamily family :
         {CaseFamily::NearPlane, CaseFamily::FarDepth, CaseFamily::HugeMotion, CaseFamily::Tiny,
          CaseFamily::Huge, CaseFamily::WideLens}) {
        TileVerifierOptions o;
        o.cases = 1500;
        o.seed = 5;
        o.witnessEvery = 16;
        o.family = family;
        const TileVerifierResult result = verifyTileTests(o);
        EXPECT_FALSE(result.anyFalseReject()) << caseFamilyName(family);
        std::int64_t naiveRejects = 0;
        for (const TileTestReport& r : result.reports)
            if (r.lossy) naiveRejects += r.falseRejects;
        EXPECT_GT(naiveRejects, 0) << caseFamilyName(family);
    }
    CaseFamily parsed;
    EXPECT_TRUE(parseCaseFamily("wide-lens", parsed));
    EXPECT_EQ(parsed, CaseFamily::WideLens);
    EXPECT_FALSE(parseCaseFamily("wide lens", parsed));
}

}  // namespace
}  // namespace patchsim
