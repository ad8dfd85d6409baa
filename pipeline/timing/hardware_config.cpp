#include "pipeline/timing/hardware_config.h"

#include <cmath>

#include "core/json_fields.h"
#include "core/text_file.h"

namespace patchsim {

namespace {

int findOp(const std::string& name, Stage stage) {
    for (int k = 0; k < kOpCount; ++k)
        if (name == opName(Op(k)) && stageOf(Op(k)) == stage) return k;
    return -1;
}

// The accepted range of each parameter, shared by the file reader and setHardwareParameter.
struct Range {
    double lo, hi;
    bool integer;
};
constexpr Range kUnits{1, 1 << 20, true};
constexpr Range kLatency{0, 1e9, false};
constexpr Range kFifoDepth{1, 1 << 20, true};
constexpr Range kThroughput{1e-9, 1e9, false};
constexpr Range kClock{1e-6, 1e6, false};
constexpr Range kScratch{1, double(std::int64_t(1) << 40), true};

// A value in range as a double, or InputError(source, field).
double checked(const Json& j, const Range& range, const std::string& source,
               const std::string& field) {
    auto fail = [&](const std::string& why) { throw InputError(source, field, why); };
    if (range.integer && !j.is_number_integer())
        fail("expected an integer in [" + ObjectReader::formatNumber(range.lo) + ", " +
             ObjectReader::formatNumber(range.hi) + "], found " + j.dump());
    if (!j.is_number()) fail("expected a number, found " + j.dump());
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < range.lo || v > range.hi)
        fail("value " + j.dump() + " is outside [" + ObjectReader::formatNumber(range.lo) + ", " +
             ObjectReader::formatNumber(range.hi) + "]");
    return v;
}

void readStage(ObjectReader r, StageConfig& s, Stage stage) {
    if (const Json* j = r.find("units"))
        s.units = int(checked(*j, kUnits, r.file(), r.fieldName("units")));
    if (const Json* j = r.find("latency"))
        s.latency = checked(*j, kLatency, r.file(), r.fieldName("latency"));
    if (const Json* j = r.find("fifo_depth"))
        s.fifoDepth = int(checked(*j, kFifoDepth, r.file(), r.fieldName("fifo_depth")));
    if (auto t = r.object("throughput")) {
        for (int k = 0; k < kOpCount; ++k) {
            if (stageOf(Op(k)) != stage) continue;
            if (const Json* j = t->find(opName(Op(k))))
                s.throughput[std::size_t(k)] =
                    checked(*j, kThroughput, r.file(), t->fieldName(opName(Op(k))));
        }
        t->finish();
    }
    r.finish();
    for (int k = 0; k < kOpCount; ++k)
        if (stageOf(Op(k)) == stage && !(s.throughput[std::size_t(k)] > 0))
            r.fail(r.fieldName("throughput." + std::string(opName(Op(k)))),
                   "missing or not positive");
}

}  // namespace

HardwareConfig parseHardwareConfig(std::string_view text, const std::string& path) {
    const Json json = parseJson(text, path);
    HardwareConfig config;
    ObjectReader root(json, "", path);
    if (const Json* j = root.find("clock_ghz"))
        config.clockGHz = checked(*j, kClock, path, "clock_ghz");
    if (const Json* j = root.find("scratch_budget_bytes"))
        config.scratchBudgetBytes =
            std::uint64_t(checked(*j, kScratch, path, "scratch_budget_bytes"));
    auto stages = root.object("stages");
    if (!stages) root.fail("stages", "missing the per-stage configuration");
    for (int s = 0; s < kStageCount; ++s) {
        auto stage = stages->object(stageName(Stage(s)));
        if (!stage) stages->fail(stages->fieldName(stageName(Stage(s))), "missing stage");
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

void setHardwareParameter(HardwareConfig& c, const std::string& path, const Json& value,
                          const std::string& source, const std::string& field) {
    auto fail = [&](const std::string& why) { throw InputError(source, field, why); };
    if (path == "clock_ghz") {
        c.clockGHz = checked(value, kClock, source, field);
        return;
    }
    if (path == "scratch_budget_bytes") {
        c.scratchBudgetBytes = std::uint64_t(checked(value, kScratch, source, field));
        return;
    }
    const auto dot = path.find('.');
    if (dot == std::string::npos) fail("unknown hardware parameter '" + path + "'");
    const std::string stageText = path.substr(0, dot), rest = path.substr(dot + 1);
    int stage = -1;
    for (int s = 0; s < kStageCount; ++s)
        if (stageText == stageName(Stage(s))) stage = s;
    if (stage < 0) fail("unknown stage '" + stageText + "'");
    StageConfig& s = c.stages[std::size_t(stage)];
    if (rest == "units")
        s.units = int(checked(value, kUnits, source, field));
    else if (rest == "latency")
        s.latency = checked(value, kLatency, source, field);
    else if (rest == "fifo_depth")
        s.fifoDepth = int(checked(value, kFifoDepth, source, field));
    else if (rest.starts_with("throughput.")) {
        const int op = findOp(rest.substr(11), Stage(stage));
        if (op < 0) fail("stage " + stageText + " has no operation '" + rest.substr(11) + "'");
        s.throughput[std::size_t(op)] = checked(value, kThroughput, source, field);
    } else {
        fail("unknown hardware parameter '" + path + "'");
    }
}

}  // namespace patchsim
