#include "pipeline/timing/hardware_config.h"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/text_file.h"
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

// The memory section: pipeline/hw/memory.json is the default hardware with memory modelled;
// without the section the model is compute-only.
TEST(HardwareConfig, TheMemorySectionIsReadAndOptional) {
    EXPECT_FALSE(defaultHardwareConfig().memory);
    const HardwareConfig m = readHardwareConfig(test::sourcePath("pipeline/hw/memory.json"));
    ASSERT_TRUE(m.memory);
    EXPECT_EQ(m.memory->cache(CacheClient::Depth).geometry.sizeBytes, 16384u);
    EXPECT_EQ(m.memory->cache(CacheClient::LastLevel).geometry.ways, 16u);
    EXPECT_EQ(m.memory->lineBytes(), 64u);
    EXPECT_EQ(m.memory->dramBytesPerClock, 32);
    const HardwareConfig d = defaultHardwareConfig();
    for (int s = 0; s < kStageCount; ++s)
        EXPECT_EQ(m.stages[std::size_t(s)].throughput, d.stages[std::size_t(s)].throughput);
}

// The vertex input cache may be left out (ATTILA's 32 lines at the memory's line size, 4-way),
// and the layer and image caches (the visibility cache's geometry).
TEST(HardwareConfig, AMemorySectionWithoutTheInputLayerAndImageCachesGetsDefaults) {
    nlohmann::json file =
        nlohmann::json::parse(readTextFile(test::sourcePath("pipeline/hw/memory.json")));
    file["memory"]["caches"].erase("vertex_input");
    file["memory"]["caches"].erase("layers");
    file["memory"]["caches"].erase("image");
    for (const char* cache : {"depth", "visibility", "llc"})
        file["memory"]["caches"][cache]["line_bytes"] = 128;
    file["memory"]["caches"]["visibility"]["size_bytes"] = 32768;
    const HardwareConfig c = parseHardwareConfig(file.dump(), "hw.json");
    const CacheConfig& layers = c.memory->cache(CacheClient::Layers);
    EXPECT_EQ(layers.geometry.sizeBytes, 32768u);
    EXPECT_EQ(layers.geometry.lineBytes, 128u);
    EXPECT_EQ(layers.linesPerClock, c.memory->cache(CacheClient::Visibility).linesPerClock);
    const CacheConfig& image = c.memory->cache(CacheClient::Image);  // like the layer cache
    EXPECT_EQ(image.geometry.sizeBytes, 32768u);
    EXPECT_EQ(image.geometry.lineBytes, 128u);
    EXPECT_FALSE(c.memory->cacheGiven[std::size_t(CacheClient::Image)]);
    const CacheConfig& input = c.memory->cache(CacheClient::VertexInput);
    EXPECT_EQ(input.geometry.sizeBytes, 32u * 128);
    EXPECT_EQ(input.geometry.lineBytes, 128u);
    EXPECT_EQ(input.geometry.ways, 4u);
    EXPECT_EQ(input.linesPerClock, 1);
    const HardwareConfig given = readHardwareConfig(test::sourcePath("pipeline/hw/memory.json"));
    EXPECT_EQ(given.memory->cache(CacheClient::VertexInput).geometry.sizeBytes, 2048u);
    EXPECT_EQ(given.memory->cache(CacheClient::Image).linesPerClock, 16);
}

std::string memoryErrorOf(const std::string& edit) {
    nlohmann::json file =
        nlohmann::json::parse(readTextFile(test::sourcePath("pipeline/hw/memory.json")));
    const nlohmann::json patch = nlohmann::json::parse(edit);
    file["memory"].merge_patch(patch);
    return errorOf(file.dump());
}

TEST(HardwareConfig, BadMemoryFieldsAreRefusedByName) {
    const std::pair<const char*, const char*> cases[] = {
        {R"({"caches": {"depth": {"size_bytes": 0}}})", "memory.caches.depth.size_bytes: value 0"},
        {R"({"caches": {"llc": {"ways": 0}}})", "memory.caches.llc.ways"},
        {R"({"caches": {"depth": {"line_bytes": 48}}})",
         "memory.caches.depth.line_bytes: must be a power of two"},
        {R"({"caches": {"visibility": {"line_bytes": 128}}})",
         "memory.caches.visibility.line_bytes: every cache"},
        {R"({"caches": {"depth": {"size_bytes": 1000}}})",
         "memory.caches.depth.size_bytes: must be a whole number of sets"},
        {R"({"caches": {"depth": {"replacement": "random"}}})", "memory.caches.depth.replacement"},
        {R"({"caches": {"llc": null}})", "memory.caches.llc: missing cache"},
        {R"({"caches": {"vertex_input": {"size_bytes": 96}}})",
         "memory.caches.vertex_input.size_bytes: must be a whole number of sets"},
        {R"({"dram": {"bytes_per_clock": -1}})", "memory.dram.bytes_per_clock"},
        {R"({"dram": {"latency": null}})", "memory.dram.latency: missing"},
        {R"({"surface_tile": 0})", "memory.surface_tile"},
        {R"({"banks": 4})", "memory.banks: unknown key"},
        {R"({"depth_compression": "zip"})", "memory.depth_compression: expected \"none\""},
        {R"({"order": "tiles"})", "memory.order: expected \"regions\" or \"patches\""},
        {R"({"caches": {"llc": {"size_bytes": 4294967296}}})",
         "memory.caches.llc.size_bytes: at most 16777216 lines"},
        {R"({"dram": {"row_bytes": 4096}})", "memory.dram.row_bytes: given without \"banks\""},
        {R"({"dram": {"banks": 0, "row_bytes": 4096, "t_rcd": 1, "t_rp": 1, "t_rrd": 1}})",
         "memory.dram.banks: value 0"},
        {R"({"dram": {"banks": 8, "row_bytes": 4096, "t_rp": 1, "t_rrd": 1}})",
         "memory.dram.t_rcd: missing"},
        {R"({"dram": {"banks": 8, "row_bytes": 1000, "t_rcd": 1, "t_rp": 1, "t_rrd": 1}})",
         "memory.dram.row_bytes: must be a power of two of at least the line size (64 bytes)"},
        {R"({"dram": {"banks": 8, "row_bytes": 32, "t_rcd": 1, "t_rp": 1, "t_rrd": 1}})",
         "memory.dram.row_bytes: must be a power of two"},
        {R"({"dram": {"banks": 8, "row_bytes": 4096, "t_rcd": -1, "t_rp": 1, "t_rrd": 1}})",
         "memory.dram.t_rcd: value -1"},
        {R"({"dram": {"banks": 2.5, "row_bytes": 4096, "t_rcd": 1, "t_rp": 1, "t_rrd": 1}})",
         "memory.dram.banks"},
        {R"({"dram": {"channels": 2}})", "memory.dram.channels: given without \"banks\""},
        {R"({"dram": {"max_reads_in_flight": 0}})", "memory.dram.max_reads_in_flight: value 0"},
        {R"({"dram": {"max_reads_in_flight": 1.5}})", "memory.dram.max_reads_in_flight"},
        {R"({"dram": {"channels": 8, "banks": 64, "row_bytes": 4096, "t_rcd": 1, "t_rp": 1,
                      "t_rrd": 1}})",
         "memory.dram.banks: channels x banks must be at most 256, found 512"},
        {R"({"dram": {"channels": 2, "channel_bytes": 96, "banks": 8, "row_bytes": 4096,
                      "t_rcd": 1, "t_rp": 1, "t_rrd": 1}})",
         "memory.dram.channel_bytes: must be a power of two"},
        {R"({"dram": {"banks": 8, "row_bytes": 4096, "t_rcd": 1, "t_rp": 1, "t_rrd": "9"}})",
         "memory.dram.t_rrd: expected a number"},
        {R"({"dram": {"banks": 8, "row_bytes": 4096, "t_rcd": 1, "t_rp": 1, "t_rrd": 1,
                      "mapping": "hash"}})",
         "memory.dram.mapping: expected \"linear\" or \"xor\""},
        {R"({"dram": {"channels": 3, "banks": 8, "row_bytes": 4096, "t_rcd": 1, "t_rp": 1,
                      "t_rrd": 1, "mapping": "xor"}})",
         "memory.dram.mapping: \"xor\" needs channels and banks that are powers of two, found 3 x "
         "8"}};
    for (const auto& [edit, expected] : cases)
        EXPECT_NE(memoryErrorOf(edit).find(expected), std::string::npos)
            << edit << " -> " << memoryErrorOf(edit);
}

// A grid point derives the caches its file left out from the point's own values, as reading a
// file with those values would.
TEST(HardwareConfig, AGridPointDerivesTheCachesItsFileLeftOut) {
    nlohmann::json file =
        nlohmann::json::parse(readTextFile(test::sourcePath("pipeline/hw/memory.json")));
    file["memory"]["caches"].erase("vertex_input");
    file["memory"]["caches"].erase("layers");
    const HardwareConfig base = parseHardwareConfig(file.dump(), "hw.json");
    HardwareConfig c = base;
    setHardwareParameters(
        c, {{"memory.caches.visibility.size_bytes", 4096, "v"}, {"memory.line_bytes", 1024, "l"}},
        "grid.json");
    EXPECT_EQ(c.memory->cache(CacheClient::Layers).geometry.sizeBytes, 4096u);
    EXPECT_EQ(c.memory->cache(CacheClient::Layers).geometry.lineBytes, 1024u);
    EXPECT_EQ(c.memory->cache(CacheClient::VertexInput).geometry.sizeBytes, 32u * 1024);
    EXPECT_FALSE(c.memory->cacheGiven[std::size_t(CacheClient::Layers)]);
    // A field of a left-out cache: the rest of it as derived from the point.
    c = base;
    setHardwareParameters(c,
                          {{"memory.caches.layers.size_bytes", 65536, "s"},
                           {"memory.caches.visibility.ways", 8, "w"}},
                          "grid.json");
    EXPECT_EQ(c.memory->cache(CacheClient::Layers).geometry.sizeBytes, 65536u);
    EXPECT_EQ(c.memory->cache(CacheClient::Layers).geometry.ways, 8u);
    EXPECT_EQ(memoryConfigJson(*c.memory)["caches"]["vertex_input"]["size_bytes"], 2048);
}

// pipeline/hw/memory_gddr3.json: memory.json with DRAM's banks and rows (ATTILA's GDDR3
// timings at the file's clock); its fields round-trip through the section's JSON and are grid
// axes, and a grid point is checked as a file is.
TEST(HardwareConfig, DramBanksAreReadAndAreGridAxes) {
    HardwareConfig c = readHardwareConfig(test::sourcePath("pipeline/hw/memory_gddr3.json"));
    ASSERT_TRUE(c.memory);
    const DramBankConfig& b = c.memory->dramBanks;
    EXPECT_EQ(b.channels, 8);
    EXPECT_EQ(b.channelBytes, 256u);
    EXPECT_EQ(b.banks, 8);
    EXPECT_EQ(b.rowBytes, 4096u);
    EXPECT_EQ(b.activateCycles, 33);
    EXPECT_EQ(b.prechargeCycles, 35);
    EXPECT_EQ(b.activateToActivateCycles, 23);
    const nlohmann::json dram = memoryConfigJson(*c.memory)["dram"];
    EXPECT_EQ(dram["banks"], 8);
    EXPECT_EQ(dram["channels"], 8);
    EXPECT_EQ(dram["t_rrd"], 23);
    EXPECT_FALSE(
        memoryConfigJson(
            *readHardwareConfig(test::sourcePath("pipeline/hw/memory.json")).memory)["dram"]
            .contains("banks"));
    EXPECT_EQ(c.memory->dramReadsInFlight, 0u);  // no limit unless given
    setHardwareParameters(c, {{"memory.dram.banks", 8, "b"}, {"memory.dram.t_rp", 0, "p"}},
                          "grid.json");
    EXPECT_EQ(c.memory->dramBanks.banks, 8);
    EXPECT_EQ(c.memory->dramBanks.prechargeCycles, 0);
    EXPECT_THROW(setHardwareParameters(c, {{"memory.dram.row_bytes", 48, "r"}}, "grid.json"),
                 InputError);
}

// memory.dram.max_reads_in_flight: read and written back into the section; a grid axis whether
// or not the file gives it, and so are the banks, whose check then asks for their timings.
TEST(HardwareConfig, ReadsInFlightAreReadAndAreAGridAxis) {
    HardwareConfig plain = readHardwareConfig(test::sourcePath("pipeline/hw/memory.json"));
    setHardwareParameters(plain, {{"memory.dram.max_reads_in_flight", 32, "r"}}, "grid.json");
    EXPECT_EQ(plain.memory->dramReadsInFlight, 32u);
    try {
        setHardwareParameters(plain, {{"memory.dram.banks", 8, "hardware.b"}}, "grid.json");
        ADD_FAILURE() << "banks without their timings were accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("memory.dram.row_bytes: missing"), std::string::npos)
            << e.what();
    }
    nlohmann::json file =
        nlohmann::json::parse(readTextFile(test::sourcePath("pipeline/hw/memory.json")));
    file["memory"]["dram"]["max_reads_in_flight"] = 64;
    HardwareConfig c = parseHardwareConfig(file.dump(), "hw.json");
    EXPECT_EQ(c.memory->dramReadsInFlight, 64u);
    EXPECT_EQ(memoryConfigJson(*c.memory)["dram"]["max_reads_in_flight"], 64);
    setHardwareParameters(c, {{"memory.dram.max_reads_in_flight", 128, "r"}}, "grid.json");
    EXPECT_EQ(c.memory->dramReadsInFlight, 128u);
}

TEST(HardwareConfig, MemoryParametersBySetPath) {
    HardwareConfig c = readHardwareConfig(test::sourcePath("pipeline/hw/memory.json"));
    setHardwareParameter(c, "memory.dram.bytes_per_clock", 8, "grid.json",
                         "memory.dram.bytes_per_clock");
    setHardwareParameter(c, "memory.caches.depth.size_bytes", 65536, "grid.json", "d");
    setHardwareParameter(c, "memory.caches.llc.replacement", "fifo", "grid.json", "r");
    setHardwareParameter(c, "memory.order", "patches", "grid.json", "o");
    EXPECT_EQ(c.memory->order, MemoryOrder::Patches);
    EXPECT_EQ(c.memory->dramBytesPerClock, 8);
    EXPECT_EQ(c.memory->cache(CacheClient::Depth).geometry.sizeBytes, 65536u);
    EXPECT_EQ(c.memory->cache(CacheClient::LastLevel).geometry.replacement, Replacement::Fifo);
    const auto refusal = [&](HardwareConfig& config, const char* path,
                             const nlohmann::json& value) {
        try {
            setHardwareParameter(config, path, value, "grid.json", "hardware.x");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(
        refusal(c, "memory.caches.depth.size_bytes", 0).find("grid.json: hardware.x: value 0"),
        std::string::npos);
    EXPECT_NE(refusal(c, "memory.caches.tiny.size_bytes", 1).find("unknown hardware parameter"),
              std::string::npos);
    EXPECT_NE(refusal(c, "memory.dram.speed", 1).find("unknown hardware parameter"),
              std::string::npos);
    HardwareConfig none = defaultHardwareConfig();
    EXPECT_NE(refusal(none, "memory.dram.latency", 1).find("no \"memory\" section"),
              std::string::npos);
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
