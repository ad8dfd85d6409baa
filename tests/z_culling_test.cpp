#include "rasterizer/common/z_culling.h"

#include <gtest/gtest.h>

namespace patchsim {
namespace {

TEST(ZCulling, RayEndsJustPastTheSampleDepth) {
    const float end = rayEndAtDepth(5.0f, 2.0f);
    EXPECT_GT(end, 2.5f);  // inclusive: an equal-depth hit still reaches the tie-break
    EXPECT_LT(end, 2.5f * (1.0f + 1e-5f));
}

}  // namespace
}  // namespace patchsim
