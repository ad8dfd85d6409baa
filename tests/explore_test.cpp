#include "pipeline/driver/explore.h"

#include <gtest/gtest.h>

#include <sstream>

#include "core/error.h"
#include "core/scene_reader.h"
#include "pipeline/timing/hardware_config.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

// A row's number in CSV column `column` (0 is the scene).
double csvNumber(const ExploreRow& row, std::ptrdiff_t column) {
    std::vector<std::string> fields;
    std::istringstream line(row.csv);
    for (std::string field; std::getline(line, field, ',');) fields.push_back(field);
    return std::stod(fields.at(std::size_t(column)));
}

std::string errorOf(const std::string& json) {
    try {
        parseExploreGrid(json, "grid.json");
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no error for " << json;
    return {};
}

TEST(Explore, GridCrossProductAndRows) {
    const ExploreGrid grid = parseExploreGrid(
        R"({"rasterizer": {"tile_size": [4, 8], "branch_method": ["root", "bitmask"], "z_culling": [true, false]},
            "hardware": {"RS.units": [1, 2, 4]}, "film": {"width": 24, "height": 16, "spp": 2}})",
        "grid.json");
    ASSERT_EQ(grid.rasterAxes.size(), 3u);
    ASSERT_EQ(grid.hardwareAxes.size(), 1u);
    EXPECT_EQ(grid.rasterAxes[1].values, (std::vector<std::string>{"root", "bitmask"}));
    EXPECT_EQ(grid.rasterAxes[2].values, (std::vector<std::string>{"true", "false"}));
    const std::vector<ExploreJob> jobs = exploreJobs(2, grid);
    EXPECT_EQ(jobs.size(), 2u * 2 * 2 * 2);
    const std::vector<SceneDesc> scenes = {readSceneFile(test::sourcePath("scenes/motion.json"))};
    const std::vector<ExploreRow> rows = runExploreJob(scenes, grid, defaultHardwareConfig(), 1, 1);
    ASSERT_EQ(rows.size(), 3u);  // one per RS.units value
    const std::string header = exploreCsvHeader(grid);
    EXPECT_EQ(std::count(header.begin(), header.end(), ','),
              std::count(rows[0].csv.begin(), rows[0].csv.end(), ','));
    EXPECT_EQ(rows[0].csv.rfind(scenes[0].path + ",4,root,false,1,", 0), 0u) << rows[0].csv;
    // Every point names its bottleneck stage and how busy that stage was.
    const std::string timing = ",total_cycles,microseconds,bottleneck,bottleneck_utilisation,";
    ASSERT_NE(header.find(timing), std::string::npos) << header;
    const auto column = std::count(header.begin(), header.begin() + header.find(timing), ',') + 3;
    std::vector<std::string> fields;
    std::istringstream line(rows[0].csv);
    for (std::string field; std::getline(line, field, ',');) fields.push_back(field);
    EXPECT_EQ(fields[std::size_t(column)], "RS") << rows[0].csv;
    const double busy = std::stod(fields[std::size_t(column) + 1]);
    EXPECT_GT(busy, 0.5);
    EXPECT_LE(busy, 1.0);
    EXPECT_EQ(rows[2].choice, (std::vector<std::size_t>{0, 0, 1, 2}));
    // More rasterizer units: fewer cycles for the same counted work (the rasterizer is this
    // frame's bottleneck, so doubling it must show).
    EXPECT_GT(rows[0].totalCycles, rows[1].totalCycles);
    EXPECT_GT(rows[1].totalCycles, rows[2].totalCycles);
    // Rows travel between MPI ranks as they are.
    const std::vector<ExploreRow> back = unpackExploreRows(packExploreRows(rows));
    ASSERT_EQ(back.size(), rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        EXPECT_EQ(back[i].csv, rows[i].csv);
        EXPECT_EQ(back[i].choice, rows[i].choice);
        EXPECT_EQ(back[i].job, rows[i].job);
    }
}

// A grid over the memory system's fields: each point replays the frame's traffic through its own
// caches and DRAM (the render is done once), and the CSV carries the DRAM bytes.
TEST(Explore, MemoryFieldsAreHardwareAxes) {
    const ExploreGrid grid = parseExploreGrid(
        R"({"hardware": {"memory.caches.llc.size_bytes": [16384, 1048576],
                         "memory.dram.bytes_per_clock": [0.5, 64]},
            "film": {"width": 48, "height": 32, "spp": 4}})",
        "grid.json");
    const std::vector<SceneDesc> scenes = {readSceneFile(test::sourcePath("scenes/motion.json"))};
    const HardwareConfig memory = readHardwareConfig(test::sourcePath("pipeline/hw/memory.json"));
    const std::vector<ExploreRow> rows = runExploreJob(scenes, grid, memory, 0, 1);
    ASSERT_EQ(rows.size(), 4u);
    const std::string header = exploreCsvHeader(grid);
    const auto column =
        std::count(header.begin(), header.begin() + header.find(",dram_bytes"), ',') + 1;
    const auto dramBytes = [&](const ExploreRow& row) { return csvNumber(row, column); };
    // rows: (small LLC, slow), (small, fast), (large, slow), (large, fast)
    EXPECT_GT(dramBytes(rows[0]), dramBytes(rows[2]));  // a larger LLC keeps lines on chip
    EXPECT_EQ(dramBytes(rows[0]), dramBytes(rows[1]));  // bandwidth moves no byte
    EXPECT_GT(rows[0].totalCycles, rows[1].totalCycles);
    const auto energyColumn =
        std::count(header.begin(), header.begin() + header.find(",energy_nj"), ',') + 1;
    const auto energy = [&](const ExploreRow& row) { return csvNumber(row, energyColumn); };
    EXPECT_EQ(energy(rows[0]), energy(rows[1]));  // bandwidth moves no joule either
    EXPECT_NE(energy(rows[0]), energy(rows[2]));
    // Before any render: the grid's memory fields need hardware that models memory.
    EXPECT_NO_THROW(checkGridHardware(grid, memory));
    try {
        checkGridHardware(grid, defaultHardwareConfig());
        ADD_FAILURE() << "memory axes accepted without a memory section";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("grid.json: hardware.memory."), std::string::npos)
            << e.what();
    }
}

// An energy entry is an axis: the process scale scales the frame's energy, nothing else.
TEST(Explore, EnergyEntriesAreHardwareAxes) {
    const ExploreGrid grid = parseExploreGrid(
        R"({"hardware": {"energy.process_scale": [1, 0.5]},
            "film": {"width": 32, "height": 24, "spp": 1}})",
        "grid.json");
    const std::vector<SceneDesc> scenes = {readSceneFile(test::sourcePath("scenes/motion.json"))};
    const std::vector<ExploreRow> rows = runExploreJob(scenes, grid, defaultHardwareConfig(), 0, 1);
    ASSERT_EQ(rows.size(), 2u);
    const std::string header = exploreCsvHeader(grid);
    const auto column =
        std::count(header.begin(), header.begin() + header.find(",energy_nj"), ',') + 1;
    const double full = csvNumber(rows[0], column);
    EXPECT_GT(full, 0);
    EXPECT_NEAR(csvNumber(rows[1], column), full / 2, full * 1e-5);
    EXPECT_EQ(rows[0].totalCycles, rows[1].totalCycles);
    try {
        checkGridHardware(
            parseExploreGrid(R"({"hardware": {"energy.fp64_mul_pj": [1]}})", "g.json"),
            defaultHardwareConfig());
        ADD_FAILURE() << "an unknown energy entry was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("energy.fp64_mul_pj"), std::string::npos) << e.what();
    }
}

// A grid point's memory fields are set together and checked as a whole, against the job's file:
// a cache's size and ways that are only right together pass, the line size of every cache is one
// axis, and a point that is wrong is refused before any render, named.
TEST(Explore, AGridPointsMemoryFieldsAreCheckedTogether) {
    const HardwareConfig memory = readHardwareConfig(test::sourcePath("pipeline/hw/memory.json"));
    const ExploreGrid together = parseExploreGrid(
        R"({"hardware": {"memory.caches.llc.size_bytes": [786432], "memory.caches.llc.ways": [24],
                         "memory.line_bytes": [64, 128]}})",
        "grid.json");
    EXPECT_NO_THROW(checkGridHardware(together, memory));
    const ExploreGrid wrong = parseExploreGrid(
        R"({"hardware": {"memory.caches.llc.size_bytes": [524288, 3072],
                         "memory.caches.llc.ways": [16, 64]}})",
        "grid.json");
    try {
        checkGridHardware(wrong, memory);
        ADD_FAILURE() << "a point with 3072 bytes of 64 ways of 64 bytes accepted";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("grid.json: hardware.memory.caches.llc."), std::string::npos) << what;
        EXPECT_NE(what.find("(at the grid point memory.caches.llc.size_bytes = 3072"),
                  std::string::npos)
            << what;
    }
    for (const char* grid : {R"({"hardware": {"memory.caches.llc": [{"ways": 2}]}})",
                             R"({"hardware": {"memory.dram": [5]}})"}) {
        try {
            checkGridHardware(parseExploreGrid(grid, "grid.json"), memory);
            ADD_FAILURE() << grid << " accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("grid.json: hardware.memory."), std::string::npos)
                << e.what();
        }
    }
}

// The patent's bounds spaces and the patch merge are grid axes like any rasterizer option, and
// every point of them renders.
TEST(Explore, BoundsSpacesAndMergingAreGridAxes) {
    const ExploreGrid grid = parseExploreGrid(
        R"({"rasterizer": {"bounds_space": ["3d", "2dh", "2d"], "merge_triangles_below": [0, 64]},
            "film": {"width": 24, "height": 16, "spp": 2}})",
        "grid.json");
    ASSERT_EQ(grid.rasterAxes.size(), 2u);
    EXPECT_EQ(grid.rasterAxes[0].values, (std::vector<std::string>{"3d", "2dh", "2d"}));
    const std::vector<ExploreJob> jobs = exploreJobs(1, grid);
    ASSERT_EQ(jobs.size(), 6u);
    const std::vector<SceneDesc> scenes = {readSceneFile(test::sourcePath("scenes/motion.json"))};
    const std::vector<ExploreRow> rows =
        runExploreJob(scenes, grid, defaultHardwareConfig(), jobs.size() - 1, 1);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_NE(rows[0].csv.find(",2d,64,"), std::string::npos) << rows[0].csv;
}

TEST(Explore, GridErrorsNameTheField) {
    EXPECT_NE(errorOf(R"({"rasterizer": {"tile_size": []}})")
                  .find("rasterizer.tile_size: expected a non-empty array"),
              std::string::npos);
    EXPECT_NE(
        errorOf(R"({"rasterizer": {"tile_sise": [4]}})").find("rasterizer.tile_sise: unknown key"),
        std::string::npos);
    EXPECT_NE(errorOf(R"({"rasterizer": {"branch_method": ["sideways"]}})")
                  .find("rasterizer.branch_method"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"rasterizer": {"bounds_space": ["3d", "4d"]}})")
                  .find("rasterizer.bounds_space"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"hardware": {"RS.wheels": [1]}})").find("RS.wheels"), std::string::npos);
    EXPECT_NE(errorOf(R"({"hardware": {"RS.units": ["many"]}})")
                  .find("hardware.RS.units[0]: expected an integer"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"film": {"spp": 0}})").find("film.spp"), std::string::npos);
    EXPECT_NE(errorOf(R"({"hardware": {"clock_ghz": [1, 1e999]}})")
                  .find("grid.json: line 1, column 32: JSON number overflow parsing '1e999'"),
              std::string::npos);
}

// Grid values follow the scene and hardware readers' rules: whole numbers where those want whole
// numbers, in their ranges, of their types.
TEST(Explore, GridValuesAreCheckedLikeTheSceneAndHardwareFiles) {
    for (const auto& [grid, field] : std::vector<std::pair<std::string, std::string>>{
             {R"({"rasterizer": {"tile_size": [8, 0]}})", "rasterizer.tile_size[1]"},
             {R"({"rasterizer": {"tile_size": [1e10]}})", "rasterizer.tile_size[0]"},
             {R"({"rasterizer": {"tile_size": [8.5]}})", "rasterizer.tile_size[0]"},
             {R"({"rasterizer": {"tile_size": ["8"]}})", "rasterizer.tile_size[0]"},
             {R"({"rasterizer": {"z_culling": ["no"]}})", "rasterizer.z_culling[0]"},
             {R"({"hardware": {"RS.units": [0.5]}})", "hardware.RS.units[0]"},
             {R"({"hardware": {"RS.units": [1e10]}})", "hardware.RS.units[0]"},
             {R"({"hardware": {"RS.throughput.ray_box_tests": [1e-12]}})",
              "hardware.RS.throughput.ray_box_tests[0]"},
             {R"({"rasterizer": {"tile_size": [4, 4]}, "rasterizer": {}})", "rasterizer"}}) {
        EXPECT_NE(errorOf(grid).find("grid.json: " + field), std::string::npos)
            << grid << " -> " << errorOf(grid);
    }
}

// A value given twice on an axis, or a scene given twice, would make every one of its points
// twice (duplicate CSV rows); both are refused, by field and by argument, as sweep refuses them.
TEST(Explore, RepeatedGridValuesAndScenesAreRefused) {
    for (const auto& [grid, message] : std::vector<std::pair<std::string, std::string>>{
             {R"({"rasterizer": {"tile_size": [8, 16, 8]}})",
              "grid.json: rasterizer.tile_size[2]: the value 8 repeats rasterizer.tile_size[0]"},
             {R"({"rasterizer": {"z_culling": [true, false, true]}})",
              "grid.json: rasterizer.z_culling[2]: the value true repeats"},
             {R"({"hardware": {"clock_ghz": [1, 1.0]}})",
              "grid.json: hardware.clock_ghz[1]: the value 1 repeats hardware.clock_ghz[0]"},
             {R"({"hardware": {"RS.units": [2, 4, 2]}})",
              "grid.json: hardware.RS.units[2]: the value 2 repeats hardware.RS.units[0]"}}) {
        EXPECT_NE(errorOf(grid).find(message), std::string::npos)
            << grid << " -> " << errorOf(grid);
    }
    const ExploreGrid grid =
        parseExploreGrid(R"({"rasterizer": {"tile_size": [8, 16]}})", "g.json");
    const std::string path = test::sourcePath("scenes/motion.json");
    const SceneDesc scene = readSceneFile(path);
    SceneDesc spelledOtherwise = scene;
    spelledOtherwise.path = test::sourcePath("scenes/../scenes/./motion.json");
    for (const auto& [second, message] : std::vector<std::pair<SceneDesc, std::string>>{
             {scene, "command line: scenes: names '" + path + "' twice"},
             {spelledOtherwise, "command line: scenes: '" + path + "' and '" +
                                    spelledOtherwise.path + "' are the same file"}}) {
        int rendered = 0;
        try {
            runExploreJobs(
                {scene, second}, grid, defaultHardwareConfig(), 1, SceneLimits{},
                [](std::size_t) { return false; },
                [&](std::size_t, const std::vector<ExploreRow>&) { ++rendered; });
            ADD_FAILURE() << "no error for " << second.path;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
        }
        EXPECT_EQ(rendered, 0);
    }
}

// A grid point whose tiles' ray scratch, with the film, exceeds the budget is refused, naming the
// grid, before any job renders.
TEST(Explore, GridTileScratchIsHeldToTheMemoryBudgetBeforeAnyRender) {
    const ExploreGrid grid =
        parseExploreGrid(R"({"rasterizer": {"tile_size": [8, 256]}})", "grid.json");
    const std::vector<SceneDesc> scenes = {readSceneFile(test::sourcePath("scenes/motion.json"))};
    SceneLimits limits;
    limits.memoryBudgetBytes = std::uint64_t(256) << 20;
    int rendered = 0;
    try {
        runExploreJobs(
            scenes, grid, defaultHardwareConfig(), 2, limits, [](std::size_t) { return true; },
            [&](std::size_t, const std::vector<ExploreRow>&) { ++rendered; });
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("grid.json: rasterizer.tile_size: tiles of 256x256"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("over the memory budget of 256 MiB"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_EQ(rendered, 0);
}

TEST(Explore, GridFilmIsHeldToTheMemoryBudget) {
    const ExploreGrid grid = parseExploreGrid(
        R"({"film": {"width": 16384, "height": 16384, "spp": 4096}})", "grid.json");
    const std::vector<SceneDesc> scenes = {readSceneFile(test::sourcePath("scenes/motion.json"))};
    try {
        jobScene(scenes, grid, exploreJobs(1, grid)[0], SceneLimits{});
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("grid.json: film: film of 16384x16384"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace patchsim
