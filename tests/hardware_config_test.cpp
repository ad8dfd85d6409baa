#include "pipeline/core/hardware_config.h"

#include <gtest/gtest.h>

#include "pipeline/core/error.h"
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
    EXPECT_THROW(readHardwareConfig("/nonexistent/hw.json"), InputError);
}

TEST(HardwareConfig, ParametersBySetPath) {
    HardwareConfig c = defaultHardwareConfig();
    setHardwareParameter(c, "RS.units", 4, "grid.json");
    setHardwareParameter(c, "RS.throughput.ray_box_tests", 32, "grid.json");
    setHardwareParameter(c, "PS.fifo_depth", 2, "grid.json");
    setHardwareParameter(c, "clock_ghz", 2, "grid.json");
    EXPECT_EQ(c.stage(Stage::RS).units, 4);
    EXPECT_EQ(c.stage(Stage::RS).throughput[std::size_t(Op::RayBoxTests)], 32);
    EXPECT_EQ(c.stage(Stage::PS).fifoDepth, 2);
    EXPECT_EQ(c.clockGHz, 2);
    EXPECT_THROW(setHardwareParameter(c, "RS.throughput.invocations", 1, "grid.json"), InputError);
    EXPECT_THROW(setHardwareParameter(c, "XX.units", 1, "grid.json"), InputError);
    EXPECT_THROW(setHardwareParameter(c, "RS.units", -1, "grid.json"), InputError);
}

}  // namespace
}  // namespace patchsim
