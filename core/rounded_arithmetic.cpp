#include "core/rounded_arithmetic.h"

#include <cmath>
#include <limits>

namespace patchsim {

namespace {

constexpr double kDoubleSlack = 0x1p-40;  // relative; double's own roundings in the bound

// The rounding to an integer a nearest rounding to the format may make at `value`, and double's
// rounding of `exact` when the double result was not exact.
double ownError(double value, double doubleResult, bool exactInDouble, const NumberFormat& f) {
    if (exactInDouble && value == doubleResult) return 0;
    const double half = 0.5 * unitInLastPlace(value, f);
    return exactInDouble ? half : half + 0x1p-52 * std::abs(doubleResult);
}

}  // namespace

RoundedValue RoundedArithmetic::rounded(double doubleResult, double carriedError,
                                        bool exactInDouble, bool inRange) const {
    // Out of range, the value is what the datapath holds (infinity, or fixed point saturated),
    // for the naive variant; the bound is gone.
    const double value = roundDoubleTo(doubleResult, format_);
    if (!inRange || !std::isfinite(doubleResult) || !representable(doubleResult, format_) ||
        !std::isfinite(value))
        return {value, std::numeric_limits<double>::infinity(), false};
    return {value, carriedError + ownError(value, doubleResult, exactInDouble, format_), true};
}

double RoundedArithmetic::directed(double x, Rounding rounding) const {
    if (!representable(x, format_)) {  // fixed point would saturate on the wrong side
        if (rounding == Rounding::Up && x > 0) return std::numeric_limits<double>::infinity();
        if (rounding == Rounding::Down && x < 0) return -std::numeric_limits<double>::infinity();
    }
    return roundDoubleTo(x, format_, rounding);
}

RoundedValue RoundedArithmetic::input(double x) const {
    return rounded(x, 0, true, true);
}

RoundedValue RoundedArithmetic::add(const RoundedValue& a, const RoundedValue& b) const {
    const double sum = a.value + b.value;
    const double bPart = sum - a.value;  // TwoSum: the sum's rounding in double, exactly
    const double residual = (a.value - (sum - bPart)) + (b.value - bPart);
    return rounded(sum, a.error + b.error, residual == 0, a.inRange && b.inRange);
}

RoundedValue RoundedArithmetic::multiply(const RoundedValue& a, const RoundedValue& b) const {
    const double product = a.value * b.value;
    const bool exact = std::fma(a.value, b.value, -product) == 0;
    const double carried =
        std::abs(a.value) * b.error + std::abs(b.value) * a.error + a.error * b.error;
    return rounded(product, carried, exact, a.inRange && b.inRange);
}

double RoundedArithmetic::certainLowerBound(const RoundedValue& a) const {
    if (!a.inRange) return -std::numeric_limits<double>::infinity();
    if (a.error == 0) return a.value;
    const double below = std::nextafter(a.value - a.error * (1 + kDoubleSlack), -INFINITY);
    return directed(below, Rounding::Down);
}

double RoundedArithmetic::certainUpperBound(const RoundedValue& a) const {
    if (!a.inRange) return std::numeric_limits<double>::infinity();
    if (a.error == 0) return a.value;
    const double above = std::nextafter(a.value + a.error * (1 + kDoubleSlack), INFINITY);
    return directed(above, Rounding::Up);
}

double RoundedArithmetic::add(double a, double b, Rounding rounding) const {
    double sum = a + b;
    const double bPart = sum - a;
    const bool exact = (a - (sum - bPart)) + (b - bPart) == 0;
    if (!exact && rounding == Rounding::Down) sum = std::nextafter(sum, -INFINITY);
    if (!exact && rounding == Rounding::Up) sum = std::nextafter(sum, INFINITY);
    return directed(sum, rounding);
}

double RoundedArithmetic::divide(double a, double b, Rounding rounding) const {
    double quotient = a / b;
    const bool exact = std::isfinite(quotient) && std::fma(quotient, b, -a) == 0;
    if (!exact && rounding == Rounding::Down) quotient = std::nextafter(quotient, -INFINITY);
    if (!exact && rounding == Rounding::Up) quotient = std::nextafter(quotient, INFINITY);
    return directed(quotient, rounding);
}

}  // namespace patchsim
