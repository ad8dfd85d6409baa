#include "pipeline/timing/energy_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/text_file.h"
#include "pipeline/timing/hardware_config.h"
#include "pipeline/timing/memory_model.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

constexpr double kKiB = 1024;

TEST(EnergyModel, TheTableHoldsHorowitzsPointsAndScalesBetweenThem) {
    const EnergyTable t;
    EXPECT_DOUBLE_EQ(t.sramRead64(8 * kKiB), 10);
    EXPECT_DOUBLE_EQ(t.sramRead64(32 * kKiB), 20);
    EXPECT_DOUBLE_EQ(t.sramRead64(1024 * kKiB), 100);
    EXPECT_NEAR(t.sramRead64(16 * kKiB), std::sqrt(10.0 * 20.0), 1e-9);  // log-log midpoint
    EXPECT_NEAR(t.sramRead64(4 * kKiB), 10 / std::sqrt(2.0), 1e-9);      // the slope continues
    EXPECT_DOUBLE_EQ(t.intAdd(8), 0.03);
    EXPECT_DOUBLE_EQ(t.intAdd(32), 0.1);
    EXPECT_DOUBLE_EQ(t.intMultiply(32), 3.1);
    EXPECT_NEAR(t.intMultiply(8), 0.2, 1e-12);  // a power law through both points
    EXPECT_NEAR(t.intMultiply(16), std::sqrt(0.2 * 3.1), 1e-12);
    EXPECT_DOUBLE_EQ(t.floatAdd(NumberFormat::fp16()), 0.4);
    EXPECT_DOUBLE_EQ(t.floatMultiply(NumberFormat::fp32()), 3.7);
    // D3D11's 16.8 snap multiplies 24-bit integers.
    EXPECT_DOUBLE_EQ(t.floatMultiply(kD3D11Snap), t.intMultiply(24));
    EXPECT_NEAR(t.intMultiply(24), 3.1 * std::pow(0.75, std::log(15.5) / std::log(4.0)), 1e-12);
}

TEST(EnergyModel, TheProcessScaleScalesEveryEntry) {
    EnergyTable scaled;
    scaled.processScale = 0.5;
    const EnergyTable base;
    EXPECT_DOUBLE_EQ(scaled.sramRead64(16 * kKiB), base.sramRead64(16 * kKiB) / 2);
    EXPECT_DOUBLE_EQ(scaled.intAdd(24), base.intAdd(24) / 2);
    EXPECT_DOUBLE_EQ(scaled.intMultiply(24), base.intMultiply(24) / 2);
    EXPECT_DOUBLE_EQ(scaled.floatMultiply(NumberFormat::fp32()), 3.7 / 2);
    for (int k = 0; k < kOpCount; ++k)
        EXPECT_NEAR(opPicojoules(Op(k), scaled, 16384), opPicojoules(Op(k), base, 16384) / 2, 1e-9)
            << opName(Op(k));
}

// Ten plane tests and two shader invocations, priced by hand from their rows in
// op_arithmetic.cpp and Horowitz's table.
TEST(EnergyModel, AFramesOperationsArePricedByTheirArithmetic) {
    HardwareConfig hw = defaultHardwareConfig();
    hw.scratchBudgetBytes = 16384;
    PatchOps ops;
    ops[Op::PlaneTests] = 6;
    PatchOps more;
    more[Op::PlaneTests] = 4;
    more[Op::Invocations] = 2;
    more[Op::Triangles] = 5;
    const EnergyReport r = estimateEnergy({ops, more}, hw, nullptr);
    // A plane test: 3 adds and 3 compares at 0.9, 3 multiplies at 3.7, 1.5 bytes of a 16 KiB
    // scratch at sqrt(200) pJ per 8 bytes.
    const double planeTest = 6 * 0.9 + 3 * 3.7 + 1.5 / 8 * std::sqrt(200.0);
    EXPECT_NEAR(r.stagePicojoules[std::size_t(Stage::RS)], 10 * planeTest, 1e-9);
    // An invocation: 76 adds and 5 compares, 96 multiplies and 4 divides (4 multiplies each),
    // 5 integer adds, and the shader's 8 pJ on each of its 186 operations.
    const double invocation = 81 * 0.9 + (96 + 16) * 3.7 + 5 * 0.1 + 186 * 8;
    EXPECT_NEAR(r.stagePicojoules[std::size_t(Stage::PS)], 2 * invocation, 1e-9);
    EXPECT_NEAR(r.stagePicojoules[std::size_t(Stage::TS)], 5 * 7 * 0.1, 1e-9);  // index adds
    EXPECT_FALSE(r.memoryModelled);
    EXPECT_EQ(r.memoryTotalPicojoules(), 0);
    EXPECT_NEAR(r.totalPicojoules(), 10 * planeTest + 2 * invocation + 3.5, 1e-9);
    EXPECT_EQ(r.triangles, 5);
    EXPECT_EQ(estimateEnergy({}, hw, nullptr).totalPicojoules(), 0);  // an empty frame
}

// rasterizer.plane_format: plane tests and time intervals compute in the format, the value and
// its error bound (twice the arithmetic); their operands still come at the node format's bits.
TEST(EnergyModel, APlaneFormatPricesThePlaneArithmeticInItTwice) {
    HardwareConfig hw = defaultHardwareConfig();
    hw.scratchBudgetBytes = 16384;
    PatchOps ops;
    ops[Op::PlaneTests] = 10;
    ops[Op::TimeIntervals] = 3;
    SiteFormats formats;
    formats.planes = NumberFormat::fp16();
    const EnergyReport r = estimateEnergy({ops}, hw, nullptr, formats);
    const double scratch = 1.5 / 8 * std::sqrt(200.0);
    // fp16: adds and compares at 0.4 pJ, multiplies at 1.1; a divide as 4 multiplies.
    const double planeTest = 2 * (6 * 0.4 + 3 * 1.1) + scratch;
    const double interval = 2 * (3 * 0.4 + 4 * 1.1);
    EXPECT_NEAR(r.stagePicojoules[std::size_t(Stage::RS)], 10 * planeTest + 3 * interval, 1e-9);
    const double fp32 = estimateEnergy({ops}, hw, nullptr).stagePicojoules[std::size_t(Stage::RS)];
    EXPECT_NEAR(fp32, 10 * (6 * 0.9 + 3 * 3.7 + scratch) + 3 * (3 * 0.9 + 4 * 3.7), 1e-9);
    formats.planes = NumberFormat::fixed(16, 8);  // integer arithmetic of 24 bits
    const EnergyReport fixed = estimateEnergy({ops}, hw, nullptr, formats);
    EXPECT_NEAR(fixed.stagePicojoules[std::size_t(Stage::RS)],
                10 * (2 * (6 * hw.energy.intAdd(24) + 3 * hw.energy.intMultiply(24)) + scratch) +
                    3 * 2 * (3 * hw.energy.intAdd(24) + 4 * hw.energy.intMultiply(24)),
                1e-9);
    EXPECT_EQ(energyReportJson(r)["plane_format"], "fp16");
    // rasterizer.ray_box_format: the ray-box tests alike, and nothing else moves.
    PatchOps boxes;
    boxes[Op::RayBoxTests] = 7;
    SiteFormats rayBoxes;
    rayBoxes.rayBoxes = NumberFormat::bf16();
    const EnergyReport b = estimateEnergy({boxes}, hw, nullptr, rayBoxes);
    const OpArithmetic& box = opArithmetic(Op::RayBoxTests);
    const double boxTest = 2 * ((box.adds + box.compares) * 0.4 + box.multiplies * 1.1) +
                           box.operandBytes / 8 * std::sqrt(200.0);
    EXPECT_NEAR(b.stagePicojoules[std::size_t(Stage::RS)], 7 * boxTest, 1e-9);
    EXPECT_EQ(energyReportJson(b)["ray_box_format"], "bf16");
}

TEST(EnergyModel, TheMemorySystemIsPricedByLineAndByDramByte) {
    const HardwareConfig hw = defaultHardwareConfig();
    MemoryReport memory;
    for (CacheConfig& c : memory.config.caches) c.geometry = {32 * 1024, 64, 4};
    memory.config.cache(CacheClient::Depth).geometry = {8 * 1024, 64, 4};
    memory.config.cache(CacheClient::LastLevel).geometry = {1024 * 1024, 64, 16};
    memory.caches[std::size_t(CacheClient::Depth)].reads = 60;
    memory.caches[std::size_t(CacheClient::Depth)].writes = 40;
    memory.caches[std::size_t(CacheClient::Visibility)].writes = 3;
    memory.caches[std::size_t(CacheClient::LastLevel)].reads = 10;
    memory.dramReadBytes = 512;
    memory.dramWriteBytes = 128;
    const EnergyReport r = estimateEnergy({}, hw, &memory);
    ASSERT_TRUE(r.memoryModelled);
    // A 64-byte line is eight 64-bit accesses.
    EXPECT_DOUBLE_EQ(r.memoryPicojoules[std::size_t(CacheClient::Depth)], 100 * 8 * 10.0);
    EXPECT_DOUBLE_EQ(r.memoryPicojoules[std::size_t(CacheClient::Visibility)], 3 * 8 * 20.0);
    EXPECT_DOUBLE_EQ(r.memoryPicojoules[std::size_t(CacheClient::LastLevel)], 10 * 8 * 100.0);
    EXPECT_DOUBLE_EQ(r.memoryPicojoules[kCacheClients], 640 / 8 * 1950.0);
    EXPECT_DOUBLE_EQ(r.totalPicojoules(), 8000 + 480 + 8000 + 156000);
}

std::string withEnergy(const nlohmann::json& energy) {
    nlohmann::json hw =
        nlohmann::json::parse(readTextFile(test::sourcePath("pipeline/hw/default.json")));
    hw["energy"] = energy;
    return hw.dump();
}

std::string errorOf(const std::string& text) {
    try {
        parseHardwareConfig(text, "hw.json");
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no error for " << text;
    return {};
}

TEST(EnergyModel, TheHardwareFileSetsEntriesAndRefusesBadOnesByName) {
    const HardwareConfig hw =
        parseHardwareConfig(withEnergy({{"fp32_mul_pj", 1.5}, {"process_scale", 0.25}}), "hw.json");
    EXPECT_EQ(hw.energy.fp32Multiply, 1.5);
    EXPECT_EQ(hw.energy.processScale, 0.25);
    EXPECT_EQ(hw.energy.fp32Add, 0.9);  // the rest keep Horowitz's
    EXPECT_NE(errorOf(withEnergy({{"fp32_mul_pj", -1}})).find("energy.fp32_mul_pj"),
              std::string::npos);
    EXPECT_NE(errorOf(withEnergy({{"fp32_mul_pj", 0}})).find("energy.fp32_mul_pj"),
              std::string::npos);
    EXPECT_NE(errorOf(withEnergy({{"fp64_mul_pj", 1}})).find("fp64_mul_pj"), std::string::npos);
    EXPECT_NE(errorOf(withEnergy({{"dram_access_pj", "a lot"}})).find("energy.dram_access_pj"),
              std::string::npos);
    EXPECT_NE(errorOf(withEnergy(3)).find("energy"), std::string::npos);
    std::string overflow = withEnergy({{"process_scale", 1}});
    const std::string entry = "\"process_scale\":1";
    overflow.replace(overflow.find(entry), entry.size(), entry + "e400");
    EXPECT_NE(errorOf(overflow).find("hw.json"), std::string::npos);
}

TEST(EnergyModel, AGridPointSetsAnEntryByPath) {
    HardwareConfig hw = defaultHardwareConfig();
    setHardwareParameter(hw, "energy.process_scale", 0.5, "grid.json", "hardware[0]");
    EXPECT_EQ(hw.energy.processScale, 0.5);
    setHardwareParameter(hw, "energy.sram_8kib_read_pj", 12, "grid.json", "hardware[0]");
    EXPECT_EQ(hw.energy.sram8KiB, 12);
    try {
        setHardwareParameter(hw, "energy.fp8_add_pj", 1, "grid.json", "hardware[1]");
        ADD_FAILURE() << "an unknown entry was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "hardware[1]");
        EXPECT_NE(std::string(e.what()).find("energy.fp8_add_pj"), std::string::npos);
    }
    EXPECT_THROW(setHardwareParameter(hw, "energy.process_scale", -2, "grid.json", "hardware[2]"),
                 InputError);
}

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

// docs/HARDWARE.md's table of each operation's arithmetic, held to op_arithmetic.cpp's.
TEST(EnergyModel, EveryOperationsArithmeticIsDocumented) {
    const std::string page = readTextFile(test::sourcePath("docs/HARDWARE.md"));
    const EnergyTable table;
    for (int k = 0; k < kOpCount; ++k) {
        const Op op = Op(k);
        const OpArithmetic& a = opArithmetic(op);
        EXPECT_GT(a.operations(), 0) << opName(op);
        char pj[32];
        std::snprintf(pj, sizeof pj, "%.1f", opPicojoules(op, table, 16384));
        const std::string row = std::string("| ") + stageName(stageOf(op)) + " | `" + opName(op) +
                                "` | " + number(a.adds) + " | " + number(a.multiplies) + " | " +
                                number(a.compares) + " | " + number(a.divides) + " | " +
                                number(a.intAdds) + " | " + number(a.intMultiplies) + " | " +
                                number(a.operandBytes) + " | " + pj + " | " + a.how + " |";
        EXPECT_NE(page.find(row), std::string::npos) << "docs/HARDWARE.md lacks the row\n" << row;
    }
}

}  // namespace
}  // namespace patchsim
