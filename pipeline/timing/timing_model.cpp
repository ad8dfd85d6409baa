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

TimingReport simulateTiming(const std::vector<PatchOps>& patches, const HardwareConfig& config) {
    TimingReport report;
    report.clockGHz = config.clockGHz;
    report.patches.resize(patches.size());
    for (std::size_t p = 0; p < patches.size(); ++p) {
        PatchTimeline& t = report.patches[p];
        for (int s = 0; s < kStageCount; ++s) {
            const double arrival = s == 0 ? 0.0
                                          : report.patches[p].delivered[std::size_t(s - 1)] +
                                                config.stages[std::size_t(s - 1)].latency;
            const double free = p == 0 ? 0.0 : report.patches[p - 1].delivered[std::size_t(s)];
            t.start[std::size_t(s)] = std::max(arrival, free);
            const double busy = serviceCycles(patches[p], config, Stage(s));
            t.finish[std::size_t(s)] = t.start[std::size_t(s)] + busy;
            // Deliver into the next stage's FIFO once it has room: the next stage must have
            // taken patch p - depth.
            double delivered = t.finish[std::size_t(s)];
            if (s + 1 < kStageCount) {
                const int depth = config.stages[std::size_t(s + 1)].fifoDepth;
                if (p >= std::size_t(depth))
                    delivered =
                        std::max(delivered,
                                 report.patches[p - std::size_t(depth)].start[std::size_t(s + 1)]);
            }
            t.delivered[std::size_t(s)] = delivered;
            StageTiming& st = report.stages[std::size_t(s)];
            st.busy += busy;
            st.stalled += delivered - t.finish[std::size_t(s)];
            st.starved += t.start[std::size_t(s)] - free;
        }
        report.peakScratchBytes = std::max(report.peakScratchBytes, patches[p].hierarchyBytes);
        report.patchesOverBudget += patches[p].hierarchyBytes > config.scratchBudgetBytes;
    }
    if (!patches.empty())
        report.totalCycles =
            report.patches.back().delivered[kStageCount - 1] + config.stages.back().latency;
    double busiest = 0;
    for (int s = 0; s < kStageCount; ++s) {
        StageTiming& st = report.stages[std::size_t(s)];
        st.utilisation = report.totalCycles > 0 ? st.busy / report.totalCycles : 0.0;
        if (st.busy > busiest) {
            busiest = st.busy;
            report.bottleneck = Stage(s);
        }
    }
    return report;
}

void writeChromeTrace(const TimingReport& report, std::ostream& out) {
    nlohmann::ordered_json events = nlohmann::ordered_json::array();
    for (int s = 0; s < kStageCount; ++s) {
        events.push_back({{"name", "thread_name"},
                          {"ph", "M"},
                          {"pid", 0},
                          {"tid", s},
                          {"args", {{"name", stageName(Stage(s))}}}});
        events.push_back({{"name", "thread_sort_index"},
                          {"ph", "M"},
                          {"pid", 0},
                          {"tid", s},
                          {"args", {{"sort_index", s}}}});
    }
    const double usPerCycle = 1.0 / (report.clockGHz * 1000.0);
    for (std::size_t p = 0; p < report.patches.size(); ++p) {
        const PatchTimeline& t = report.patches[p];
        for (int s = 0; s < kStageCount; ++s) {
            const double start = t.start[std::size_t(s)], finish = t.finish[std::size_t(s)];
            if (finish <= start) continue;
            events.push_back({{"name", "patch " + std::to_string(p)},
                              {"cat", stageName(Stage(s))},
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
    std::snprintf(line, sizeof line, "  peak scratch %llu bytes, %zu patches over the budget\n",
                  static_cast<unsigned long long>(r.peakScratchBytes), r.patchesOverBudget);
    out << line;
}

}  // namespace patchsim
