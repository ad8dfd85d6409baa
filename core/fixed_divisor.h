#pragma once
// Division of 32-bit unsigned integers by a divisor fixed at run time, without a divide
// instruction, exact for every dividend.
//
// Representation
// --------------
// The divisor d and c = ceil(2^64 / d), kept modulo 2^64 (so c is 0 for d = 1). Then
// a / d = floor(c * a / 2^64) and a % d = floor((c * a mod 2^64) * d / 2^64) for every 32-bit a
// (Lemire, Kaser and Kurz, "Faster remainder by direct computation", 2019, with 64-bit c for
// 32-bit operands). Two multiplies replace a division that costs 20 to 30 cycles; the sample
// generator takes several remainders by the sample count per sample.

#include <cstdint>

namespace patchsim {

class FixedDivisor {
  public:
    explicit FixedDivisor(std::uint32_t divisor)
        : divisor_(divisor), inverse_(~std::uint64_t(0) / divisor + 1) {}

    std::uint32_t divisor() const { return divisor_; }

    std::uint32_t quotient(std::uint32_t a) const {
        return divisor_ == 1 ? a : std::uint32_t(highHalf(inverse_, a));
    }
    std::uint32_t remainder(std::uint32_t a) const {
        return std::uint32_t(highHalf(inverse_ * a, divisor_));
    }

  private:
    // The upper 64 bits of the 128-bit product.
    static std::uint64_t highHalf(std::uint64_t x, std::uint64_t y) {
        __extension__ using Wide = unsigned __int128;
        return std::uint64_t((Wide(x) * Wide(y)) >> 64);
    }

    std::uint32_t divisor_;
    std::uint64_t inverse_;
};

}  // namespace patchsim
