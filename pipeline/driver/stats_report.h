#pragma once
// Counter reports: a human table and the stats JSON (schema in docs/COUNTERS.md).

#include <ostream>
#include <string>
#include <vector>

#include "core/counters.h"
#include "pipeline/timing/energy_model.h"
#include "pipeline/timing/timing_model.h"

namespace patchsim {

inline constexpr int kStatsSchemaVersion = 1;

struct StatsContext {
    std::string command;                                     // "tessellate", "info", ...
    std::string scene;                                       // scene path
    std::vector<std::pair<std::string, std::string>> facts;  // extra key/value lines
    // The options the job ran with (job_options.h, rasterizer_options.h), by their stats key.
    std::vector<std::pair<std::string, std::string>> options;
    const TimingReport* timing = nullptr;  // cycle report, when modelled
    const MemoryReport* memory = nullptr;  // memory traffic, when the hardware models memory
    const EnergyReport* energy = nullptr;  // the frame's modelled energy, with the timing
};

void printCounterTable(std::ostream& out, const CounterValues& values);
void writeStatsJson(std::ostream& out, const StatsContext& context, const CounterValues& values);

}  // namespace patchsim
