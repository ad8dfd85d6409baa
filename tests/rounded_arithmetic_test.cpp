#include "core/rounded_arithmetic.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace patchsim {
namespace {

using Exact = __float128;  // 113 bits: the test's sums of float products are exact in it

double absExact(Exact x) {
    return double(x < 0 ? -x : x);
}

const NumberFormat kFormats[] = {NumberFormat::fp16(),        NumberFormat::bf16(),
                                 NumberFormat::fp32(),        NumberFormat::fixed(16, 8),
                                 NumberFormat::fixed(24, 16), NumberFormat::fixed(12, 4)};

// A plane distance n . p + d on float operands, as tile_frustum_rounded.cpp evaluates it: the
// bound holds on every case, and it is tight enough to matter (within a few roundings of the
// terms' size).
TEST(RoundedArithmetic, TheBoundHoldsOnDotProductsInEveryFormat) {
    std::mt19937 random(11);
    std::uniform_real_distribution<float> value(-40.0f, 40.0f);
    for (const NumberFormat& format : kFormats) {
        const RoundedArithmetic a(format);
        int inRange = 0;
        double worstUse = 0;  // largest actual error over its bound
        for (int i = 0; i < 50000; ++i) {
            float n[3], p[3];
            for (int k = 0; k < 3; ++k) n[k] = i % 4 == 0 && k < 2 ? float(k) : value(random);
            for (int k = 0; k < 3; ++k) p[k] = value(random);
            const float d = value(random);
            RoundedValue sum = a.input(d);
            Exact exact = Exact(d);
            double size = std::abs(d);
            for (int k = 0; k < 3; ++k) {
                sum = a.add(sum, a.multiply(a.input(n[k]), a.input(p[k])));
                exact += Exact(n[k]) * Exact(p[k]);
                size += std::abs(double(n[k]) * p[k]);
            }
            if (!sum.inRange) continue;
            ++inRange;
            const double actual = absExact(Exact(sum.value) - exact);
            ASSERT_LE(actual, sum.error) << formatName(format) << " case " << i;
            ASSERT_LE(a.certainLowerBound(sum), double(exact)) << formatName(format);
            ASSERT_GE(a.certainUpperBound(sum), double(exact)) << formatName(format);
            if (sum.error > 0) worstUse = std::max(worstUse, actual / sum.error);
            // Not vacuous: no more than a few of the format's steps at the terms' size.
            const double step = format.kind == NumberFormat::Kind::Fixed
                                    ? unitInLastPlace(0.0, format) * (1 + std::abs(n[2]) + 40)
                                    : unitInLastPlace(size, format);
            EXPECT_LE(sum.error, 8 * step) << formatName(format);
        }
        EXPECT_GT(inRange, 25000) << formatName(format);
        EXPECT_GT(worstUse, 0.1) << formatName(format) << ": the bound is far looser than needed";
    }
}

#ifdef __FLT16_MAX__
// The naive datapath's values are IEEE half's own arithmetic, operation for operation.
TEST(RoundedArithmetic, Fp16ValuesAreHalfPrecisionArithmetic) {
    std::mt19937 random(3);
    std::uniform_real_distribution<float> value(-300.0f, 300.0f);
    const RoundedArithmetic a(NumberFormat::fp16());
    for (int i = 0; i < 20000; ++i) {
        const float x = value(random), y = value(random);
        const _Float16 hx = _Float16(x), hy = _Float16(y);
        const RoundedValue rx = a.input(x), ry = a.input(y);
        EXPECT_EQ(rx.value, double(float(hx)));
        EXPECT_EQ(a.multiply(rx, ry).value, double(float(_Float16(hx * hy)))) << x << " " << y;
        EXPECT_EQ(a.add(rx, ry).value, double(float(_Float16(hx + hy)))) << x << " " << y;
    }
}
#endif

// Operations the format does exactly add nothing to the bound: a plane's unit normal component
// times a coordinate of the format, and a sum of two small integers.
TEST(RoundedArithmetic, ExactOperationsAddNoError) {
    for (const NumberFormat& format : kFormats) {
        const RoundedArithmetic a(format);
        const RoundedValue one = a.input(1.0), three = a.input(3.0), half = a.input(0.5);
        EXPECT_EQ(a.multiply(one, three).error, 0) << formatName(format);
        EXPECT_EQ(a.add(three, half).error, 0) << formatName(format);
        EXPECT_EQ(a.certainLowerBound(a.add(three, half)), 3.5) << formatName(format);
        EXPECT_GT(a.input(0.1).error, 0) << formatName(format);
    }
}

// Directed sums and quotients bracket the exact result, in every format.
TEST(RoundedArithmetic, DirectedSumsAndQuotientsBracketTheExactOnes) {
    std::mt19937 random(5);
    std::uniform_real_distribution<float> value(0.001f, 20.0f);
    for (const NumberFormat& format : kFormats) {
        const RoundedArithmetic a(format);
        for (int i = 0; i < 20000; ++i) {
            const double x = a.input(value(random)).value, y = a.input(value(random)).value;
            const Exact sum = Exact(x) + Exact(y), quotient = Exact(x) / Exact(y);
            EXPECT_LE(Exact(a.add(x, y, Rounding::Down)), sum) << formatName(format);
            EXPECT_GE(Exact(a.add(x, y, Rounding::Up)), sum) << formatName(format);
            if (y == 0) continue;
            EXPECT_LE(Exact(a.divide(x, y, Rounding::Down)), quotient) << formatName(format);
            EXPECT_GE(Exact(a.divide(x, y, Rounding::Up)), quotient) << formatName(format);
        }
    }
}

// Beyond the range: fixed point saturates and a float format overflows; either way the value is
// out of range and so is everything computed from it, and its bounds open to infinity.
TEST(RoundedArithmetic, OutOfRangeValuesGiveUpTheirBound) {
    const RoundedArithmetic fixed(NumberFormat::fixed(8, 4));
    const RoundedValue big = fixed.multiply(fixed.input(100.0), fixed.input(100.0));
    EXPECT_FALSE(big.inRange);
    EXPECT_EQ(big.value, 127.9375);  // saturated, as the naive datapath holds it
    EXPECT_FALSE(fixed.add(big, fixed.input(1.0)).inRange);
    EXPECT_EQ(fixed.certainLowerBound(big), -INFINITY);
    EXPECT_EQ(fixed.certainUpperBound(big), INFINITY);
    EXPECT_EQ(fixed.add(100.0, 100.0, Rounding::Up), INFINITY);  // not the saturated 127.9375
    EXPECT_EQ(fixed.add(-100.0, -100.0, Rounding::Down), -INFINITY);
    EXPECT_EQ(fixed.add(100.0, 100.0, Rounding::Down), 127.9375);  // saturating is a lower bound
    const RoundedArithmetic half(NumberFormat::fp16());
    EXPECT_FALSE(half.multiply(half.input(1000.0), half.input(1000.0)).inRange);
    EXPECT_FALSE(half.input(1e6).inRange);
}

}  // namespace
}  // namespace patchsim
