#include "pipeline/driver/explore.h"

#include <gtest/gtest.h>

#include "pipeline/core/error.h"
#include "pipeline/core/scene_reader.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

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
    const std::vector<std::string> rows =
        runExploreJob(scenes, grid, defaultHardwareConfig(), jobs[1], 1);
    ASSERT_EQ(rows.size(), 3u);  // one per RS.units value
    const std::string header = exploreCsvHeader(grid);
    EXPECT_EQ(std::count(header.begin(), header.end(), ','),
              std::count(rows[0].begin(), rows[0].end(), ','));
    EXPECT_EQ(rows[0].rfind(scenes[0].path + ",4,root,false,1,", 0), 0u) << rows[0];
    // More rasterizer units: fewer (or equal) cycles for the same counted work.
    auto cycles = [](const std::string& row) {
        std::size_t pos = 0;
        for (int i = 0; i < 5; ++i) pos = row.find(',', pos) + 1;
        return std::stod(row.substr(pos));
    };
    EXPECT_GE(cycles(rows[0]), cycles(rows[1]));
    EXPECT_GE(cycles(rows[1]), cycles(rows[2]));
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
    EXPECT_NE(errorOf(R"({"hardware": {"RS.wheels": [1]}})").find("RS.wheels"), std::string::npos);
    EXPECT_NE(errorOf(R"({"hardware": {"RS.units": ["many"]}})")
                  .find("hardware.RS.units: 'many' is not a number"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"film": {"spp": 0}})").find("film.spp"), std::string::npos);
}

}  // namespace
}  // namespace patchsim
