#pragma once
// Arithmetic in a number format with a bound on how far it has strayed (issue 35: the tile
// planes and the leaf time intervals computed in fp16, bf16 or fixed point).
//
// Representation
// --------------
// A RoundedValue is what a datapath of the format holds after an operation, `value` (a value of
// the format, kept exactly in a double), together with `error`, an upper bound on its distance
// from the same expression evaluated exactly on the operands before they entered the format.
// This is running error analysis: every inexact operation adds its own rounding, which for
// rounding to nearest is at most half the format's spacing at the result (a float format's
// spacing is a power of two read off the result's exponent, fixed point's a constant; an exact
// one, which hardware knows by IEEE's inexact flag, adds nothing), and carries its
// operands' bounds through (for a product, |a| e_b + |b| e_a + e_a e_b). A site that must not
// reject then tests against the bound, not against zero: a plane distance is certainly positive
// only when value > error.
//
// The bound is itself computed in double and its total widened by a relative 2^-40, which covers
// double's own roundings in the few operations a site makes. A value the format cannot hold
// (a float format's overflow, fixed point's saturation) or NaN clears `inRange`, and so does any
// operation on such a value; a conservative site then gives up its test and accepts.
//
// With `Rounding::Nearest` this is also the naive datapath: the same values, the bound ignored.

#include "core/number_format.h"

namespace patchsim {

struct RoundedValue {
    double value = 0;     // what the datapath holds (infinity or saturated once out of range)
    double error = 0;     // >= |value - exact|, while in range
    bool inRange = true;  // false once an operation overflowed or saturated
};

class RoundedArithmetic {
  public:
    explicit RoundedArithmetic(NumberFormat format) : format_(format) {}
    const NumberFormat& format() const { return format_; }

    // `x` entering the datapath, rounded to nearest; exact inputs carry no error.
    RoundedValue input(double x) const;
    RoundedValue add(const RoundedValue& a, const RoundedValue& b) const;
    RoundedValue multiply(const RoundedValue& a, const RoundedValue& b) const;

    // The largest value of the format that is certainly no more than the exact one
    // (value - error, rounded down), and the smallest certainly no less. Beyond a fixed-point
    // range on the outward side (a lower bound below it, an upper bound above) the bound is
    // infinite, as saturating there would not bound; on the other side saturating is a bound.
    double certainLowerBound(const RoundedValue& a) const;
    double certainUpperBound(const RoundedValue& a) const;

    // a + b and a / b of two finite values of the format, rounded once as asked. Beyond a
    // fixed-point range on the rounding's side (up above it, down below it) the result is
    // infinite; on the other side it saturates, which is still directed. Infinite operands
    // give a directed but saturated result, not IEEE's infinity.
    double add(double a, double b, Rounding rounding) const;
    double divide(double a, double b, Rounding rounding) const;

  private:
    double directed(double x, Rounding rounding) const;
    RoundedValue rounded(double doubleResult, double carriedError, bool exactInDouble,
                         bool inRange) const;
    NumberFormat format_;
};

}  // namespace patchsim
