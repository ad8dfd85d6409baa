#include "backend/images/heat_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <limits>

#include "backend/images/image.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

TEST(HeatMap, ColourScaleGetsBrighterWithTheValue) {
    float previous = -1;
    for (int i = 0; i <= 100; ++i) {
        const HeatColor c = heatColor(float(i) / 100.0f);
        const float luminance = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
        EXPECT_GT(luminance, previous) << i;
        previous = luminance;
    }
    const HeatColor nan = heatColor(std::numeric_limits<float>::quiet_NaN());
    EXPECT_EQ(nan.r, heatColor(0).r);
}

TEST(HeatMap, WritesTheMapWithALegendBelow) {
    HeatMapGrid grid{"rays cast per tile", 4, 3, 8, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}};
    const std::string path = test::temporaryDirectory() + "/heat.png";
    writeHeatMap(grid, path);
    const Image image = readImage(path);
    EXPECT_EQ(image.width, 200);  // at least wide enough for the legend
    EXPECT_EQ(image.height, 3 * 8 + 44);
    // Low values are dark, high values bright; the cells are 8 x 8 pixels.
    const Vec3 low = image.get(2, 2), high = image.get(3 * 8 + 2, 2 * 8 + 2);
    EXPECT_LT(low.x + low.y + low.z, high.x + high.y + high.z);
    // The legend's text is drawn: some white pixels below the map.
    bool text = false;
    for (int y = 3 * 8; y < image.height && !text; ++y)
        for (int x = 0; x < image.width && !text; ++x)
            text = image.get(x, y).x > 0.9f && image.get(x, y).z > 0.9f;
    EXPECT_TRUE(text);
}

TEST(HeatMap, FrameWorkGivesPixelAndTileMaps) {
    PixelCounters pixels(TileGrid{16, 8, 8});
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            pixels.add(x, y, pixelQuantity("samples_tested"), 4);
            pixels.add(x, y, pixelQuantity("visibility_samples"), 1);
        }
    EXPECT_EQ(pixels.values(pixelQuantity("samples_tested"))[pixels.pixel(3, 5)], 4u);
    const std::string dir = test::temporaryDirectory();
    OutputSet outputs;
    const std::vector<std::string> files = writeHeatMaps(pixels, dir, outputs);
    EXPECT_EQ(files.size(), 2 * kPixelQuantities.size() + 3);  // and STE pixel/tile, tile tests
    for (const std::string& f : files) EXPECT_FALSE(std::filesystem::exists(f)) << "before commit";
    outputs.commit();
    for (const std::string& f : files) EXPECT_TRUE(std::filesystem::exists(f)) << f;
    for (const char* name :
         {"heat_samples_tested_pixel.png", "heat_rays_cast_tile.png", "heat_ste_pixel.png",
          "heat_ray_triangle_tests_tile.png", "heat_tile_tests_tile.png"})
        EXPECT_NE(std::find(files.begin(), files.end(), dir + "/" + name), files.end()) << name;
}

}  // namespace
}  // namespace patchsim
