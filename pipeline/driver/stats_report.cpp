#include "pipeline/driver/stats_report.h"

#include <cstdio>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>

#include "rasterizer/patent/raster_work.h"

namespace patchsim {

namespace {
std::map<std::string, CounterInfo> infoByName() {
    std::map<std::string, CounterInfo> byName;
    for (const CounterInfo& info : CounterRegistry::instance().infos())
        byName.emplace(info.name, info);
    return byName;
}
}  // namespace

void printCounterTable(std::ostream& out, const CounterValues& counterValues) {
    const auto infos = infoByName();
    const auto values = counterValues.byName();
    std::size_t width = 0;
    for (const auto& [name, value] : values) width = std::max(width, name.size());
    std::string stage;
    for (const auto& [name, value] : values) {
        const std::string thisStage = name.substr(0, name.find('/'));
        if (thisStage != stage) {
            stage = thisStage;
            out << stage << "\n";
        }
        const auto it = infos.find(name);
        out << "  " << std::left << std::setw(int(width) + 2) << name << std::right << std::setw(16)
            << value << "  " << (it != infos.end() ? it->second.unit : "") << "\n";
    }
    const RatioCounter& ste = sampleTestEfficiency();
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "%16.4f", counterValues.ratio(ste));
    out << "  " << std::left << std::setw(int(width) + 2) << ste.name << ratio << "  ratio\n";
}

void writeStatsJson(std::ostream& out, const StatsContext& context,
                    const CounterValues& counterValues) {
    const auto infos = infoByName();
    const auto values = counterValues.byName();
    nlohmann::ordered_json json;
    json["schema"] = "patchsim-stats";
    json["version"] = kStatsSchemaVersion;
    json["command"] = context.command;
    json["scene"] = context.scene;
    for (const auto& [key, value] : context.facts) json["facts"][key] = value;
    for (const auto& [key, value] : context.options) json["options"][key] = value;
    nlohmann::ordered_json counters = nlohmann::ordered_json::object();
    for (const auto& [name, value] : values) {
        const auto it = infos.find(name);
        counters[name] = {{"value", value}, {"unit", it != infos.end() ? it->second.unit : ""}};
    }
    json["counters"] = counters;
    if (context.timing) {
        const TimingReport& t = *context.timing;
        nlohmann::ordered_json stages = nlohmann::ordered_json::object();
        for (int s = 0; s < kStageCount; ++s) {
            const StageTiming& st = t.stages[std::size_t(s)];
            stages[stageName(Stage(s))] = {{"busy_cycles", st.busy},
                                           {"stalled_cycles", st.stalled},
                                           {"starved_cycles", st.starved},
                                           {"utilisation", st.utilisation}};
        }
        json["timing"] = {{"total_cycles", t.totalCycles},
                          {"microseconds", t.microseconds()},
                          {"clock_ghz", t.clockGHz},
                          {"bottleneck", t.bottleneckName()},
                          {"peak_scratch_bytes", t.peakScratchBytes},
                          {"patches_over_scratch_budget", t.patchesOverBudget},
                          {"stages", stages}};
        if (t.memory) {
            const MemoryTiming& m = *t.memory;
            nlohmann::ordered_json parts = nlohmann::ordered_json::object();
            for (int k = 0; k < kMemoryParts; ++k)
                parts[memoryPartTitle(k)] = {{"busy_cycles", m.busy[std::size_t(k)]},
                                             {"utilisation", m.utilisation[std::size_t(k)]}};
            json["timing"]["memory"] = {{"busy_cycles", m.server.busy},
                                        {"stalled_cycles", m.server.stalled},
                                        {"starved_cycles", m.server.starved},
                                        {"utilisation", m.server.utilisation},
                                        {"bound", t.memoryBound},
                                        {"dram_bytes_per_cycle", m.dramBytesPerCycle},
                                        {"parts", parts}};
        }
    }
    if (context.memory) json["memory"] = memoryReportJson(*context.memory);
    if (context.energy) json["energy"] = energyReportJson(*context.energy);
    out << json.dump(2) << "\n";
}

}  // namespace patchsim
