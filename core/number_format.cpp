#include "core/number_format.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace patchsim {

namespace {

// An IEEE-like binary format: fraction bits, the smallest normal exponent and the largest finite
// value.
struct FloatLayout {
    int fractionBits;
    int minExponent;  // of the smallest normal value, 2^minExponent
    double largest;
};

FloatLayout layoutOf(NumberFormat::Kind kind) {
    if (kind == NumberFormat::Kind::Fp16) return {10, -14, 65504.0};
    if (kind == NumberFormat::Kind::Bf16)
        return {7, -126, std::ldexp(2.0 - std::ldexp(1.0, -7), 127)};
    return {23, -126, double(std::numeric_limits<float>::max())};
}

// `scaled` (an exact double) to an integer as asked; ties to even.
double roundInteger(double scaled, Rounding rounding) {
    if (rounding == Rounding::Down) return std::floor(scaled);
    if (rounding == Rounding::Up) return std::ceil(scaled);
    return std::nearbyint(scaled);  // the default environment: to nearest, ties to even
}

// The format's spacing at |x|: 2^(exponent - fraction bits), the exponent no smaller than the
// smallest normal one (below it the spacing is the subnormals').
double unitInLastPlaceOf(double x, const FloatLayout& f) {
    int exponent = f.minExponent;
    if (x != 0.0 && std::isfinite(x)) exponent = std::max(std::ilogb(x), f.minExponent);
    return std::ldexp(1.0, exponent - f.fractionBits);
}

double roundFloatFormat(double x, const FloatLayout& f, Rounding rounding) {
    const double ulp = unitInLastPlaceOf(x, f);
    const double value = roundInteger(x / ulp, rounding) * ulp;
    if (std::abs(value) <= f.largest) return value;
    // Beyond the largest finite value: infinity, unless the rounding goes toward zero.
    const bool towardZero =
        (value > 0 && rounding == Rounding::Down) || (value < 0 && rounding == Rounding::Up);
    if (towardZero) return std::copysign(f.largest, value);
    return std::copysign(std::numeric_limits<double>::infinity(), value);
}

}  // namespace

double roundDoubleTo(double x, const NumberFormat& format, Rounding rounding) {
    if (std::isnan(x) || std::isinf(x)) return x;
    if (format.kind != NumberFormat::Kind::Fixed)
        return roundFloatFormat(x, layoutOf(format.kind), rounding);
    const double ulp = std::ldexp(1.0, -format.fractionBits);
    const double low = -std::ldexp(1.0, format.integerBits - 1);
    const double high = -low - ulp;
    const double value = roundInteger(x / ulp, rounding) * ulp;
    return std::min(std::max(value, low), high);
}

float roundTo(float x, const NumberFormat& format, Rounding rounding) {
    if (format.kind == NumberFormat::Kind::Fp32) return x;
    return float(roundDoubleTo(double(x), format, rounding));
}

bool representable(double x, const NumberFormat& format) {
    if (format.kind != NumberFormat::Kind::Fixed || !std::isfinite(x)) return true;
    const double ulp = std::ldexp(1.0, -format.fractionBits);
    const double low = -std::ldexp(1.0, format.integerBits - 1);
    return x >= low && x <= -low - ulp;
}

double unitInLastPlace(double x, const NumberFormat& format) {
    if (format.kind == NumberFormat::Kind::Fixed) return std::ldexp(1.0, -format.fractionBits);
    return unitInLastPlaceOf(x, layoutOf(format.kind));
}

std::string formatName(const NumberFormat& format) {
    switch (format.kind) {
        case NumberFormat::Kind::Fp32:
            return "fp32";
        case NumberFormat::Kind::Fp16:
            return "fp16";
        case NumberFormat::Kind::Bf16:
            return "bf16";
        case NumberFormat::Kind::Fixed:
            return "fixed" + std::to_string(format.integerBits) + "." +
                   std::to_string(format.fractionBits);
    }
    return "?";
}

bool parseNumberFormat(const std::string& name, NumberFormat& out) {
    for (const NumberFormat f : {NumberFormat::fp32(), NumberFormat::fp16(), NumberFormat::bf16()})
        if (name == formatName(f)) {
            out = f;
            return true;
        }
    int integerBits = 0, fractionBits = 0, consumed = 0;
    if (std::sscanf(name.c_str(), "fixed%d.%d%n", &integerBits, &fractionBits, &consumed) != 2 ||
        consumed != int(name.size()))
        return false;
    const NumberFormat f = NumberFormat::fixed(integerBits, fractionBits);
    if (integerBits < 2 || integerBits > 32 || fractionBits < 0 || fractionBits > 30 ||
        integerBits + fractionBits > 48 || formatName(f) != name)
        return false;
    out = f;
    return true;
}

int storageBits(const NumberFormat& format) {
    switch (format.kind) {
        case NumberFormat::Kind::Fp32:
            return 32;
        case NumberFormat::Kind::Fp16:
        case NumberFormat::Kind::Bf16:
            return 16;
        case NumberFormat::Kind::Fixed:
            return format.integerBits + format.fractionBits;
    }
    return 32;
}

}  // namespace patchsim
