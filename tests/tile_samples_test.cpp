#include "rasterizer/tile_samples.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace patchsim {
namespace {

Camera testCamera(int width, int height) {
    CameraDesc desc;
    desc.open = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}};
    desc.close = desc.open;
    return Camera(desc, {}, width, height);
}

// A tile grid whose last column and row are partial tiles.
const TileGrid kGrid{19, 13, 8};

TEST(TileSamples, EverySampleOnceInItsTileOrderedByTimeThenRecord) {
    const Camera camera = testCamera(kGrid.width, kGrid.height);
    for (SamplePattern pattern : {SamplePattern::Stratified, SamplePattern::Grid}) {
        const SampleGenerator generator(11, 9, Effects{true, false, true, false}, pattern);
        for (int threads : {1, 2}) {
            const TileSamples tiles(kGrid, camera, generator, threads);
            std::vector<int> seen(std::size_t(kGrid.width * kGrid.height * 9), 0);
            for (int ty = 0; ty < kGrid.tilesY(); ++ty)
                for (int tx = 0; tx < kGrid.tilesX(); ++tx) {
                    const TileRect r = kGrid.rect(tx, ty);
                    const std::span<const TileSample> tile = tiles.tile(tx, ty);
                    ASSERT_EQ(tile.size(), std::size_t((r.x1 - r.x0) * (r.y1 - r.y0) * 9));
                    for (std::size_t i = 0; i < tile.size(); ++i) {
                        const TileSample& s = tile[i];
                        const int pixel = int(s.record / 9), index = int(s.record % 9);
                        const int x = pixel % kGrid.width, y = pixel / kGrid.width;
                        EXPECT_TRUE(x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1);
                        const Sample expected = generator.sample(x, y, index);
                        EXPECT_EQ(s.time, expected.time);
                        EXPECT_EQ(s.lens, expected.lens);
                        EXPECT_EQ(s.disk, concentricDisk(expected.lens));
                        ++seen[s.record];
                        if (i > 0) {
                            const TileSample& p = tile[i - 1];
                            EXPECT_TRUE(p.time < s.time ||
                                        (p.time == s.time && p.record < s.record))
                                << "tile " << tx << "," << ty << " position " << i;
                        }
                    }
                }
            EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
        }
    }
}

TEST(TileSamples, ATimeRangeIsExactlyTheSamplesInsideIt) {
    const Camera camera = testCamera(kGrid.width, kGrid.height);
    const SampleGenerator generator(5, 16, Effects{true, false, false, false}, SamplePattern::Grid);
    const TileSamples tiles(kGrid, camera, generator, 1);
    // The grid pattern's times include exactly 0 and 1, the ends of a range.
    for (TimeRange range : {TimeRange{0.25f, 0.5f}, TimeRange{0.0f, 0.0f}, TimeRange{0.0f, 1.0f},
                            TimeRange{0.7f, 1.0f}, TimeRange{0.6f, 0.4f}}) {
        const std::span<const TileSample> all = tiles.tile(1, 1);
        const std::span<const TileSample> inside = tiles.inTime(1, 1, range);
        const auto expected = std::count_if(all.begin(), all.end(), [&](const TileSample& s) {
            return !range.isEmpty() && s.time >= range.lower && s.time <= range.upper;
        });
        EXPECT_EQ(std::ptrdiff_t(inside.size()), expected) << range.lower << " " << range.upper;
        for (const TileSample& s : inside) {
            EXPECT_GE(s.time, range.lower);
            EXPECT_LE(s.time, range.upper);
        }
    }
}

TEST(TileSamples, WithoutTimeEverySampleIsAtTimeZeroInRecordOrder) {
    const Camera camera = testCamera(kGrid.width, kGrid.height);
    const SampleGenerator generator(3, 4, Effects{false, false, true, false});
    const TileSamples tiles(kGrid, camera, generator, 2);
    const std::span<const TileSample> tile = tiles.tile(2, 0);
    ASSERT_FALSE(tile.empty());
    for (std::size_t i = 0; i < tile.size(); ++i) {
        EXPECT_EQ(tile[i].time, 0.0f);
        EXPECT_FALSE(std::signbit(tile[i].time));
        if (i > 0) {
            EXPECT_LT(tile[i - 1].record, tile[i].record);
        }
    }
}

}  // namespace
}  // namespace patchsim
