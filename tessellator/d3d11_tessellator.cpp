#include "tessellator/d3d11_tessellator.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>

namespace patchsim {

namespace {

constexpr int kFractionBits = 16;
constexpr std::uint32_t kFractionMask = 0x0000ffffu;
constexpr std::uint32_t kIntegerMask = 0x7fff0000u;
constexpr std::uint32_t kOne = 1u << kFractionBits;
constexpr std::uint32_t kOneHalf = 0x00008000u;
constexpr std::uint32_t kOneThird = 0x00005555u;
constexpr std::uint32_t kTwoThirds = 0x0000aaaau;

constexpr float kMinOddFactor = 1.0f;
constexpr float kMaxOddFactor = 63.0f;
constexpr float kMinEvenFactor = 2.0f;
constexpr float kMaxEvenFactor = 64.0f;
// 2^-16, the smallest positive fixed-point fraction.
constexpr float kFixedEpsilon = 0.0000152587890625f;

// 1/n in 16.16 for n segments, as tabulated by the reference (entry 0 unused).
constexpr std::uint32_t kReciprocal[65] = {
    0xffffffff, 0x10000, 0x8000, 0x5555, 0x4000, 0x3333, 0x2aab, 0x2492, 0x2000, 0x1c72, 0x199a,
    0x1746,     0x1555,  0x13b1, 0x1249, 0x1111, 0x1000, 0xf0f,  0xe39,  0xd79,  0xccd,  0xc31,
    0xba3,      0xb21,   0xaab,  0xa3d,  0x9d9,  0x97b,  0x925,  0x8d4,  0x889,  0x842,  0x800,
    0x7c2,      0x788,   0x750,  0x71c,  0x6eb,  0x6bd,  0x690,  0x666,  0x63e,  0x618,  0x5f4,
    0x5d1,      0x5b0,   0x591,  0x572,  0x555,  0x539,  0x51f,  0x505,  0x4ec,  0x4d5,  0x4be,
    0x4a8,      0x492,   0x47e,  0x46a,  0x457,  0x444,  0x432,  0x421,  0x410,  0x400};

// Where vertex i ends up on a half edge under ruler-function split order; drives stitching.
constexpr int kFinalPointPosition[33] = {0,  32, 16, 8,  17, 4,  18, 9,  19, 2,  20,
                                         10, 21, 5,  22, 11, 23, 1,  24, 12, 25, 6,
                                         26, 13, 27, 3,  28, 14, 29, 7,  30, 15, 31};
constexpr int kLoopStart[33] = {1, 1, 17, 9, 9, 5, 5, 5, 5, 3, 3, 3, 3, 3, 3, 3, 3,
                                2, 2, 2,  2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2};
constexpr int kLoopEnd[33] = {0,  0,  17, 17, 25, 25, 25, 25, 29, 29, 29, 29, 29, 29, 29, 29, 31,
                              31, 31, 31, 31, 31, 31, 31, 31, 31, 31, 31, 31, 31, 31, 31, 32};

std::uint32_t floatBits(float f) {
    return std::bit_cast<std::uint32_t>(f);
}

bool isNaN(float a) {
    const std::uint32_t bits = floatBits(a);
    return (bits & 0x7f800000u) == 0x7f800000u && (bits & 0x007fffffu) != 0;
}

// Denormals flush to a signed zero, as D3D float math does.
float flushDenorm(float a) {
    const std::uint32_t bits = floatBits(a);
    if ((bits & 0x7fffffffu) < 0x00800000u) return std::bit_cast<float>(bits & 0x80000000u);
    return a;
}

// IEEE 754R min and max as the reference defines them: a NaN operand b yields a.
float d3dMin(float a, float b) {
    const float fa = flushDenorm(a), fb = flushDenorm(b);
    if (isNaN(fb)) return a;
    if (fa == 0 && fb == 0) return (floatBits(fa) & 0x80000000u) ? a : b;
    return fa < fb ? a : b;
}

float d3dMax(float a, float b) {
    const float fa = flushDenorm(a), fb = flushDenorm(b);
    if (isNaN(fb)) return a;
    if (fa == 0 && fb == 0) return (floatBits(fb) & 0x80000000u) ? a : b;
    return fa >= fb ? a : b;
}

float clampFactor(float f, float lower, float upper) {
    return d3dMin(upper, d3dMax(lower, f));
}

bool isEvenFloat(float f) {
    return (static_cast<int>(f) & 1) == 0;
}

std::uint32_t fxpCeil(std::uint32_t x) {
    return (x & kFractionMask) ? (x & kIntegerMask) + kOne : x;
}
std::uint32_t fxpFloor(std::uint32_t x) {
    return x & kIntegerMask;
}

// Clears the most significant set bit of a value below 2^8 (the reference's RemoveMSB).
int removeMsb(int value) {
    if (value <= 0) return 0;
    const unsigned msb = std::bit_floor(static_cast<unsigned>(value));
    return static_cast<int>(static_cast<unsigned>(value) & ~msb);
}

}  // namespace

std::uint32_t floatToFixed16(float input) {
    // Unsigned 15.16 conversion with round-to-nearest-even, NaN and negatives to 0.
    constexpr int kMantissaBits = 23;
    constexpr std::int32_t kBias = 127;
    constexpr std::int32_t kHidden = 1 << kMantissaBits;
    constexpr std::int32_t kMantissaMask = kHidden - 1;
    constexpr std::int32_t kMaxPositiveBits = (kBias + 15) << kMantissaBits;  // 32768.0f
    const std::int32_t bits = std::bit_cast<std::int32_t>(input);
    const std::int32_t exponent = ((bits & 0x7f800000) >> kMantissaBits) - kBias;
    const bool negative = (bits & std::int32_t(0x80000000u)) != 0;
    if (exponent == kBias + 1 && (bits & kMantissaMask)) return 0;  // NaN
    if (!negative && bits >= kMaxPositiveBits) return 0xffffffffu;
    if (negative) return 0;
    if (exponent < -kFractionBits - 1) return 0;
    std::int32_t out = (bits & kMantissaMask) | kHidden;
    const std::int32_t extraBits = kMantissaBits - kFractionBits - exponent;
    if (extraBits >= 0) {
        const std::int32_t lsb = 1 << extraBits;
        const std::int32_t half = lsb >> 1;
        if ((out & lsb) || (out & (lsb - 1)) > half) out += half;
        out >>= extraBits;
    } else {
        out <<= -extraBits;
    }
    return static_cast<std::uint32_t>(out);
}

float fixedToFloat16(std::uint32_t x) {
    return static_cast<float>(x >> kFractionBits) +
           static_cast<float>(x & kFractionMask) / static_cast<float>(1 << kFractionBits);
}

struct D3D11Tessellator::QuadSetup {
    std::uint32_t outside[4]{}, inside[2]{};
    Parity outsideParity[4]{}, insideParity[2]{};
    FactorContext outsideCtx[4]{}, insideCtx[2]{};
    bool culled = false, minimum = false;
    int outsidePoints[4]{}, insidePoints[2]{};
    int insideBase = 0;
    int pointCount = 0;
};

struct D3D11Tessellator::TriSetup {
    std::uint32_t outside[3]{}, inside = 0;
    Parity outsideParity[3]{}, insideParity{};
    FactorContext outsideCtx[3]{}, insideCtx{};
    bool culled = false, minimum = false;
    int outsidePoints[3]{}, insidePoints = 0;
    int insideBase = 0;
    int pointCount = 0;
};

D3D11Tessellator::D3D11Tessellator(Partitioning partitioning, Winding winding)
    : partitioning_(partitioning), winding_(winding) {
    originalParity_ = partitioning == Partitioning::FractionalOdd ? Parity::Odd : Parity::Even;
    parity_ = originalParity_;
}

void D3D11Tessellator::factorRange(float& lower, float& upper) const {
    switch (partitioning_) {
        case Partitioning::Integer:
        case Partitioning::Pow2:  // the fixed-function stage treats pow2 as integer
            lower = kMinOddFactor;
            upper = kMaxEvenFactor;
            break;
        case Partitioning::FractionalEven:
            lower = kMinEvenFactor;
            upper = kMaxEvenFactor;
            break;
        case Partitioning::FractionalOdd:
            lower = kMinOddFactor;
            upper = kMaxOddFactor;
            break;
    }
}

int D3D11Tessellator::pointsForFactor(std::uint32_t f) const {
    if (odd()) return static_cast<int>((fxpCeil(kOneHalf + (f + 1) / 2) * 2) >> kFractionBits);
    return static_cast<int>(((fxpCeil((f + 1) / 2) * 2) >> kFractionBits) + 1);
}

void D3D11Tessellator::computeContext(std::uint32_t f, FactorContext& ctx) const {
    std::uint32_t half = (f + 1) / 2;
    // A factor of 1 in even mode behaves like odd: its half factor is 1/2.
    if (odd() || half == kOneHalf) half += kOneHalf;
    const std::uint32_t floorHalf = fxpFloor(half);
    const std::uint32_t ceilHalf = fxpCeil(half);
    ctx.halfFactorFraction = half - floorHalf;
    ctx.halfFactorPoints = static_cast<int>(ceilHalf >> kFractionBits);
    if (ceilHalf == floorHalf) {
        ctx.splitPointOnFloorHalf = ctx.halfFactorPoints + 1;  // never reached
    } else if (odd()) {
        ctx.splitPointOnFloorHalf =
            floorHalf == kOne
                ? 0
                : (removeMsb(static_cast<int>(floorHalf >> kFractionBits) - 1) << 1) + 1;
    } else {
        ctx.splitPointOnFloorHalf =
            (removeMsb(static_cast<int>(floorHalf >> kFractionBits)) << 1) + 1;
    }
    int floorSegments = static_cast<int>((floorHalf * 2) >> kFractionBits);
    int ceilSegments = static_cast<int>((ceilHalf * 2) >> kFractionBits);
    if (odd()) {
        floorSegments -= 1;
        ceilSegments -= 1;
    }
    ctx.invSegmentsOnFloor = kReciprocal[floorSegments];
    ctx.invSegmentsOnCeil = kReciprocal[ceilSegments];
}

std::uint32_t D3D11Tessellator::placePoint(const FactorContext& ctx, int point) const {
    bool flip = false;
    if (point >= ctx.halfFactorPoints) {
        point = (ctx.halfFactorPoints << 1) - point;
        if (odd()) point -= 1;
        flip = true;
    }
    // 16-bit fixed math cannot reach 0.5 exactly, so the midpoint is special.
    if (point == ctx.halfFactorPoints) return kOneHalf;
    const std::uint32_t onCeil = static_cast<std::uint32_t>(point);
    std::uint32_t onFloor = onCeil;
    if (point > ctx.splitPointOnFloorHalf) onFloor -= 1;
    const std::uint32_t floorLocation = onFloor * ctx.invSegmentsOnFloor;
    const std::uint32_t ceilLocation = onCeil * ctx.invSegmentsOnCeil;
    std::uint32_t location =
        floorLocation * (kOne - ctx.halfFactorFraction) + ceilLocation * ctx.halfFactorFraction;
    location = (location + kOneHalf) >> kFractionBits;
    return flip ? kOne - location : location;
}

void D3D11Tessellator::definePoint(std::uint32_t u, std::uint32_t v, int offset) {
    out_->points[static_cast<std::size_t>(offset)] = {fixedToFloat16(u), fixedToFloat16(v)};
}

int D3D11Tessellator::remap(int index) const {
    if (usingWrapPatch_) {
        if (index >= wrap_.outsideBase) {
            return index == wrap_.outsideBad ? wrap_.outsideReplacement
                                             : index + wrap_.outsideDelta;
        }
        return index == wrap_.insideBad ? wrap_.insideReplacement : index + wrap_.insideDelta;
    }
    if (usingInvertPatch_) {
        if (index >= invert_.base) {
            return index == invert_.cornerBad ? invert_.cornerReplacement
                                              : invert_.inversionEnd - index;
        }
        if (index == invert_.cornerBad) return invert_.cornerReplacement;
    }
    return index;
}

void D3D11Tessellator::defineTriangle(int i0, int i1, int i2) {
    auto& idx = out_->indices;
    idx.push_back(static_cast<std::uint32_t>(remap(i0)));
    if (winding_ == Winding::Clockwise) {
        idx.push_back(static_cast<std::uint32_t>(remap(i1)));
        idx.push_back(static_cast<std::uint32_t>(remap(i2)));
    } else {
        idx.push_back(static_cast<std::uint32_t>(remap(i2)));
        idx.push_back(static_cast<std::uint32_t>(remap(i1)));
    }
}

// ---------------------------------------------------------------------------------------------
// Quad domain

void D3D11Tessellator::tessellateQuad(const QuadTessFactors& factors, Tessellation& out) {
    out.clear();
    out_ = &out;
    QuadSetup s;
    quadProcess(factors, s);
    if (s.culled) {
        out.culled = true;
        return;
    }
    if (s.minimum) {
        out.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        defineTriangle(0, 1, 3);
        defineTriangle(1, 2, 3);
        return;
    }
    out.points.resize(static_cast<std::size_t>(s.pointCount));
    quadPoints(s);
    quadConnectivity(s);
}

void D3D11Tessellator::quadProcess(const QuadTessFactors& f, QuadSetup& s) {
    parity_ = originalParity_;
    for (float e : f.edge) {
        if (!(e > 0)) {  // NaN culls too
            s.culled = true;
            return;
        }
    }
    float lower = 0, upper = 0;
    factorRange(lower, upper);
    float outside[4];
    for (int e = 0; e < 4; ++e) {
        outside[e] = clampFactor(f.edge[e], lower, upper);
        if (integerPartitioning()) outside[e] = std::ceil(outside[e]);
    }
    if (partitioning_ == Partitioning::FractionalOdd) {
        // If any factor ends up above 1 in fixed point, force a picture frame inside.
        const float threshold = kMinOddFactor + kFixedEpsilon / 2;
        bool frame = f.inside[0] > threshold || f.inside[1] > threshold;
        for (float e : outside) frame = frame || e > threshold;
        if (frame) lower = kMinOddFactor + kFixedEpsilon;
    }
    float inside[2];
    for (int a = 0; a < 2; ++a) {
        inside[a] = clampFactor(f.inside[a], lower, upper);  // NaN maps to lower
        if (integerPartitioning()) inside[a] = std::ceil(inside[a]);
    }
    for (int e = 0; e < 4; ++e) {
        s.outsideParity[e] = integerPartitioning()
                                 ? (isEvenFloat(outside[e]) ? Parity::Even : Parity::Odd)
                                 : originalParity_;
        s.outside[e] = floatToFixed16(outside[e]);
    }
    for (int a = 0; a < 2; ++a) {
        s.insideParity[a] =
            integerPartitioning()
                ? ((isEvenFloat(inside[a]) || inside[a] == 1.0f) ? Parity::Even : Parity::Odd)
                : originalParity_;
        s.inside[a] = floatToFixed16(inside[a]);
    }
    if (integerPartitioning() || odd()) {
        bool allOne = s.inside[0] == kOne && s.inside[1] == kOne;
        for (std::uint32_t e : s.outside) allOne = allOne && e == kOne;
        if (allOne) {
            s.minimum = true;
            return;
        }
    }
    for (int e = 0; e < 4; ++e) {
        parity_ = s.outsideParity[e];
        computeContext(s.outside[e], s.outsideCtx[e]);
        s.outsidePoints[e] = pointsForFactor(s.outside[e]);
        s.pointCount += s.outsidePoints[e];
    }
    s.pointCount -= 4;
    for (int a = 0; a < 2; ++a) {
        parity_ = s.insideParity[a];
        computeContext(s.inside[a], s.insideCtx[a]);
        const int minimum = s.insideParity[a] == Parity::Odd ? 4 : 3;
        // max() allows degenerate transition regions when the inside factor is 1.
        s.insidePoints[a] = std::max(minimum, pointsForFactor(s.inside[a]));
    }
    s.insideBase = s.pointCount;
    s.pointCount += (s.insidePoints[0] - 2) * (s.insidePoints[1] - 2);
}

void D3D11Tessellator::quadPoints(const QuadSetup& s) {
    int offset = 0;
    // Outer ring, clockwise from the top-left corner.
    for (int edge = 0; edge < 4; ++edge) {
        const int end = s.outsidePoints[edge] - 1;
        parity_ = s.outsideParity[edge];
        for (int p = 0; p < end; ++p, ++offset) {
            const int q = (edge == 1 || edge == 2) ? p : end - p;
            const std::uint32_t param = placePoint(s.outsideCtx[edge], q);
            if (edge & 1)
                definePoint(param, edge == 3 ? kOne : 0, offset);
            else
                definePoint(edge == 2 ? kOne : 0, param, offset);
        }
    }
    // Inner rings, clockwise from (u=0, v=1), spiralling to the centre.
    const int rings = std::min(s.insidePoints[0], s.insidePoints[1]) >> 1;
    for (int ring = 1; ring < rings; ++ring) {
        const int start = ring;
        const int end[2] = {s.insidePoints[0] - 1 - start, s.insidePoints[1] - 1 - start};
        for (int edge = 0; edge < 4; ++edge) {
            const int perpAxis = edge & 1;
            const int alongAxis = (edge + 1) & 1;
            const int perpPoint = edge < 2 ? start : end[perpAxis];
            parity_ = s.insideParity[perpAxis];
            const std::uint32_t perp = placePoint(s.insideCtx[perpAxis], perpPoint);
            parity_ = s.insideParity[alongAxis];
            for (int p = start; p < end[alongAxis]; ++p, ++offset) {
                const int q = (edge == 1 || edge == 2) ? p : end[alongAxis] - (p - start);
                const std::uint32_t param = placePoint(s.insideCtx[alongAxis], q);
                if (alongAxis)
                    definePoint(perp, param, offset);
                else
                    definePoint(param, perp, offset);
            }
        }
    }
    // Even tessellation leaves a degenerate centre "ring": a row of points.
    if (s.insidePoints[0] > s.insidePoints[1] && s.insideParity[1] == Parity::Even) {
        const int end = s.insidePoints[0] - 1 - rings;
        parity_ = s.insideParity[0];
        for (int p = rings; p <= end; ++p, ++offset)
            definePoint(placePoint(s.insideCtx[0], p), kOneHalf, offset);
    } else if (s.insidePoints[1] >= s.insidePoints[0] && s.insideParity[0] == Parity::Even) {
        const int end = s.insidePoints[1] - 1 - rings;
        parity_ = s.insideParity[1];
        for (int p = end; p >= rings; --p, ++offset)
            definePoint(kOneHalf, placePoint(s.insideCtx[1], p), offset);
    }
    assert(offset == s.pointCount);
}

void D3D11Tessellator::quadConnectivity(const QuadSetup& s) {
    const int rowsToCenter[2] = {(s.insidePoints[0] + 1) >> 1, (s.insidePoints[1] + 1) >> 1};
    const int rings = std::min(rowsToCenter[0], rowsToCenter[1]);
    // Even partitioning leaves a degenerate row of points, an exception to the ring order.
    const int degenerateRing[2] = {s.insideParity[1] == Parity::Even ? rowsToCenter[1] - 1 : -1,
                                   s.insideParity[0] == Parity::Even ? rowsToCenter[0] - 1 : -1};
    const FactorContext* outsideCtx[4] = {&s.outsideCtx[0], &s.outsideCtx[1], &s.outsideCtx[2],
                                          &s.outsideCtx[3]};
    Parity outsideParity[4] = {s.outsideParity[0], s.outsideParity[1], s.outsideParity[2],
                               s.outsideParity[3]};
    int outsidePoints[4] = {s.outsidePoints[0], s.outsidePoints[1], s.outsidePoints[2],
                            s.outsidePoints[3]};
    int insideBase = s.insideBase;
    int outsideBase = 0;
    for (int ring = 1; ring < rings; ++ring) {
        const int insideEdgePoints[2] = {s.insidePoints[0] - 2 * ring,
                                         s.insidePoints[1] - 2 * ring};
        const int edge0InsideBase = insideBase;
        const int edge0OutsideBase = outsideBase;
        for (int edge = 0; edge < 4; ++edge) {
            const int axis = (edge + 1) & 1;
            int stitchInside = insideBase;
            int stitchOutside = outsideBase;
            if (edge == 3) {
                // Stitching sees two increasing rows although the ring wraps to its start.
                if (ring == degenerateRing[axis]) {
                    invert_.base = insideBase + 1;
                    invert_.cornerBad = outsideBase + outsidePoints[edge] - 1;
                    invert_.cornerReplacement = edge0OutsideBase;
                    invert_.inversionEnd = (invert_.base << 1) - 1;
                    stitchInside = invert_.base;
                    usingInvertPatch_ = true;
                } else {
                    wrap_.insideDelta = insideBase;
                    wrap_.insideBad = insideEdgePoints[axis] - 1;
                    wrap_.insideReplacement = edge0InsideBase;
                    wrap_.outsideBase = wrap_.insideBad + 1;
                    wrap_.outsideDelta = outsideBase - wrap_.outsideBase;
                    wrap_.outsideBad = wrap_.outsideBase + outsidePoints[edge] - 1;
                    wrap_.outsideReplacement = edge0OutsideBase;
                    stitchInside = 0;
                    stitchOutside = wrap_.outsideBase;
                    usingWrapPatch_ = true;
                }
            } else if (edge == 2 && ring == degenerateRing[axis]) {
                invert_.base = insideBase;
                invert_.cornerBad = -1;
                invert_.cornerReplacement = -1;
                invert_.inversionEnd = invert_.base << 1;
                stitchInside = invert_.base;
                usingInvertPatch_ = true;
            }
            if (ring == 1) {
                stitchTransition(stitchInside, s.insideCtx[axis].halfFactorPoints,
                                 s.insideParity[axis], stitchOutside,
                                 outsideCtx[edge]->halfFactorPoints, outsideParity[edge]);
            } else {
                stitchRegular(true, Diagonals::Mirrored, insideEdgePoints[axis], stitchInside,
                              stitchOutside);
            }
            usingWrapPatch_ = false;
            usingInvertPatch_ = false;
            outsideBase += outsidePoints[edge] - 1;
            if (edge == 2 && ring == degenerateRing[axis])
                insideBase -= insideEdgePoints[axis] - 1;
            else
                insideBase += insideEdgePoints[axis] - 1;
            outsidePoints[edge] = insideEdgePoints[axis];
        }
        if (ring == 1) {
            for (int edge = 0; edge < 4; ++edge) {
                outsideCtx[edge] = &s.insideCtx[edge & 1];
                outsideParity[edge] = s.insideParity[edge & 1];
            }
        }
    }
    // Centre: a strip of quads when the shorter axis is odd.
    if (s.insidePoints[0] > s.insidePoints[1] && s.insideParity[1] == Parity::Odd) {
        const int quads = (((s.insidePoints[0] >> 1) - (s.insidePoints[1] >> 1)) << 1) +
                          (s.insideParity[0] == Parity::Even ? 2 : 1);
        invert_.base = outsideBase + quads + 2;
        invert_.cornerBad = invert_.base;
        invert_.cornerReplacement = outsideBase;
        invert_.inversionEnd = invert_.base + invert_.base + quads;
        usingInvertPatch_ = true;
        stitchRegular(false, Diagonals::InsideToOutside, quads + 1, invert_.base, outsideBase + 1);
        usingInvertPatch_ = false;
    } else if (s.insidePoints[1] >= s.insidePoints[0] && s.insideParity[0] == Parity::Odd) {
        const int quads = (((s.insidePoints[1] >> 1) - (s.insidePoints[0] >> 1)) << 1) +
                          (s.insideParity[1] == Parity::Even ? 2 : 1);
        invert_.base = outsideBase + quads + 1;
        invert_.cornerBad = -1;
        invert_.inversionEnd = invert_.base + invert_.base + quads;
        usingInvertPatch_ = true;
        const Diagonals diagonals = s.insideParity[1] == Parity::Even
                                        ? Diagonals::InsideToOutside
                                        : Diagonals::InsideToOutsideExceptMiddle;
        stitchRegular(false, diagonals, quads + 1, invert_.base, outsideBase);
        usingInvertPatch_ = false;
    }
}

// ---------------------------------------------------------------------------------------------
// Triangle domain

void D3D11Tessellator::tessellateTri(const TriTessFactors& factors, Tessellation& out) {
    out.clear();
    out_ = &out;
    TriSetup s;
    triProcess(factors, s);
    if (s.culled) {
        out.culled = true;
        return;
    }
    if (s.minimum) {
        out.points = {{0, 1}, {0, 0}, {1, 0}};
        defineTriangle(0, 1, 2);
        return;
    }
    out.points.resize(static_cast<std::size_t>(s.pointCount));
    triPoints(s);
    triConnectivity(s);
}

void D3D11Tessellator::triProcess(const TriTessFactors& f, TriSetup& s) {
    parity_ = originalParity_;
    for (float e : f.edge) {
        if (!(e > 0)) {
            s.culled = true;
            return;
        }
    }
    float lower = 0, upper = 0;
    factorRange(lower, upper);
    float outside[3];
    for (int e = 0; e < 3; ++e) {
        outside[e] = clampFactor(f.edge[e], lower, upper);
        if (integerPartitioning()) outside[e] = std::ceil(outside[e]);
    }
    if (partitioning_ == Partitioning::FractionalOdd) {
        const float threshold = kMinOddFactor + kFixedEpsilon / 2;
        bool frame = false;
        for (float e : outside) frame = frame || e > threshold;
        if (frame) lower = kMinOddFactor + kFixedEpsilon;
    }
    float inside = clampFactor(f.inside, lower, upper);
    if (integerPartitioning()) inside = std::ceil(inside);
    for (int e = 0; e < 3; ++e) {
        s.outsideParity[e] = integerPartitioning()
                                 ? (isEvenFloat(outside[e]) ? Parity::Even : Parity::Odd)
                                 : originalParity_;
        s.outside[e] = floatToFixed16(outside[e]);
    }
    s.insideParity = integerPartitioning()
                         ? ((isEvenFloat(inside) || inside == 1.0f) ? Parity::Even : Parity::Odd)
                         : originalParity_;
    s.inside = floatToFixed16(inside);
    if (integerPartitioning() || odd()) {
        bool allOne = s.inside == kOne;
        for (std::uint32_t e : s.outside) allOne = allOne && e == kOne;
        if (allOne) {
            s.minimum = true;
            return;
        }
    }
    for (int e = 0; e < 3; ++e) {
        parity_ = s.outsideParity[e];
        computeContext(s.outside[e], s.outsideCtx[e]);
        s.outsidePoints[e] = pointsForFactor(s.outside[e]);
        s.pointCount += s.outsidePoints[e];
    }
    s.pointCount -= 3;
    parity_ = s.insideParity;
    computeContext(s.inside, s.insideCtx);
    s.insidePoints = std::max(odd() ? 4 : 3, pointsForFactor(s.inside));
    s.insideBase = s.pointCount;
    const int interiorRings = (s.insidePoints >> 1) - 1;
    s.pointCount += odd() ? 3 * (interiorRings * (interiorRings + 1) - interiorRings)
                          : 3 * (interiorRings * (interiorRings + 1)) + 1;
}

void D3D11Tessellator::triPoints(const TriSetup& s) {
    int offset = 0;
    // Outer ring, clockwise from corner V (edge u=0 first).
    for (int edge = 0; edge < 3; ++edge) {
        const int end = s.outsidePoints[edge] - 1;
        parity_ = s.outsideParity[edge];
        for (int p = 0; p < end; ++p, ++offset) {
            const int q = (edge & 1) ? p : end - p;
            const std::uint32_t param = placePoint(s.outsideCtx[edge], q);
            if (edge == 0)
                definePoint(0, param, offset);
            else
                definePoint(param, edge == 2 ? kOne - param : 0, offset);
        }
    }
    parity_ = s.insideParity;
    const int rings = s.insidePoints >> 1;
    for (int ring = 1; ring < rings; ++ring) {
        const int start = ring;
        const int end = s.insidePoints - 1 - start;
        for (int edge = 0; edge < 3; ++edge) {
            // Maps the 1D ring position to its barycentric depth (times 2/3, rounded).
            std::uint32_t perp = placePoint(s.insideCtx, start) * kTwoThirds;
            perp = (perp + kOneHalf) >> kFractionBits;
            const std::uint32_t shift = (perp + 1) / 2u;
            for (int p = start; p < end; ++p, ++offset) {
                const int q = (edge & 1) ? p : end - (p - start);
                const std::uint32_t param = placePoint(s.insideCtx, q);
                switch (edge) {
                    case 0:
                        definePoint(perp, param - shift, offset);
                        break;
                    case 1:
                        definePoint(param - shift, perp, offset);
                        break;
                    default:
                        definePoint(param - shift, kOne - (param - shift) - perp, offset);
                        break;
                }
            }
        }
    }
    if (!odd()) definePoint(kOneThird, kOneThird, offset++);
    assert(offset == s.pointCount);
}

void D3D11Tessellator::triConnectivity(const TriSetup& s) {
    const int rings = (s.insidePoints + 1) >> 1;  // +1 so even includes the centre point
    const FactorContext* outsideCtx[3] = {&s.outsideCtx[0], &s.outsideCtx[1], &s.outsideCtx[2]};
    Parity outsideParity[3] = {s.outsideParity[0], s.outsideParity[1], s.outsideParity[2]};
    int outsidePoints[3] = {s.outsidePoints[0], s.outsidePoints[1], s.outsidePoints[2]};
    int insideBase = s.insideBase;
    int outsideBase = 0;
    for (int ring = 1; ring < rings; ++ring) {
        const int insideEdgePoints = s.insidePoints - 2 * ring;
        const int edge0InsideBase = insideBase;
        const int edge0OutsideBase = outsideBase;
        for (int edge = 0; edge < 3; ++edge) {
            int stitchInside = insideBase;
            int stitchOutside = outsideBase;
            if (edge == 2) {
                wrap_.insideDelta = insideBase;
                wrap_.insideBad = insideEdgePoints - 1;
                wrap_.insideReplacement = edge0InsideBase;
                wrap_.outsideBase = wrap_.insideBad + 1;
                wrap_.outsideDelta = outsideBase - wrap_.outsideBase;
                wrap_.outsideBad = wrap_.outsideBase + outsidePoints[edge] - 1;
                wrap_.outsideReplacement = edge0OutsideBase;
                usingWrapPatch_ = true;
                stitchInside = 0;
                stitchOutside = wrap_.outsideBase;
            }
            if (ring == 1) {
                stitchTransition(stitchInside, s.insideCtx.halfFactorPoints, s.insideParity,
                                 stitchOutside, outsideCtx[edge]->halfFactorPoints,
                                 outsideParity[edge]);
            } else {
                stitchRegular(true, Diagonals::Mirrored, insideEdgePoints, stitchInside,
                              stitchOutside);
            }
            usingWrapPatch_ = false;
            outsideBase += outsidePoints[edge] - 1;
            insideBase += insideEdgePoints - 1;
            outsidePoints[edge] = insideEdgePoints;
        }
        if (ring == 1) {
            for (int edge = 0; edge < 3; ++edge) {
                outsideCtx[edge] = &s.insideCtx;
                outsideParity[edge] = s.insideParity;
            }
        }
    }
    parity_ = s.insideParity;
    if (odd()) defineTriangle(outsideBase, outsideBase + 1, outsideBase + 2);
}

// ---------------------------------------------------------------------------------------------
// Stitching of two rows of points

void D3D11Tessellator::stitchRegular(bool trapezoid, Diagonals diagonals, int insidePoints,
                                     int inside, int outside) {
    if (trapezoid) {
        defineTriangle(outside, outside + 1, inside);
        ++outside;
    }
    int p = 0;
    switch (diagonals) {
        case Diagonals::InsideToOutside:
            for (p = 0; p < insidePoints - 1; ++p, ++inside, ++outside) {
                defineTriangle(inside, outside, outside + 1);
                defineTriangle(inside, outside + 1, inside + 1);
            }
            break;
        case Diagonals::InsideToOutsideExceptMiddle:  // odd tessellation only
            for (p = 0; p < insidePoints / 2 - 1; ++p, ++inside, ++outside) {
                defineTriangle(outside, outside + 1, inside);
                defineTriangle(inside, outside + 1, inside + 1);
            }
            defineTriangle(outside, inside + 1, inside);
            defineTriangle(outside, outside + 1, inside + 1);
            ++inside;
            ++outside;
            p += 2;
            for (; p < insidePoints; ++p, ++inside, ++outside) {
                defineTriangle(outside, outside + 1, inside);
                defineTriangle(inside, outside + 1, inside + 1);
            }
            break;
        case Diagonals::Mirrored:
            for (p = 0; p < insidePoints / 2; ++p, ++inside, ++outside) {
                defineTriangle(outside, inside + 1, inside);
                defineTriangle(outside, outside + 1, inside + 1);
            }
            for (; p < insidePoints - 1; ++p, ++inside, ++outside) {
                defineTriangle(inside, outside, outside + 1);
                defineTriangle(inside, outside + 1, inside + 1);
            }
            break;
    }
    if (trapezoid) defineTriangle(outside, outside + 1, inside);
}

void D3D11Tessellator::stitchTransition(int inside, int insideHalf, Parity insideParity,
                                        int outside, int outsideHalf, Parity outsideParity) {
    if (insideParity == Parity::Odd) insideHalf -= 1;
    if (outsideParity == Parity::Odd) outsideHalf -= 1;
    const int first = std::min(kLoopStart[insideHalf], kLoopStart[outsideHalf]);
    const int last = std::max(kLoopEnd[insideHalf], kLoopEnd[outsideHalf]);
    auto advanceOutside = [&] {
        defineTriangle(outside, outside + 1, inside);
        ++outside;
    };
    auto advanceInside = [&] {
        defineTriangle(inside, outside, inside + 1);
        ++inside;
    };
    // First half, walked in ruler-function order.
    if (kFinalPointPosition[0] < outsideHalf) advanceOutside();
    for (int i = first; i <= last; ++i) {
        if (kFinalPointPosition[i] < insideHalf) advanceInside();
        if (kFinalPointPosition[i] < outsideHalf) advanceOutside();
    }
    if (insideParity != outsideParity || insideParity == Parity::Odd) {
        if (insideParity == outsideParity) {  // quad in the middle
            defineTriangle(inside, outside, inside + 1);
            defineTriangle(inside + 1, outside, outside + 1);
            ++inside;
            ++outside;
        } else if (insideParity == Parity::Even) {  // triangle pointing inside
            defineTriangle(inside, outside, outside + 1);
            ++outside;
        } else {  // triangle pointing outside
            defineTriangle(inside, outside, inside + 1);
            ++inside;
        }
    }
    // Second half, mirrored.
    for (int i = last; i >= first; --i) {
        if (kFinalPointPosition[i] < outsideHalf) advanceOutside();
        if (kFinalPointPosition[i] < insideHalf) advanceInside();
    }
    if (kFinalPointPosition[0] < outsideHalf) advanceOutside();
}

}  // namespace patchsim
