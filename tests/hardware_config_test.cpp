#include "pipeline/timing/hardware_config.h"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

std::string errorOf(const std::string& json) {
    try {
        parseHardwareConfig(json, "hw.json");
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "hw.json");
        return e.what();
    }
    ADD_FAILURE() << "no error for " << json;
    return {};
}

TEST(HardwareConfig, DefaultShipsAndIsBuiltIn) {
    const HardwareConfig builtIn = defaultHardwareConfig();
    const HardwareConfig file = readHardwareConfig(test::sourcePath("pipeline/hw/default.json"));
    EXPECT_EQ(builtIn.stage(Stage::RS).throughput, file.stage(Stage::RS).throughput);
    EXPECT_GT(builtIn.clockGHz, 0);
    for (int k = 0; k < kOpCount; ++k)
        EXPECT_GT(builtIn.stage(stageOf(Op(k))).throughput[std::size_t(k)], 0) << opName(Op(k));
}

// The iso-arithmetic file (scripts/iso-hardware.py) reprices only the rasterizer's and output
// merger's operation kinds; every stage keeps the default's units, latency and FIFO, and the other
// stages their throughputs, so a comparison under both files changes one thing.
TEST(HardwareConfig, IsoArithmeticRepricesOnlyTheRasterizerAndOutputMerger) {
    const HardwareConfig base = defaultHardwareConfig();
    const HardwareConfig iso =
        readHardwareConfig(test::sourcePath("pipeline/hw/iso_arithmetic.json"));
    EXPECT_EQ(iso.clockGHz, base.clockGHz);
    bool repriced = false;
    for (int s = 0; s < kStageCount; ++s) {
        const StageConfig &a = base.stages[std::size_t(s)], &b = iso.stages[std::size_t(s)];
        EXPECT_EQ(a.units, b.units) << stageName(Stage(s));
        EXPECT_EQ(a.latency, b.latency) << stageName(Stage(s));
        EXPECT_EQ(a.fifoDepth, b.fifoDepth) << stageName(Stage(s));
        if (Stage(s) != Stage::RS && Stage(s) != Stage::OM) {
            EXPECT_EQ(a.throughput, b.throughput) << stageName(Stage(s));
        } else {
            repriced = repriced || a.throughput != b.throughput;
        }
    }
    EXPECT_TRUE(repriced);
}

TEST(HardwareConfig, ErrorsNameTheField) {
    const std::string full = R"({"stages": {"IA": {"throughput": {"patches": 1}}}})";
    EXPECT_NE(errorOf(full).find("stages.VS: missing stage"), std::string::npos);
    EXPECT_NE(errorOf("{\"stages\": 3}").find("stages: expected an object"), std::string::npos);
    EXPECT_NE(errorOf("{}").find("stages: missing"), std::string::npos);
    EXPECT_NE(errorOf("{\"clock_ghz\": -1, \"stages\": {}}").find("clock_ghz"), std::string::npos);
    EXPECT_NE(errorOf("{\"stages\": {\"IA\": {\"units\": 0}}}").find("stages.IA.units"),
              std::string::npos);
    EXPECT_NE(errorOf("{\"stages\": {\"IA\": {\"throughput\": {\"rays\": 1}}}}")
                  .find("stages.IA.throughput.rays: unknown key"),
              std::string::npos);
    EXPECT_NE(errorOf("{\"stages\": {\"IA\": {}}}")
                  .find("stages.IA.throughput.patches: missing or not positive"),
              std::string::npos);
    EXPECT_NE(errorOf("{\"stages\": {,}}").find("hw.json: line 1, column 13: JSON syntax error"),
              std::string::npos);
    EXPECT_NE(errorOf("{\n\"clock_ghz\": 2e400, \"stages\": {}}")
                  .find("hw.json: line 2, column 14: JSON number overflow parsing '2e400'"),
              std::string::npos);
    EXPECT_THROW(readHardwareConfig("/nonexistent/hw.json"), InputError);
}

TEST(HardwareConfig, ParametersBySetPath) {
    HardwareConfig c = defaultHardwareConfig();
    auto set = [&](const char* path, const nlohmann::json& value) {
        setHardwareParameter(c, path, value, "grid.json", path);
    };
    set("RS.units", 4);
    set("RS.throughput.ray_box_tests", 32);
    set("PS.fifo_depth", 2);
    set("clock_ghz", 2);
    EXPECT_EQ(c.stage(Stage::RS).units, 4);
    EXPECT_EQ(c.stage(Stage::RS).throughput[std::size_t(Op::RayBoxTests)], 32);
    EXPECT_EQ(c.stage(Stage::PS).fifoDepth, 2);
    EXPECT_EQ(c.clockGHz, 2);
    EXPECT_THROW(set("RS.throughput.invocations", 1), InputError);
    EXPECT_THROW(set("XX.units", 1), InputError);
    EXPECT_THROW(set("RS.units", -1), InputError);
}

// The same ranges as the hardware file: units and FIFO depths are whole and at least 1,
// throughputs at least 1e-9, nothing overflows.
TEST(HardwareConfig, SetPathRefusesWhatTheFileReaderRefuses) {
    HardwareConfig c = defaultHardwareConfig();
    for (const auto& [path, value] :
         std::vector<std::pair<const char*, nlohmann::json>>{{"RS.units", 0.5},
                                                             {"RS.units", 1e10},
                                                             {"RS.units", "8"},
                                                             {"RS.fifo_depth", 2.5},
                                                             {"RS.throughput.ray_box_tests", 1e-12},
                                                             {"clock_ghz", 0},
                                                             {"scratch_budget_bytes", 10.5}}) {
        try {
            setHardwareParameter(c, path, value, "grid.json", "hardware." + std::string(path));
            ADD_FAILURE() << path << " = " << value.dump() << " accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("grid.json: hardware." + std::string(path)),
                      std::string::npos)
                << e.what();
        }
    }
}

}  // namespace
}  // namespace patchsim

namespace patchsim {
namespace {

// docs/HARDWARE.md's table of operations, held to the one list of them (core/stage_ops.h): every
// operation on a row of its own stage.
TEST(HardwareConfig, EveryOperationIsDocumentedWithItsStage) {
    std::ifstream in(test::sourcePath("docs/HARDWARE.md"));
    std::string line;
    std::vector<std::string> rows;
    while (std::getline(in, line))
        if (line.rfind("| ", 0) == 0) rows.push_back(line);
    for (int k = 0; k < kOpCount; ++k) {
        const Op op = Op(k);
        const std::string stage = std::string("| ") + stageName(stageOf(op)) + " | ";
        const std::string key = std::string("`") + opName(op) + "`";
        bool found = false;
        for (const std::string& row : rows) {
            if (row.rfind(stage, 0) != 0) continue;
            const std::size_t end = row.find(" | ", stage.size());
            found = found ||
                    row.substr(stage.size(), end - stage.size()).find(key) != std::string::npos;
        }
        EXPECT_TRUE(found) << opName(op) << " has no row of stage " << stageName(stageOf(op))
                           << " in docs/HARDWARE.md";
    }
}

}  // namespace
}  // namespace patchsim
