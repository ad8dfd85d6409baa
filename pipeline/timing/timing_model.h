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
// When the hardware models memory, the memory system is one more server after OM, with its own
// FIFO (memory_model.h gives each patch's line accesses and DRAM bytes): a patch's OM cannot
// deliver while that FIFO is full, so a busy memory system stalls the stages before it.

#include <array>
#include <cstdint>
#include <optional>
#include <ostream>
#include <vector>

#include "pipeline/timing/hardware_config.h"
#include "pipeline/timing/memory_model.h"

namespace patchsim {

struct StageTiming {
    double busy = 0, stalled = 0, starved = 0;
    double utilisation = 0;  // busy / total
};

// Stage s's times at index s; with memory modelled, the memory system's at kStageCount.
inline constexpr int kMemoryServer = kStageCount;
struct PatchTimeline {
    std::array<double, kStageCount + 1> start{}, finish{}, delivered{};
};

// The memory system as the timing model sees it: one server after OM whose service time for a
// patch is the longest of its parts (each cache's line accesses at its rate, DRAM's bytes at its
// bandwidth or, with banks, its channels', banks' and activations' time: dram_banks.h; with a limit
// on reads in flight, its DRAM reads x latency / that limit, Little's law), since they work side by
// side. The caches, then DRAM, then DRAM's reads in flight (memory.dram.max_reads_in_flight).
inline constexpr int kMemoryParts = kCacheClients + 2;
inline constexpr int kDramPart = kCacheClients, kReadsInFlightPart = kCacheClients + 1;
const char* memoryPartTitle(int part);  // "depth cache", ..., "DRAM", "DRAM reads in flight"
struct MemoryTiming {
    StageTiming server;
    std::array<double, kMemoryParts> busy{};         // cycles each part needed
    std::array<double, kMemoryParts> utilisation{};  // busy / total
    double dramBytesPerCycle = 0;                    // achieved over the frame
};

struct TimingReport {
    double totalCycles = 0;
    std::array<StageTiming, kStageCount> stages{};
    std::optional<Stage> bottleneck;  // the busiest stage; none when no stage did any work
    // Set when the memory system is modelled; `memoryBound` when it is busier than every stage,
    // and then the bottleneck is its busiest part.
    std::optional<MemoryTiming> memory;
    bool memoryBound = false;
    int memoryBottleneck = 0;
    const char* bottleneckName() const {
        if (memoryBound) return memoryPartTitle(memoryBottleneck);
        return bottleneck ? stageName(*bottleneck) : "none";
    }
    double bottleneckUtilisation() const;
    std::uint64_t peakScratchBytes = 0;
    std::size_t patchesOverBudget = 0;
    std::vector<PatchTimeline> patches;
    double clockGHz = 1;

    double microseconds() const { return totalCycles / (clockGHz * 1000.0); }
};

// Service time of one patch at one stage.
double serviceCycles(const PatchOps& ops, const HardwareConfig& config, Stage stage);

// With `memory` (and config.memory), each patch also passes through the memory system.
TimingReport simulateTiming(const std::vector<PatchOps>& patches, const HardwareConfig& config,
                            const MemoryReport* memory = nullptr);

// The memory server's service time of one patch, and each part's share of it.
double memoryCycles(const PatchMemory& patch, const MemoryConfig& config,
                    std::array<double, kMemoryParts>& parts);

// Chrome trace-event JSON (chrome://tracing, Perfetto): one track per stage, one slice per patch,
// times in microseconds at the configured clock.
// With the memory system modelled (and its report given), a "memory" track and a counter
// track of DRAM bandwidth in GB/s.
void writeChromeTrace(const TimingReport& report, std::ostream& out,
                      const MemoryReport* memory = nullptr);

void printTimingReport(const TimingReport& report, std::ostream& out);

}  // namespace patchsim
