#include "core/image_pass_trace.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace patchsim {
namespace {

TEST(ImagePassTrace, PlanesAreMaskBitsAndAPassCountsItsBytesByPlane) {
    ImagePassTrace trace(4, 2);  // plane 0: the resolved image, 8 pixels of 8 bytes
    ASSERT_EQ(trace.planes().size(), 1u);
    EXPECT_EQ(trace.planes()[0].elements, 8u);
    EXPECT_EQ(ImagePassTrace::resolvedImage(), 1u);
    const std::uint16_t depth = trace.addPlane("depth", 8, 4);
    const std::uint16_t tiles = trace.addPlane("tiles", 2, 4);
    EXPECT_EQ(depth, 2u);
    EXPECT_EQ(tiles, 4u);
    trace.beginPass("filter");
    for (std::size_t i = 0; i < 8; ++i)
        trace.read(std::uint16_t(ImagePassTrace::resolvedImage() | depth), i);
    trace.write(tiles, 0);
    trace.write(tiles, 1);
    ASSERT_EQ(trace.passes().size(), 1u);
    const ImagePass& pass = trace.passes()[0];
    EXPECT_EQ(pass.name, "filter");
    EXPECT_EQ(pass.elements.size(), 10u);
    EXPECT_EQ(trace.passBytes(pass, false), 8u * (8 + 4));
    EXPECT_EQ(trace.passBytes(pass, true), 2u * 4);
    EXPECT_EQ(pass.planes[8], std::uint16_t(tiles | kImageWrite));
    EXPECT_EQ(trace.bytes(), 10u * 6);
}

TEST(ImagePassTrace, AnUpdateCountsAsARead) {
    ImagePassTrace trace(2, 1, 2);  // two resolved frames: planes 0 and 1
    EXPECT_EQ(trace.planes().size(), 2u);
    EXPECT_EQ(ImagePassTrace::resolvedImage(1), 2u);
    const std::uint16_t sum = trace.addPlane("sum", 2, 16);
    trace.beginPass("blend");
    trace.update(sum, 1);
    trace.read(ImagePassTrace::resolvedImage(1), 0);
    EXPECT_EQ(trace.passBytes(trace.passes()[0], false), 16u + 8);
    EXPECT_EQ(trace.passBytes(trace.passes()[0], true), 16u);
}

TEST(ImagePassTrace, HoldsAtMostFourteenPlanes) {
    ImagePassTrace trace(1, 1);
    for (int p = 1; p < kMaxImagePlanes; ++p) trace.addPlane("p", 1, 1);
    EXPECT_THROW(trace.addPlane("one too many", 1, 1), std::logic_error);
}

}  // namespace
}  // namespace patchsim
