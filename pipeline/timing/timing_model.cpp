#include "pipeline/timing/timing_model.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace patchsim {

double serviceCycles(const PatchOps& ops, const HardwareConfig& config, Stage stage) {
    const StageConfig& s = config.stage(stage);
    double cycles = 0;
    for (int k = 0; k < kOpCount; ++k) {
        if (stageOf(Op(k)) != stage || ops.ops[std::size_t(k)] == 0) continue;
        cycles += ops.ops[std::size_t(k)] / (s.throughput[std::size_t(k)] * double(s.units));
    }
    return cycles;
}

const char* memoryPartTitle(int part) {
    if (part < kCacheClients) return cacheClientTitle(CacheClient(part));
    return part == kDramPart ? "DRAM" : "DRAM reads in flight";
}

double TimingReport::bottleneckUtilisation() const {
    if (memoryBound) return memory->utilisation[std::size_t(memoryBottleneck)];
    return bottleneck ? stages[std::size_t(*bottleneck)].utilisation : 0.0;
}

double memoryCycles(const PatchMemory& patch, const MemoryConfig& config,
                    std::array<double, kMemoryParts>& parts) {
    double cycles = 0;
    for (int c = 0; c < kCacheClients; ++c) {
        parts[std::size_t(c)] = double(patch.lineAccesses[std::size_t(c)]) /
                                config.caches[std::size_t(c)].linesPerClock;
        cycles = std::max(cycles, parts[std::size_t(c)]);
    }
    // An ideal bus moves the patch's bytes at its rate; with banks, the longest of its channels'
    // bus, banks' and activations' loads (dram_banks.h), never less.
    parts[kDramPart] = config.dramBanks.modelled()
                           ? patch.dramCycles
                           : double(patch.dramBytes) / config.dramBytesPerClock;
    // Each read holds one of the reads in flight for DRAM's latency: at most that many reads
    // per latency (Little's law). Writes are posted and wait for nothing.
    parts[kReadsInFlightPart] =
        config.dramReadsInFlight > 0
            ? double(patch.dramReads) * config.dramLatency / double(config.dramReadsInFlight)
            : 0.0;
    return std::max({cycles, parts[kDramPart], parts[kReadsInFlightPart]});
}

namespace {

// The servers a patch passes through, in order: the stages, then the memory system if modelled.
struct Servers {
    const HardwareConfig& config;
    const MemoryReport* memory;
    int count() const { return kStageCount + (memory ? 1 : 0); }
    double latency(int s) const {
        return s < kStageCount ? config.stages[std::size_t(s)].latency : config.memory->dramLatency;
    }
    int fifoDepth(int s) const {
        return s < kStageCount ? config.stages[std::size_t(s)].fifoDepth : config.memory->fifoDepth;
    }
};

}  // namespace

TimingReport simulateTiming(const std::vector<PatchOps>& patches, const HardwareConfig& config,
                            const MemoryReport* memory) {
    TimingReport report;
    report.clockGHz = config.clockGHz;
    report.patches.resize(patches.size());
    const Servers servers{config, config.memory && memory ? memory : nullptr};
    StageTiming memoryServer;
    MemoryTiming memoryTiming;
    std::array<double, kMemoryParts> parts{};
    for (std::size_t p = 0; p < patches.size(); ++p) {
        PatchTimeline& t = report.patches[p];
        for (int s = 0; s < servers.count(); ++s) {
            const auto at = std::size_t(s);
            const double arrival = s == 0 ? 0.0 : t.delivered[at - 1] + servers.latency(s - 1);
            const double free = p == 0 ? 0.0 : report.patches[p - 1].delivered[at];
            t.start[at] = std::max(arrival, free);
            double busy = 0;
            if (s < kStageCount) {
                busy = serviceCycles(patches[p], config, Stage(s));
            } else {
                busy = memoryCycles(servers.memory->patches[p], *config.memory, parts);
                for (int k = 0; k < kMemoryParts; ++k)
                    memoryTiming.busy[std::size_t(k)] += parts[std::size_t(k)];
            }
            t.finish[at] = t.start[at] + busy;
            // Deliver into the next server's FIFO once it has room: it must have taken patch
            // p - depth.
            double delivered = t.finish[at];
            if (s + 1 < servers.count()) {
                const int depth = servers.fifoDepth(s + 1);
                if (p >= std::size_t(depth))
                    delivered =
                        std::max(delivered, report.patches[p - std::size_t(depth)].start[at + 1]);
            }
            t.delivered[at] = delivered;
            StageTiming& st = s < kStageCount ? report.stages[at] : memoryServer;
            st.busy += busy;
            st.stalled += delivered - t.finish[at];
            st.starved += t.start[at] - free;
        }
        report.peakScratchBytes = std::max(report.peakScratchBytes, patches[p].hierarchyBytes);
        report.patchesOverBudget += patches[p].hierarchyBytes > config.scratchBudgetBytes;
    }
    if (!patches.empty()) {
        const int last = servers.count() - 1;
        report.totalCycles =
            report.patches.back().delivered[std::size_t(last)] + servers.latency(last);
    }
    const auto share = [&](double busy) {
        return report.totalCycles > 0 ? busy / report.totalCycles : 0.0;
    };
    double busiest = 0;
    for (int s = 0; s < kStageCount; ++s) {
        StageTiming& st = report.stages[std::size_t(s)];
        st.utilisation = share(st.busy);
        if (st.busy > busiest) {
            busiest = st.busy;
            report.bottleneck = Stage(s);
        }
    }
    if (servers.memory) {
        memoryServer.utilisation = share(memoryServer.busy);
        memoryTiming.server = memoryServer;
        for (int k = 0; k < kMemoryParts; ++k) {
            memoryTiming.utilisation[std::size_t(k)] = share(memoryTiming.busy[std::size_t(k)]);
            if (memoryTiming.busy[std::size_t(k)] >
                memoryTiming.busy[std::size_t(report.memoryBottleneck)])
                report.memoryBottleneck = k;
        }
        memoryTiming.dramBytesPerCycle =
            report.totalCycles > 0 ? double(servers.memory->dramBytes()) / report.totalCycles : 0.0;
        report.memoryBound = memoryServer.busy > busiest;
        report.memory = memoryTiming;
    }
    return report;
}

void writeChromeTrace(const TimingReport& report, std::ostream& out, const MemoryReport* memory) {
    nlohmann::ordered_json events = nlohmann::ordered_json::array();
    const int servers = kStageCount + (report.memory && memory ? 1 : 0);
    for (int s = 0; s < servers; ++s) {
        events.push_back({{"name", "thread_name"},
                          {"ph", "M"},
                          {"pid", 0},
                          {"tid", s},
                          {"args", {{"name", s < kStageCount ? stageName(Stage(s)) : "memory"}}}});
        events.push_back({{"name", "thread_sort_index"},
                          {"ph", "M"},
                          {"pid", 0},
                          {"tid", s},
                          {"args", {{"sort_index", s}}}});
    }
    const double usPerCycle = 1.0 / (report.clockGHz * 1000.0);
    for (std::size_t p = 0; p < report.patches.size(); ++p) {
        const PatchTimeline& t = report.patches[p];
        for (int s = 0; s < servers; ++s) {
            const double start = t.start[std::size_t(s)], finish = t.finish[std::size_t(s)];
            if (finish <= start) continue;
            if (s == kMemoryServer) {
                // DRAM bandwidth while the memory system serves this patch, in GB/s.
                const double bytes = double(memory->patches[p].dramBytes);
                const double gbPerSecond = bytes / (finish - start) * report.clockGHz;
                for (const auto& [at, value] : {std::pair{start, gbPerSecond}, {finish, 0.0}})
                    events.push_back({{"name", "DRAM bandwidth"},
                                      {"ph", "C"},
                                      {"pid", 0},
                                      {"ts", at * usPerCycle},
                                      {"args", {{"GB/s", value}}}});
            }
            events.push_back({{"name", "patch " + std::to_string(p)},
                              {"cat", s < kStageCount ? stageName(Stage(s)) : "memory"},
                              {"ph", "X"},
                              {"pid", 0},
                              {"tid", s},
                              {"ts", start * usPerCycle},
                              {"dur", (finish - start) * usPerCycle},
                              {"args",
                               {{"patch", p},
                                {"start_cycle", start},
                                {"busy_cycles", finish - start},
                                {"stalled_cycles", t.delivered[std::size_t(s)] - finish}}}});
        }
    }
    out << nlohmann::ordered_json{{"traceEvents", events}, {"displayTimeUnit", "ns"}}.dump()
        << "\n";
}

void printTimingReport(const TimingReport& r, std::ostream& out) {
    char line[160];
    std::snprintf(line, sizeof line, "timing: %.0f cycles (%.3f us at %.2f GHz), bottleneck %s\n",
                  r.totalCycles, r.microseconds(), r.clockGHz, r.bottleneckName());
    out << line;
    out << "  stage        busy     stalled     starved  utilisation\n";
    for (int s = 0; s < kStageCount; ++s) {
        const StageTiming& st = r.stages[std::size_t(s)];
        std::snprintf(line, sizeof line, "  %-5s %11.0f %11.0f %11.0f  %10.1f%%\n",
                      stageName(Stage(s)), st.busy, st.stalled, st.starved, 100.0 * st.utilisation);
        out << line;
    }
    if (r.memory) {
        const MemoryTiming& m = *r.memory;
        std::snprintf(line, sizeof line, "  %-5s %11.0f %11.0f %11.0f  %10.1f%%\n", "MEM",
                      m.server.busy, m.server.stalled, m.server.starved,
                      100.0 * m.server.utilisation);
        out << line;
        for (int k = 0; k < kMemoryParts; ++k) {
            std::snprintf(line, sizeof line, "    %-18s %11.0f busy  %10.1f%%\n",
                          memoryPartTitle(k), m.busy[std::size_t(k)],
                          100.0 * m.utilisation[std::size_t(k)]);
            out << line;
        }
    }
    std::snprintf(line, sizeof line, "  peak scratch %llu bytes, %zu patches over the budget\n",
                  static_cast<unsigned long long>(r.peakScratchBytes), r.patchesOverBudget);
    out << line;
}

}  // namespace patchsim
