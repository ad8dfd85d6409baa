#pragma once
// The D3D11 fixed-function tessellator (TS).
//
// Representation
// --------------
// The tessellator works in 16.16 unsigned fixed point, exactly as the D3D11 reference does, so
// every domain coordinate it emits is a multiple of 2^-16 and converts to float without rounding. A
// tessellation factor is first clamped to the range of its partitioning mode, then (integer and
// pow2) rounded up, then converted to fixed point. Per factor a small "context" is derived: how
// many points lie on half of the edge, the fraction of the half factor, the reciprocals of the
// segment counts on the floor and ceiling factors, and the point at which the floor factor splits.
// Points are then placed on half an edge and mirrored (1 - x, computed in fixed point), which is
// why the two patches that share an edge produce bitwise-identical edge parameters.
//
// Output is a point list (u,v) and a triangle index list. Quad domains are produced as an outer
// ring per edge (u=0, v=0, u=1, v=1 in D3D order), inner rings spiralling to the centre, and a
// degenerate centre row or strip; triangle domains as three-sided rings. Rings are stitched with
// the ruler-function transition table of the reference, so triangle order, index values and
// winding are those of the D3D11 reference tessellator.
//
// Triangle domains use barycentric (u, v) with w = 1 - u - v; edge 0 is u = 0, edge 1 is v = 0,
// edge 2 is w = 0.

#include <cstdint>
#include <vector>

#include "core/tessellation_modes.h"

namespace patchsim {

enum class Winding : std::uint8_t { Clockwise, CounterClockwise };

struct DomainPoint {
    float u = 0.0f;
    float v = 0.0f;
};

// D3D11 order: edge[0] is u=0, edge[1] is v=0, edge[2] is u=1, edge[3] is v=1.
struct QuadTessFactors {
    float edge[4] = {1, 1, 1, 1};
    float inside[2] = {1, 1};  // along u, along v
};

// D3D11 order: edge[0] is u=0, edge[1] is v=0, edge[2] is w=0.
struct TriTessFactors {
    float edge[3] = {1, 1, 1};
    float inside = 1;
};

struct Tessellation {
    std::vector<DomainPoint> points;
    std::vector<std::uint32_t> indices;  // three per triangle
    bool culled = false;

    std::size_t triangleCount() const { return indices.size() / 3; }
    void clear() {
        points.clear();
        indices.clear();
        culled = false;
    }
};

// One tessellator per thread; it keeps no state between calls other than its mode, so the same
// object can tessellate any number of patches. Output vectors are reused (cleared, not freed).
class D3D11Tessellator {
  public:
    explicit D3D11Tessellator(Partitioning partitioning, Winding winding = Winding::Clockwise);

    void tessellateQuad(const QuadTessFactors& factors, Tessellation& out);
    void tessellateTri(const TriTessFactors& factors, Tessellation& out);

    Partitioning partitioning() const { return partitioning_; }

    // Public for tests: the fixed-point per-factor context of the reference.
    struct FactorContext {
        std::uint32_t invSegmentsOnFloor = 0;
        std::uint32_t invSegmentsOnCeil = 0;
        std::uint32_t halfFactorFraction = 0;
        int halfFactorPoints = 0;
        int splitPointOnFloorHalf = 0;
    };

  private:
    enum class Parity : std::uint8_t { Even, Odd };
    struct QuadSetup;
    struct TriSetup;
    // Index remapping used while stitching the last edge of a ring (wrap-around) and the
    // degenerate centre rows of even quad tessellations.
    struct WrapPatch {
        int insideDelta = 0, insideBad = 0, insideReplacement = 0;
        int outsideBase = 0, outsideDelta = 0, outsideBad = 0, outsideReplacement = 0;
    };
    struct InvertPatch {
        int base = 0, cornerBad = -1, cornerReplacement = -1, inversionEnd = 0;
    };
    enum class Diagonals : std::uint8_t { InsideToOutside, InsideToOutsideExceptMiddle, Mirrored };

    bool integerPartitioning() const {
        return partitioning_ == Partitioning::Integer || partitioning_ == Partitioning::Pow2;
    }
    bool odd() const { return parity_ == Parity::Odd; }
    void factorRange(float& lower, float& upper) const;

    void computeContext(std::uint32_t fxpFactor, FactorContext& ctx) const;
    int pointsForFactor(std::uint32_t fxpFactor) const;
    std::uint32_t placePoint(const FactorContext& ctx, int point) const;

    void definePoint(std::uint32_t u, std::uint32_t v, int offset);
    void defineTriangle(int i0, int i1, int i2);  // given clockwise
    int remap(int index) const;

    void quadProcess(const QuadTessFactors& f, QuadSetup& s);
    void quadPoints(const QuadSetup& s);
    void quadConnectivity(const QuadSetup& s);
    void triProcess(const TriTessFactors& f, TriSetup& s);
    void triPoints(const TriSetup& s);
    void triConnectivity(const TriSetup& s);

    void stitchRegular(bool trapezoid, Diagonals diagonals, int insidePoints, int insideBase,
                       int outsideBase);
    void stitchTransition(int insideBase, int insideHalfPoints, Parity insideParity,
                          int outsideBase, int outsideHalfPoints, Parity outsideParity);

    Partitioning partitioning_;
    Parity originalParity_ = Parity::Even;
    Parity parity_ = Parity::Even;
    Winding winding_;
    Tessellation* out_ = nullptr;
    bool usingWrapPatch_ = false;
    bool usingInvertPatch_ = false;
    WrapPatch wrap_;
    InvertPatch invert_;
};

// Bit-level helpers of the D3D11 reference, public for tests.
std::uint32_t floatToFixed16(float value);
float fixedToFloat16(std::uint32_t value);

}  // namespace patchsim
