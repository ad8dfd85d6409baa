#include "pipeline/timing/timing_model.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

// Every stage: one unit, throughput 1 for each of its ops, no latency, deep FIFOs.
HardwareConfig flatConfig() {
    HardwareConfig c;
    for (StageConfig& s : c.stages) {
        s.units = 1;
        s.latency = 0;
        s.fifoDepth = 64;
        s.throughput.fill(1.0);
    }
    return c;
}

std::vector<PatchOps> patchesWith(std::size_t n, std::initializer_list<std::pair<Op, double>> ops) {
    std::vector<PatchOps> patches(n);
    for (PatchOps& p : patches)
        for (auto [op, count] : ops) p[op] = count;
    return patches;
}

TEST(TimingModel, SingleStage) {
    HardwareConfig c = flatConfig();
    c.stage(Stage::IA).throughput[std::size_t(Op::Patches)] = 2;  // 4 ops at 2 per clock: 2 cycles
    const TimingReport r = simulateTiming(patchesWith(3, {{Op::Patches, 4}}), c);
    EXPECT_DOUBLE_EQ(r.totalCycles, 6);
    EXPECT_DOUBLE_EQ(r.stages[0].busy, 6);
    EXPECT_DOUBLE_EQ(r.stages[0].utilisation, 1.0);
    EXPECT_EQ(r.bottleneck, Stage::IA);
    // Two units halve it.
    c.stage(Stage::IA).units = 2;
    EXPECT_DOUBLE_EQ(simulateTiming(patchesWith(3, {{Op::Patches, 4}}), c).totalCycles, 3);
}

TEST(TimingModel, AFrameWithNoWorkHasNoBottleneck) {
    const TimingReport none = simulateTiming({}, flatConfig());
    EXPECT_FALSE(none.bottleneck.has_value());
    EXPECT_STREQ(none.bottleneckName(), "none");
    const TimingReport idle = simulateTiming(patchesWith(3, {}), flatConfig());
    EXPECT_FALSE(idle.bottleneck.has_value());
    std::ostringstream text;
    printTimingReport(idle, text);
    EXPECT_NE(text.str().find("bottleneck none"), std::string::npos) << text.str();
}

TEST(TimingModel, SecondStageIsTheBottleneck) {
    // IA takes 1 cycle per patch, VS 3: VS starts patches at 1, 4, 7, 10 and ends at 13.
    const HardwareConfig c = flatConfig();
    const TimingReport r =
        simulateTiming(patchesWith(4, {{Op::Patches, 1}, {Op::ControlPoints, 3}}), c);
    EXPECT_DOUBLE_EQ(r.totalCycles, 13);
    EXPECT_EQ(r.bottleneck, Stage::VS);
    EXPECT_DOUBLE_EQ(r.stages[1].busy, 12);
    EXPECT_DOUBLE_EQ(r.stages[1].starved, 1);  // waits for the first patch only
    EXPECT_DOUBLE_EQ(r.stages[0].stalled, 0);  // deep FIFO: IA never blocks
    EXPECT_DOUBLE_EQ(r.patches[3].start[1], 10);
}

TEST(TimingModel, ShallowFifoStallsTheStageBefore) {
    HardwareConfig c = flatConfig();
    c.stage(Stage::VS).fifoDepth = 1;
    const TimingReport r =
        simulateTiming(patchesWith(4, {{Op::Patches, 1}, {Op::ControlPoints, 3}}), c);
    // IA may deliver patch p only once VS has started patch p-1: blocked 0, 0, 1 and 2 cycles.
    EXPECT_DOUBLE_EQ(r.stages[0].stalled, 3);
    EXPECT_DOUBLE_EQ(r.patches[2].delivered[0], 4);
    EXPECT_DOUBLE_EQ(r.patches[3].delivered[0], 7);
    EXPECT_DOUBLE_EQ(r.totalCycles, 13);  // the bottleneck still sets the total
}

TEST(TimingModel, LatencyDelaysDelivery) {
    HardwareConfig c = flatConfig();
    c.stage(Stage::IA).latency = 5;
    c.stage(Stage::OM).latency = 2;
    const TimingReport r =
        simulateTiming(patchesWith(1, {{Op::Patches, 1}, {Op::ControlPoints, 1}}), c);
    EXPECT_DOUBLE_EQ(r.totalCycles, 1 + 5 + 1 + 2);
}

TEST(TimingModel, PatchOverTheScratchBudget) {
    HardwareConfig c = flatConfig();
    c.scratchBudgetBytes = 1000;
    std::vector<PatchOps> patches = patchesWith(3, {{Op::Patches, 1}});
    patches[0].hierarchyBytes = 900;
    patches[1].hierarchyBytes = 1500;
    patches[2].hierarchyBytes = 1000;
    const TimingReport r = simulateTiming(patches, c);
    EXPECT_EQ(r.patchesOverBudget, 1u);
    EXPECT_EQ(r.peakScratchBytes, 1500u);
}

TEST(TimingModel, ChromeTraceHasOneSlicePerPatchAndStage) {
    HardwareConfig c = flatConfig();
    c.clockGHz = 2;
    const TimingReport r =
        simulateTiming(patchesWith(2, {{Op::Patches, 2}, {Op::RayBoxTests, 4}}), c);
    std::ostringstream out;
    writeChromeTrace(r, out);
    const nlohmann::json trace = nlohmann::json::parse(out.str());
    int slices = 0;
    for (const auto& e : trace["traceEvents"]) {
        if (e["ph"] != "X") continue;
        ++slices;
        EXPECT_GT(e["dur"].get<double>(), 0.0);
    }
    EXPECT_EQ(slices, 4);  // IA and RS for two patches
    // 2 cycles at 2 GHz is 0.001 us.
    EXPECT_DOUBLE_EQ(trace["traceEvents"][16]["dur"].get<double>(), 0.001);
}

// Every method's counted work is charged: the reference method tests every sample against every
// triangle, far more rasterizer work than the patch method for the same frame.
TEST(TimingModel, TheReferenceMethodsWorkIsCharged) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/motion.json"));
    scene.film = {48, 32, 2, 1};
    const HardwareConfig hw = defaultHardwareConfig();
    const TimingReport patch = simulateTiming(renderScene(scene, {}).patchOps, hw);
    RenderOptions reference;
    reference.method = &methodNamed("reference");
    const TimingReport brute = simulateTiming(renderScene(scene, reference).patchOps, hw);
    EXPECT_GT(brute.stages[std::size_t(Stage::RS)].busy,
              10 * patch.stages[std::size_t(Stage::RS)].busy);
    EXPECT_GT(brute.totalCycles, patch.totalCycles);
    EXPECT_EQ(brute.bottleneck, Stage::RS);
}

}  // namespace
}  // namespace patchsim
