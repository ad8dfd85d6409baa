#include "core/fixed_divisor.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

namespace patchsim {
namespace {

// Quotient and remainder equal the division's for every divisor the sampler meets (sample counts
// and grid sides) and for random ones, at the dividends where an approximate inverse would slip
// first: multiples of the divisor and their neighbours, and the ends of the 32-bit range.
TEST(FixedDivisor, EqualsTheDivisionForEveryDividend) {
    std::vector<std::uint32_t> divisors;
    for (std::uint32_t d = 1; d <= 1100; ++d) divisors.push_back(d);
    std::mt19937 random(5);
    for (int k = 0; k < 200; ++k) divisors.push_back(std::uint32_t(random()) | 1u);
    for (std::uint32_t d : {0x7fffffffu, 0x80000000u, 0xfffffffeu, 0xffffffffu, 641u, 6700417u})
        divisors.push_back(d);
    for (std::uint32_t d : divisors) {
        const FixedDivisor f(d);
        ASSERT_EQ(f.divisor(), d);
        std::vector<std::uint32_t> dividends = {0u,          1u,          0x7fffffffu,
                                                0x80000000u, 0xffffffffu, 0xfffffffeu};
        for (std::uint64_t q : {std::uint64_t(1), std::uint64_t(2), std::uint64_t(0xffffffffu / d)})
            for (std::int64_t delta : {-1, 0, 1}) {
                const std::int64_t a = std::int64_t(q * d) + delta;
                if (a >= 0 && a <= 0xffffffffll) dividends.push_back(std::uint32_t(a));
            }
        for (int k = 0; k < 300; ++k) dividends.push_back(std::uint32_t(random()));
        for (std::uint32_t a : dividends) {
            ASSERT_EQ(f.quotient(a), a / d) << a << " / " << d;
            ASSERT_EQ(f.remainder(a), a % d) << a << " % " << d;
        }
    }
}

// Every dividend below 2^20 for the small divisors (the sample counts of real films).
TEST(FixedDivisor, ExhaustiveForSmallDivisorsAndDividends) {
    for (std::uint32_t d = 1; d <= 64; ++d) {
        const FixedDivisor f(d);
        for (std::uint32_t a = 0; a < (1u << 20); ++a) {
            if (f.quotient(a) != a / d || f.remainder(a) != a % d) {
                FAIL() << a << " by " << d;
            }
        }
    }
}

}  // namespace
}  // namespace patchsim
