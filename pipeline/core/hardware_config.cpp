#include "pipeline/core/hardware_config.h"

#include <cmath>

#include "pipeline/core/json_fields.h"
#include "pipeline/core/text_file.h"

namespace patchsim {

namespace {

constexpr const char* kStageNames[kStageCount] = {"IA", "VS", "HS", "TS", "DS", "RS", "PS", "OM"};
constexpr const char* kOpNames[kOpCount] = {"patches",
                                            "control_points",
                                            "edge_factors",
                                            "domain_points",
                                            "triangles",
                                            "evaluations",
                                            "stencil_applications",
                                            "nodes_built",
                                            "plane_tests",
                                            "time_intervals",
                                            "samples_tested",
                                            "ray_box_tests",
                                            "ray_triangle_tests",
                                            "invocations",
                                            "depth_tests",
                                            "transparent_fragments"};
constexpr Stage kOpStages[kOpCount] = {
    Stage::IA, Stage::VS, Stage::HS, Stage::TS, Stage::TS, Stage::DS, Stage::DS, Stage::RS,
    Stage::RS, Stage::RS, Stage::RS, Stage::RS, Stage::RS, Stage::PS, Stage::OM, Stage::OM};

int findOp(const std::string& name, Stage stage) {
    for (int k = 0; k < kOpCount; ++k)
        if (name == kOpNames[k] && kOpStages[k] == stage) return k;
    return -1;
}

void readStage(ObjectReader r, StageConfig& s, Stage stage) {
    s.units = int(r.integer("units", s.units, 1, 1 << 20));
    s.latency = r.number("latency", s.latency, 0, 1e9);
    s.fifoDepth = int(r.integer("fifo_depth", s.fifoDepth, 1, 1 << 20));
    if (auto t = r.object("throughput")) {
        for (int k = 0; k < kOpCount; ++k) {
            if (kOpStages[k] != stage) continue;
            s.throughput[std::size_t(k)] =
                t->number(kOpNames[k], s.throughput[std::size_t(k)], 1e-9, 1e9);
        }
        t->finish();
    }
    r.finish();
    for (int k = 0; k < kOpCount; ++k)
        if (kOpStages[k] == stage && !(s.throughput[std::size_t(k)] > 0))
            r.fail(r.fieldName("throughput." + std::string(kOpNames[k])),
                   "missing or not positive");
}

}  // namespace

const char* stageName(Stage s) {
    return kStageNames[int(s)];
}
const char* opName(Op op) {
    return kOpNames[int(op)];
}
Stage stageOf(Op op) {
    return kOpStages[int(op)];
}

HardwareConfig parseHardwareConfig(std::string_view text, const std::string& path) {
    const Json json = parseJson(text, path);
    HardwareConfig config;
    ObjectReader root(json, "", path);
    config.clockGHz = root.number("clock_ghz", config.clockGHz, 1e-6, 1e6);
    config.scratchBudgetBytes = std::uint64_t(root.integer(
        "scratch_budget_bytes", std::int64_t(config.scratchBudgetBytes), 1, std::int64_t(1) << 40));
    auto stages = root.object("stages");
    if (!stages) root.fail("stages", "missing the per-stage configuration");
    for (int s = 0; s < kStageCount; ++s) {
        auto stage = stages->object(kStageNames[s]);
        if (!stage) stages->fail(stages->fieldName(kStageNames[s]), "missing stage");
        readStage(*stage, config.stages[std::size_t(s)], Stage(s));
    }
    stages->finish();
    root.finish();
    return config;
}

HardwareConfig readHardwareConfig(const std::string& path) {
    return parseHardwareConfig(readTextFile(path), path);
}

HardwareConfig defaultHardwareConfig() {
    const auto text = builtinAsset("hw/default.json");
    if (!text) throw InputError("builtin:hw/default.json", "", "missing from the build");
    return parseHardwareConfig(*text, "builtin:hw/default.json");
}

void setHardwareParameter(HardwareConfig& c, const std::string& path, double value,
                          const std::string& source) {
    auto fail = [&](const std::string& why) { throw InputError(source, path, why); };
    if (!std::isfinite(value) || value <= 0) fail("must be a positive number");
    if (path == "clock_ghz") {
        c.clockGHz = value;
        return;
    }
    if (path == "scratch_budget_bytes") {
        c.scratchBudgetBytes = std::uint64_t(value);
        return;
    }
    const auto dot = path.find('.');
    if (dot == std::string::npos) fail("unknown hardware parameter");
    const std::string stageText = path.substr(0, dot), rest = path.substr(dot + 1);
    int stage = -1;
    for (int s = 0; s < kStageCount; ++s)
        if (stageText == kStageNames[s]) stage = s;
    if (stage < 0) fail("unknown stage '" + stageText + "'");
    StageConfig& s = c.stages[std::size_t(stage)];
    if (rest == "units")
        s.units = int(value);
    else if (rest == "latency")
        s.latency = value;
    else if (rest == "fifo_depth")
        s.fifoDepth = int(value);
    else if (rest.starts_with("throughput.")) {
        const int op = findOp(rest.substr(11), Stage(stage));
        if (op < 0) fail("stage " + stageText + " has no operation '" + rest.substr(11) + "'");
        s.throughput[std::size_t(op)] = value;
    } else {
        fail("unknown hardware parameter");
    }
}

}  // namespace patchsim
