#include "rasterizer/verifier/tile_test_verifier.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <sstream>

#include "core/enum_names.h"
#include "core/parallel.h"
#include "rasterizer/patent/branch_node.h"
#include "rasterizer/patent/screen_bounds.h"
#include "rasterizer/patent/tile_traversal.h"
#include "rasterizer/verifier/tile_test_cases.h"

namespace patchsim {

// ---- Excess distribution ----

void ExcessHistogram::add(double excess) {
    const double bin = std::floor(std::max(0.0, excess) / binWidth);
    ++bins[std::size_t(std::min(bin, double(kBins)))];
    ++count;
}

void ExcessHistogram::merge(const ExcessHistogram& o) {
    for (std::size_t i = 0; i < bins.size(); ++i) bins[i] += o.bins[i];
    count += o.count;
}

double ExcessHistogram::quantile(double q) const {
    if (count == 0) return 0.0;
    const auto rank = std::int64_t(std::ceil(q * double(count)));
    std::int64_t seen = 0;
    for (std::size_t i = 0; i < bins.size(); ++i) {
        seen += bins[i];
        if (seen >= std::max<std::int64_t>(rank, 1)) return double(i) * binWidth;
    }
    return double(kBins) * binWidth;
}

bool TileVerifierResult::anyFalseReject() const {
    return std::any_of(reports.begin(), reports.end(),
                       [](const TileTestReport& r) { return r.falseRejects > 0 && !r.lossy; }) ||
           witnessOutsideTruth > 0;
}

namespace {

enum class Outcome : std::uint8_t { TrueAccept, TrueReject, FalseAccept, FalseReject };
const char* outcomeName(Outcome o) {
    constexpr const char* names[] = {"true-accept", "true-reject", "false-accept", "false-reject"};
    return names[int(o)];
}

// One variant (or hierarchy check) on one case.
struct CheckResult {
    Outcome outcome = Outcome::TrueReject;
    bool accept = false;
    TimeRange times = TimeRange::empty();
    double excess = -1;  // < 0: not measured
};

struct CaseTruth {
    TileTruth exact;
    std::vector<WitnessHit> witness;
};

double width(const TimeRange& r) {
    return r.isEmpty() ? 0.0 : double(r.upper) - double(r.lower);
}

// True when some ray from the part of the lens the variant excluded hits.
bool hitOutsideLensRect(const TileTestInput& in, const LensRect& kept) {
    if (in.lens.radius <= 0) return false;
    const LensRect strips[4] = {
        {-1, kept.u0, -1, 1}, {kept.u1, 1, -1, 1}, {-1, 1, -1, kept.v0}, {-1, 1, kept.v1, 1}};
    for (int k = 0; k < 4; ++k) {
        const bool excluded = k == 0   ? kept.u0 > -1
                              : k == 1 ? kept.u1 < 1
                              : k == 2 ? kept.v0 > -1
                                       : kept.v1 < 1;
        if (excluded && exactTileTruth(*in.camera, in.lens, in.tile, in.box, strips[k]).hit)
            return true;
    }
    return false;
}

CheckResult judgeBoxVariant(const TileTestVariant& variant, const TileTestInput& in,
                            const CaseTruth& truth) {
    const TileTestOutput out = variant.run(in);
    CheckResult r;
    r.accept = out.accept;
    r.times = out.accept ? out.times : TimeRange::empty();
    if (!truth.exact.hit) {
        r.outcome = out.accept ? Outcome::FalseAccept : Outcome::TrueReject;
        return r;
    }
    bool missed =
        !out.accept || out.times.lower > truth.exact.times.lower ||
        out.times.upper < truth.exact.times.upper ||
        (!(out.lens.u0 <= -1 && out.lens.u1 >= 1 && out.lens.v0 <= -1 && out.lens.v1 >= 1) &&
         hitOutsideLensRect(in, out.lens));
    for (const WitnessHit& h : truth.witness)
        missed = missed || !out.times.contains(h.time) || !out.lens.contains(h.lens);
    r.outcome = missed ? Outcome::FalseReject : Outcome::TrueAccept;
    if (!missed) r.excess = width(out.times) - width(truth.exact.times);
    return r;
}

CaseTruth boxTruth(const TileTestInput& in, bool witnessed, std::int64_t& outsideTruth) {
    CaseTruth truth;
    truth.exact = exactTileTruth(*in.camera, in.lens, in.tile, in.box);
    if (!witnessed) return truth;
    truth.witness = sampledWitness(*in.camera, in.lens, in.tile, in.box);
    constexpr float kTolerance = 1e-4f;  // the witness's float rays against the double truth
    for (const WitnessHit& h : truth.witness)
        if (!truth.exact.hit || h.time < truth.exact.times.lower - kTolerance ||
            h.time > truth.exact.times.upper + kTolerance)
            ++outsideTruth;
    return truth;
}

// ---- Hierarchy checks ----

constexpr BoundsSpace kSpaces[] = {BoundsSpace::Camera3D, BoundsSpace::Homogeneous2D,
                                   BoundsSpace::Screen2D};
constexpr BranchMethod kBranchMethods[] = {BranchMethod::Root, BranchMethod::FirstSplit,
                                           BranchMethod::Bitmask};
constexpr int kBoundsLevels = 4;

std::vector<std::string> hierarchyCheckNames() {
    std::vector<std::string> names;
    for (BoundsSpace s : kSpaces) names.push_back(std::string("traversal-") + boundsSpaceName(s));
    for (BoundsSpace s : kSpaces)
        names.push_back(std::string("traversal-") + boundsSpaceName(s) + "-every-level");
    for (BranchMethod m : kBranchMethods)
        names.push_back(std::string("branch-") + branchMethodName(m));
    for (int l = 0; l < kBoundsLevels; ++l) names.push_back("bounds-level-" + std::to_string(l));
    for (int l = 0; l < kBoundsLevels; ++l) names.push_back("bounds-2d-level-" + std::to_string(l));
    return names;
}

bool isAncestorOrSelf(int ancestor, int node) {
    while (node > ancestor) node = (node - 1) / 2;
    return node == ancestor;
}

int lowestCommonAncestor(int a, int b) {
    while (a != b) (a > b ? a : b) = ((a > b ? a : b) - 1) / 2;
    return a;
}

struct HierarchyTruth {
    std::uint64_t hitLeaves = 0;
    TimeRange times = TimeRange::empty();
    std::vector<TimeRange> leafTimes;
};

HierarchyTruth hierarchyTruth(const HierarchyCase& c) {
    HierarchyTruth truth;
    const PatchHierarchy& h = c.hierarchy;
    for (int leaf = 0; leaf < h.leafCount(); ++leaf) {
        const TileTruth t = exactTileTruth(verifierCamera(), c.lens, c.tile(),
                                           h.node(PatchHierarchy::firstLeaf(h.depth()) + leaf));
        truth.leafTimes.push_back(t.times);
        if (!t.hit) continue;
        truth.hitLeaves |= std::uint64_t(1) << leaf;
        truth.times.extend(t.times);
    }
    return truth;
}

CheckResult judgeTraversal(const HierarchyCase& c, const HierarchyTruth& truth,
                           const TileTraversal& t) {
    CheckResult r;
    r.accept = t.overlaps;
    r.times = t.overlaps ? t.times : TimeRange::empty();
    if (truth.hitLeaves == 0) {
        r.outcome = t.overlaps ? Outcome::FalseAccept : Outcome::TrueReject;
        return r;
    }
    // Every leaf the truth hits is kept, and its own time interval (which gates the rays that
    // reach it) covers the truth's.
    bool missed = (truth.hitLeaves & ~t.leafMask) != 0;
    for (int leaf = 0; leaf < c.hierarchy.leafCount() && !missed; ++leaf)
        if (truth.hitLeaves >> leaf & 1)
            missed =
                t.leafTimes[std::size_t(leaf)].lower > truth.leafTimes[std::size_t(leaf)].lower ||
                t.leafTimes[std::size_t(leaf)].upper < truth.leafTimes[std::size_t(leaf)].upper;
    r.outcome = missed ? Outcome::FalseReject : Outcome::TrueAccept;
    if (!missed) r.excess = width(t.times) - width(truth.times);
    return r;
}

// The branch node must lie above every leaf the truth hits; its excess is the levels above the
// lowest such node.
CheckResult judgeBranch(const HierarchyCase& c, const HierarchyTruth& truth, int branch) {
    CheckResult r;
    r.accept = true;
    if (truth.hitLeaves == 0) return r;  // nothing to start from
    const PatchHierarchy& h = c.hierarchy;
    int lowest = -1;
    bool missed = false;
    for (int leaf = 0; leaf < h.leafCount(); ++leaf) {
        if (!(truth.hitLeaves >> leaf & 1)) continue;
        const int node = PatchHierarchy::firstLeaf(h.depth()) + leaf;
        missed = missed || !isAncestorOrSelf(branch, node);
        lowest = lowest < 0 ? node : lowestCommonAncestor(lowest, node);
    }
    r.outcome = missed ? Outcome::FalseReject : Outcome::TrueAccept;
    if (!missed) r.excess = h.levelOf(lowest) - h.levelOf(branch);
    return r;
}

// `screenNodes` empty: the bounds from the 3D boxes; else from the 2D space's nodes.
CheckResult judgeBounds(const HierarchyCase& c, const HierarchyTruth& truth, int level,
                        const std::vector<ScreenMovingBox>& screenNodes) {
    const Camera& camera = verifierCamera();
    const TileGrid grid{camera.width(), camera.height(), c.tileSize};
    const TileRange covered =
        tilesCovering(screenNodes.empty() ? screenBounds(c.hierarchy, level, camera, c.lens)
                                          : screenBounds(c.hierarchy, level, camera, screenNodes),
                      grid);
    CheckResult r;
    r.accept = c.tileX >= covered.x0 && c.tileX < covered.x1 && c.tileY >= covered.y0 &&
               c.tileY < covered.y1;
    if (truth.hitLeaves == 0)
        r.outcome = r.accept ? Outcome::FalseAccept : Outcome::TrueReject;
    else
        r.outcome = r.accept ? Outcome::TrueAccept : Outcome::FalseReject;
    return r;
}

std::vector<CheckResult> hierarchyChecks(const HierarchyCase& c, const HierarchyTruth& truth) {
    std::vector<CheckResult> results;
    const Camera& camera = verifierCamera();
    TileTraversal cameraSpace;
    SpaceNodes nodes;
    for (TimeRefinement refine : {TimeRefinement::Leaves, TimeRefinement::EveryLevel})
        for (BoundsSpace s : kSpaces) {
            RasterWork work;
            nodes.build(c.hierarchy, s, camera, c.lens, work);
            const TileTraversal t =
                traverseTile(c.hierarchy, nodes, {&camera, c.lens, c.tile(), camera.farPlane()},
                             true, refine, work);
            if (s == BoundsSpace::Camera3D && refine == TimeRefinement::Leaves) cameraSpace = t;
            results.push_back(judgeTraversal(c, truth, t));
        }
    for (BranchMethod m : kBranchMethods)
        results.push_back(judgeBranch(
            c, truth, cameraSpace.overlaps ? branchNode(m, cameraSpace, c.hierarchy.depth()) : 0));
    for (int l = 0; l < kBoundsLevels; ++l) results.push_back(judgeBounds(c, truth, l, {}));
    // `nodes` holds the 2D space's, built last.
    for (int l = 0; l < kBoundsLevels; ++l)
        results.push_back(judgeBounds(c, truth, l, nodes.screen));
    return results;
}

// ---- The run ----

void tally(TileTestReport& report, const CheckResult& r, CaseModel model, std::int64_t number) {
    ++report.cases;
    switch (r.outcome) {
        case Outcome::TrueAccept:
            ++report.trueHits;
            break;
        case Outcome::FalseReject:
            ++report.trueHits;
            ++report.falseRejects;
            if (report.firstFailure.empty()) report.firstFailure = caseName(model, number);
            break;
        case Outcome::FalseAccept:
            ++report.trueMisses;
            ++report.falseAccepts;
            break;
        case Outcome::TrueReject:
            ++report.trueMisses;
            break;
    }
    if (r.excess >= 0) report.excess.add(r.excess);
}

void csvRow(std::ostream& out, CaseModel model, std::int64_t number, const std::string& kind,
            const std::string& check, bool truthHit, const TimeRange& truthTimes,
            const CheckResult& r) {
    char line[320];
    std::snprintf(line, sizeof line, "%s,%lld,%s,%s,%d,%.7g,%.7g,%d,%.7g,%.7g,%s,%.7g\n",
                  caseModelName(model), static_cast<long long>(number), kind.c_str(), check.c_str(),
                  int(truthHit), truthHit ? double(truthTimes.lower) : 0.0,
                  truthHit ? double(truthTimes.upper) : 0.0, int(r.accept),
                  r.accept ? double(r.times.lower) : 0.0, r.accept ? double(r.times.upper) : 0.0,
                  outcomeName(r.outcome), std::max(0.0, r.excess));
    out << line;
}

// The reports of one chunk of cases of one model (merged in chunk order afterwards).
struct Chunk {
    std::vector<TileTestReport> reports;
    std::int64_t witnessCases = 0, witnessHits = 0, witnessOutsideTruth = 0;
    std::string csv;
};

TileTestReport emptyReport(const std::string& name, CaseModel model) {
    TileTestReport r;
    r.name = name;
    r.model = model;
    return r;
}

std::vector<TileTestReport> emptyReports(CaseModel model) {
    std::vector<TileTestReport> reports;
    if (model == CaseModel::Hierarchy) {
        for (const std::string& name : hierarchyCheckNames()) {
            reports.push_back(emptyReport(name, model));
            if (name.rfind("branch-", 0) == 0) {
                reports.back().excess.binWidth = 1.0;
                reports.back().excessUnit = "levels";
            }
        }
        return reports;
    }
    for (const auto& v : registeredTileTests())
        if (model == CaseModel::Lens ? v->handlesLens() : v->handlesPinhole()) {
            reports.push_back(emptyReport(v->name(), model));
            reports.back().lossy = v->lossy();
        }
    return reports;
}

void runBoxCases(const TileVerifierOptions& o, CaseModel model, std::int64_t begin,
                 std::int64_t end, Chunk& chunk) {
    std::vector<const TileTestVariant*> variants;
    for (const auto& v : registeredTileTests())
        if (model == CaseModel::Lens ? v->handlesLens() : v->handlesPinhole())
            variants.push_back(v.get());
    for (std::int64_t n = begin; n < end; ++n) {
        const BoxCase c = makeBoxCase(o.seed, model, n, o.family);
        const bool witnessed = o.witnessEvery > 0 && n % o.witnessEvery == 0;
        const CaseTruth truth = boxTruth(c.input, witnessed, chunk.witnessOutsideTruth);
        chunk.witnessCases += witnessed;
        chunk.witnessHits += std::int64_t(truth.witness.size());
        for (std::size_t v = 0; v < variants.size(); ++v) {
            const CheckResult r = judgeBoxVariant(*variants[v], c.input, truth);
            tally(chunk.reports[v], r, model, n);
            if (o.csv) {
                std::ostringstream row;
                csvRow(row, model, n, boxCaseKindName(c.kind), variants[v]->name(), truth.exact.hit,
                       truth.exact.times, r);
                chunk.csv += row.str();
            }
        }
    }
}

void runHierarchyCases(const TileVerifierOptions& o, std::int64_t begin, std::int64_t end,
                       Chunk& chunk) {
    const std::vector<std::string> names = hierarchyCheckNames();
    HierarchyCase c;
    for (std::int64_t n = begin; n < end; ++n) {
        makeHierarchyCase(o.seed, n, c);
        const HierarchyTruth truth = hierarchyTruth(c);
        const std::vector<CheckResult> results = hierarchyChecks(c, truth);
        for (std::size_t k = 0; k < results.size(); ++k) {
            tally(chunk.reports[k], results[k], CaseModel::Hierarchy, n);
            if (o.csv) {
                std::ostringstream row;
                csvRow(row, CaseModel::Hierarchy, n, c.lens.radius > 0 ? "lens" : "pinhole",
                       names[k], truth.hitLeaves != 0, truth.times, results[k]);
                chunk.csv += row.str();
            }
        }
    }
}

void mergeChunk(TileVerifierResult& result, std::size_t offset, const Chunk& chunk) {
    for (std::size_t k = 0; k < chunk.reports.size(); ++k) {
        TileTestReport& into = result.reports[offset + k];
        const TileTestReport& from = chunk.reports[k];
        into.cases += from.cases;
        into.trueHits += from.trueHits;
        into.trueMisses += from.trueMisses;
        into.falseRejects += from.falseRejects;
        into.falseAccepts += from.falseAccepts;
        into.excess.merge(from.excess);
        if (into.firstFailure.empty()) into.firstFailure = from.firstFailure;
    }
    result.witnessCases += chunk.witnessCases;
    result.witnessHits += chunk.witnessHits;
    result.witnessOutsideTruth += chunk.witnessOutsideTruth;
}

}  // namespace

TileVerifierResult verifyTileTests(const TileVerifierOptions& o) {
    constexpr std::int64_t kChunk = 2048;
    const int threads = resolveThreadCount(o.threads);
    TileVerifierResult result;
    if (o.csv)
        *o.csv << "model,case,kind,variant,truth_hit,true_tmin,true_tmax,accept,tmin,tmax,"
                  "outcome,excess\n";
    for (CaseModel model : {CaseModel::Pinhole, CaseModel::Lens, CaseModel::Hierarchy}) {
        const std::size_t offset = result.reports.size();
        for (TileTestReport& r : emptyReports(model)) result.reports.push_back(std::move(r));
        const std::int64_t chunks = (o.cases + kChunk - 1) / kChunk;
        // Batches of chunks keep the CSV text in memory small and its rows in case order.
        const std::int64_t batch = std::int64_t(threads) * 8;
        for (std::int64_t first = 0; first < chunks; first += batch) {
            std::vector<Chunk> work(std::size_t(std::min(batch, chunks - first)));
            parallelFor(work.size(), threads, [&](int, std::size_t i) {
                const std::int64_t begin = (first + std::int64_t(i)) * kChunk;
                const std::int64_t end = std::min(o.cases, begin + kChunk);
                work[i].reports = emptyReports(model);
                if (model == CaseModel::Hierarchy)
                    runHierarchyCases(o, begin, end, work[i]);
                else
                    runBoxCases(o, model, begin, end, work[i]);
            });
            for (const Chunk& chunk : work) {
                mergeChunk(result, offset, chunk);
                if (o.csv) *o.csv << chunk.csv;
            }
        }
    }
    return result;
}

bool replayTileCase(const std::string& name, std::uint64_t seed, std::ostream& out,
                    CaseFamily family) {
    CaseModel model;
    std::int64_t number;
    if (!parseCaseName(name, model, number)) return false;
    out << "case " << name << " (seed " << seed << ")\n";
    char line[256];
    if (model == CaseModel::Hierarchy) {
        HierarchyCase c;
        makeHierarchyCase(seed, number, c);
        printHierarchyCase(c, out);
        const HierarchyTruth truth = hierarchyTruth(c);
        std::snprintf(line, sizeof line, "truth: leaves hit 0x%llx, times [%.9g, %.9g]\n",
                      static_cast<unsigned long long>(truth.hitLeaves), double(truth.times.lower),
                      double(truth.times.upper));
        out << line;
        const std::vector<std::string> names = hierarchyCheckNames();
        const std::vector<CheckResult> results = hierarchyChecks(c, truth);
        for (std::size_t k = 0; k < results.size(); ++k) {
            std::snprintf(line, sizeof line, "%s: %s, accept %d, times [%.9g, %.9g]\n",
                          names[k].c_str(), outcomeName(results[k].outcome), int(results[k].accept),
                          double(results[k].times.lower), double(results[k].times.upper));
            out << line;
        }
        return true;
    }
    const BoxCase c = makeBoxCase(seed, model, number, family);
    printBoxCase(c, out);
    std::int64_t outside = 0;
    const CaseTruth truth = boxTruth(c.input, true, outside);
    std::snprintf(line, sizeof line,
                  "truth: hit %d, times [%.9g, %.9g]; witness: %zu sampled hits, %lld outside\n",
                  int(truth.exact.hit), double(truth.exact.times.lower),
                  double(truth.exact.times.upper), truth.witness.size(),
                  static_cast<long long>(outside));
    out << line;
    for (const auto& v : registeredTileTests()) {
        if (!(model == CaseModel::Lens ? v->handlesLens() : v->handlesPinhole())) continue;
        const TileTestOutput o = v->run(c.input);
        const CheckResult r = judgeBoxVariant(*v, c.input, truth);
        std::snprintf(line, sizeof line,
                      "%s: %s, accept %d, times [%.9g, %.9g], lens u [%.6g, %.6g] v [%.6g, %.6g]\n",
                      v->name().c_str(), outcomeName(r.outcome), int(o.accept),
                      double(o.times.lower), double(o.times.upper), double(o.lens.u0),
                      double(o.lens.u1), double(o.lens.v0), double(o.lens.v1));
        out << line;
    }
    return true;
}

}  // namespace patchsim
