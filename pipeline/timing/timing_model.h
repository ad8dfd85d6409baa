#pragma once
// The cycle-approximate timing model: a streaming flow of patches through the eight pipeline
// stages (DESIGN.md section 8).
//
// Representation
// --------------
// Each patch carries its counted operations (PatchOps). A stage's service time for a patch is
// the sum over its operation kinds of ops / (throughput x units) cycles. Patches flow in order;
// stage s starts patch p when it has delivered patch p-1 and patch p has arrived (delivered by
// stage s-1 plus that stage's latency). A FIFO of depth D sits in front of every stage: stage s
// can only deliver patch p once stage s+1 has taken patch p-D out of its FIFO, so a full FIFO
// stalls the stage before it. From the resulting start, finish and delivery times come the total
// cycles, each stage's busy, stalled (finished but blocked) and starved (waiting for input)
// cycles, utilisation, the bottleneck, and a per-patch timeline (Chrome trace-event JSON).

#include <array>
#include <cstdint>
#include <optional>
#include <ostream>
#include <vector>

#include "pipeline/timing/hardware_config.h"

namespace patchsim {

struct StageTiming {
    double busy = 0, stalled = 0, starved = 0;
    double utilisation = 0;  // busy / total
};

struct PatchTimeline {
    std::array<double, kStageCount> start{}, finish{}, delivered{};
};

struct TimingReport {
    double totalCycles = 0;
    std::array<StageTiming, kStageCount> stages{};
    std::optional<Stage> bottleneck;  // the busiest stage; none when no stage did any work
    const char* bottleneckName() const { return bottleneck ? stageName(*bottleneck) : "none"; }
    std::uint64_t peakScratchBytes = 0;
    std::size_t patchesOverBudget = 0;
    std::vector<PatchTimeline> patches;
    double clockGHz = 1;

    double microseconds() const { return totalCycles / (clockGHz * 1000.0); }
};

// Service time of one patch at one stage.
double serviceCycles(const PatchOps& ops, const HardwareConfig& config, Stage stage);

TimingReport simulateTiming(const std::vector<PatchOps>& patches, const HardwareConfig& config);

// Chrome trace-event JSON (chrome://tracing, Perfetto): one track per stage, one slice per patch,
// times in microseconds at the configured clock.
void writeChromeTrace(const TimingReport& report, std::ostream& out);

void printTimingReport(const TimingReport& report, std::ostream& out);

}  // namespace patchsim
