#include "core/number_format.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace patchsim {
namespace {

// Floats of every magnitude a rasterizer sees, and the awkward ones: zeros, subnormals of both
// formats, the binade edges, halves between neighbours, the largest values and beyond.
std::vector<float> probeValues() {
    std::vector<float> v = {0.0f,     -0.0f,    1.0f,       -1.0f,         0.1f,      1.0f / 3.0f,
                            65504.0f, 65519.0f, 65520.0f,   65536.0f,      -65520.0f, 1e-8f,
                            6.0e-8f,  -3.0e-8f, 6.1035e-5f, 2048.5f,       2049.0f,   1e30f,
                            3.4e38f,  1e-40f,   -1e-45f,    127.99609375f, 128.0f,    -128.0f};
    std::mt19937 random(7);
    std::uniform_int_distribution<std::uint32_t> bits;
    for (int i = 0; i < 20000; ++i) {
        const float x = std::bit_cast<float>(bits(random));
        if (std::isfinite(x)) v.push_back(x);
    }
    std::uniform_real_distribution<float> screen(-4096.0f, 4096.0f);
    for (int i = 0; i < 20000; ++i) v.push_back(screen(random));
    return v;
}

#ifdef __FLT16_MAX__
// Round to nearest equals the compiler's own conversion to IEEE half.
TEST(NumberFormat, Fp16ToNearestIsTheHardwareConversion) {
    for (const float x : probeValues()) {
        const float expected = float(static_cast<_Float16>(x));
        const float got = roundTo(x, NumberFormat::fp16());
        EXPECT_EQ(std::bit_cast<std::uint32_t>(got), std::bit_cast<std::uint32_t>(expected)) << x;
    }
}
#endif

// bfloat16 is float's top 16 bits: to nearest is adding half the dropped part, ties to even.
TEST(NumberFormat, Bf16ToNearestKeepsTheTopSixteenBitsRoundedToEven) {
    for (const float x : probeValues()) {
        const std::uint32_t b = std::bit_cast<std::uint32_t>(x);
        const std::uint32_t rounded = (b + 0x7fffu + ((b >> 16) & 1u)) & 0xffff0000u;
        const float expected = std::bit_cast<float>(rounded);
        EXPECT_EQ(std::bit_cast<std::uint32_t>(roundTo(x, NumberFormat::bf16())),
                  std::bit_cast<std::uint32_t>(expected))
            << x;
    }
}

// Rounded down and up, a value lies between two neighbours of the format, each a value of it
// (rounding it again changes nothing), at most one unit apart; a value of the format is itself.
TEST(NumberFormat, DownAndUpBracketEveryValueByNeighbours) {
    const NumberFormat formats[] = {NumberFormat::fp16(), NumberFormat::bf16(), kD3D11Snap,
                                    NumberFormat::fixed(8, 4), NumberFormat::fp32()};
    for (const NumberFormat& f : formats) {
        for (const float x : probeValues()) {
            if (!representable(x, f)) continue;
            const float down = roundTo(x, f, Rounding::Down), up = roundTo(x, f, Rounding::Up);
            ASSERT_LE(down, x) << formatName(f) << " " << x;
            ASSERT_GE(up, x) << formatName(f) << " " << x;
            EXPECT_EQ(roundTo(down, f), down) << formatName(f) << " " << x;
            if (std::isfinite(up)) {
                EXPECT_EQ(roundTo(up, f, Rounding::Down), up);
            }
            const float nearest = roundTo(x, f);
            EXPECT_TRUE(nearest == down || nearest == up) << formatName(f) << " " << x;
            if (std::isfinite(up) && std::isfinite(down)) {
                EXPECT_LE(double(up) - double(down), unitInLastPlace(up, f))
                    << formatName(f) << " " << x;
            }
            if (roundTo(x, f) == x) {
                EXPECT_TRUE(down == x && up == x) << formatName(f) << " " << x;
            }
        }
    }
}

TEST(NumberFormat, OverflowGoesToInfinityExceptTowardZero) {
    const NumberFormat half = NumberFormat::fp16();
    EXPECT_EQ(roundTo(65519.0f, half), 65504.0f);
    EXPECT_TRUE(std::isinf(roundTo(65520.0f, half)));  // the tie rounds to even: 2^16
    EXPECT_TRUE(std::isinf(roundTo(65505.0f, half, Rounding::Up)));
    EXPECT_EQ(roundTo(1e9f, half, Rounding::Down), 65504.0f);
    EXPECT_EQ(roundTo(-1e9f, half, Rounding::Up), -65504.0f);
    EXPECT_EQ(roundTo(-1e9f, half, Rounding::Down), -std::numeric_limits<float>::infinity());
    EXPECT_TRUE(std::isnan(roundTo(std::nanf(""), half)));
    EXPECT_EQ(roundTo(std::numeric_limits<float>::max(), NumberFormat::bf16(), Rounding::Down),
              std::ldexp(255.0f / 128.0f, 127));
}

// D3D11's 16.8 snap: multiples of 1/256 in [-32768, 32768 - 1/256]; beyond it a value saturates
// and is reported as not representable.
TEST(NumberFormat, TheD3D11SnapIsSixteenDotEightFixedPoint) {
    EXPECT_EQ(formatName(kD3D11Snap), "fixed16.8");
    EXPECT_EQ(roundTo(1.0f / 3.0f, kD3D11Snap), 85.0f / 256.0f);
    EXPECT_EQ(roundTo(1.0f / 3.0f, kD3D11Snap, Rounding::Up), 86.0f / 256.0f);
    EXPECT_EQ(roundTo(-1.0f / 3.0f, kD3D11Snap, Rounding::Down), -86.0f / 256.0f);
    EXPECT_EQ(roundTo(0.5f / 256.0f, kD3D11Snap), 0.0f);           // a tie, to even
    EXPECT_EQ(roundTo(1.5f / 256.0f, kD3D11Snap), 2.0f / 256.0f);  // a tie, to even
    EXPECT_EQ(unitInLastPlace(1000.0f, kD3D11Snap), 1.0 / 256.0);
    EXPECT_TRUE(representable(32767.99609375f, kD3D11Snap));
    EXPECT_FALSE(representable(32768.0f, kD3D11Snap));
    EXPECT_TRUE(representable(-32768.0f, kD3D11Snap));
    EXPECT_EQ(roundTo(1e6f, kD3D11Snap, Rounding::Up), 32767.99609375f);  // saturated
    EXPECT_EQ(formatName(NumberFormat::fp16()), "fp16");
}

}  // namespace
}  // namespace patchsim
