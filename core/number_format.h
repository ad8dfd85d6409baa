#pragma once
// The number formats an arithmetic site of the modelled hardware may compute in (issue 35: the
// screen bounds, the tile planes, the leaf time intervals, the ray tests, the domain-shaded
// positions), emulated exactly on float.
//
// Representation
// --------------
// A NumberFormat is a kind and, for fixed point, its widths. fp32 is IEEE single (every float
// is exact); fp16 is IEEE half (1 sign, 5 exponent, 10 fraction bits, subnormals, largest
// 65504); bf16 is bfloat16 (1, 8, 7: float's range, 8 bits of significand). Fixed point is two's
// complement with `integerBits` bits before the point (the sign among them) and `fractionBits`
// after, so its values are the multiples of 2^-fractionBits in [-2^(integerBits-1),
// 2^(integerBits-1) - 2^-fractionBits]; D3D11's rasterizer snaps vertices to 16.8 (kD3D11Snap).
//
// roundTo gives the format's value for a float: the nearest (ties to even), or the nearest below
// or above, which a conservative site uses to widen a bound outward. Every step is exact in
// double (a float times a power of two, rounded to an integer, times the power again), so the
// emulation is exact, not an approximation of the format. A float format's overflow goes to
// infinity, except toward zero (the largest finite value); fixed point saturates at its range,
// which no rounding direction can make conservative: representable() says when a value lies
// outside it. NaN stays NaN.

#include <cstdint>
#include <string>

namespace patchsim {

struct NumberFormat {
    enum class Kind : std::uint8_t { Fp32, Fp16, Bf16, Fixed };
    Kind kind = Kind::Fp32;
    int integerBits = 0;   // fixed point only, the sign bit included
    int fractionBits = 0;  // fixed point only

    static NumberFormat fp32() { return {}; }
    static NumberFormat fp16() { return {Kind::Fp16, 0, 0}; }
    static NumberFormat bf16() { return {Kind::Bf16, 0, 0}; }
    static NumberFormat fixed(int integerBits, int fractionBits) {
        return {Kind::Fixed, integerBits, fractionBits};
    }
    bool operator==(const NumberFormat&) const = default;
};

// D3D11's vertex snap: 16.8 fixed point (8 bits of sub-pixel precision).
inline const NumberFormat kD3D11Snap = NumberFormat::fixed(16, 8);

enum class Rounding : std::uint8_t { Nearest, Down, Up };

// `x` in `format`, rounded as asked (see the essay above).
float roundTo(float x, const NumberFormat& format, Rounding rounding = Rounding::Nearest);
// The same for a double, for arithmetic emulated in the format (rounded_arithmetic.h): fp32
// rounds to float's grid here, and a fixed-point value wider than float's significand stays
// exact.
double roundDoubleTo(double x, const NumberFormat& format, Rounding rounding = Rounding::Nearest);

// False for a finite value beyond a fixed-point format's range (it would saturate); true for
// every float format and for infinities and NaN, which keep their meaning.
bool representable(double x, const NumberFormat& format);

// The distance from |x| to the next larger value of the format: one unit in the last place.
double unitInLastPlace(double x, const NumberFormat& format);

// "fp32", "fp16", "bf16", "fixed16.8".
std::string formatName(const NumberFormat& format);
// The inverse of formatName: "fixedI.F" with I in [2, 32], F in [0, 30] and I + F <= 48. False
// for anything else.
bool parseNumberFormat(const std::string& name, NumberFormat& out);
// Bits a value takes in storage: 32, 16, or I + F.
int storageBits(const NumberFormat& format);

}  // namespace patchsim
