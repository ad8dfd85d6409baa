#include "rasterizer/z_culling.h"

#include <gtest/gtest.h>

namespace patchsim {
namespace {

TEST(ZCulling, TileBoundIsTheDeepestSampleStillOpen) {
    VisibilityBuffer buffer(8, 8, 2, 100.0f);
    const TileRect tile{0, 0, 4, 4};
    EXPECT_EQ(tileDepthBound(buffer, tile), 100.0f);  // nothing drawn: the far plane
    VisibilityRecord hit;
    hit.patch = 0;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            for (int s = 0; s < 2; ++s) {
                hit.depth = 3.0f + float(x + y + s);
                buffer.offer(x, y, s, hit);
            }
    EXPECT_EQ(tileDepthBound(buffer, tile), 3.0f + 3 + 3 + 1);
    EXPECT_EQ(tileDepthBound(buffer, {4, 4, 8, 8}), 100.0f);  // another tile, still open
}

TEST(ZCulling, RayEndsJustPastTheSampleDepth) {
    const float end = rayEndAtDepth(5.0f, 2.0f);
    EXPECT_GT(end, 2.5f);  // inclusive: an equal-depth hit still reaches the tie-break
    EXPECT_LT(end, 2.5f * (1.0f + 1e-5f));
}

}  // namespace
}  // namespace patchsim
