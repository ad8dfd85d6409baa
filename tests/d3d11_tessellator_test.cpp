#include "tessellator/d3d11_tessellator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>

#include "tessellator/hull_shader.h"

namespace patchsim {
namespace {

constexpr Partitioning kAllModes[] = {Partitioning::Integer, Partitioning::Pow2,
                                      Partitioning::FractionalOdd, Partitioning::FractionalEven};

// Segments per edge that a uniform factor gives after the HS and TS rules of each mode.
int segmentsFor(Partitioning mode, float f) {
    switch (mode) {
        case Partitioning::Integer:
            return int(std::ceil(std::clamp(f, 1.0f, 64.0f)));
        case Partitioning::Pow2: {
            int n = 1;
            while (float(n) < std::clamp(f, 1.0f, 64.0f)) n *= 2;
            return n;
        }
        case Partitioning::FractionalOdd: {
            int n = int(std::ceil(std::clamp(f, 1.0f, 63.0f)));
            return n % 2 ? n : n + 1;
        }
        case Partitioning::FractionalEven: {
            int n = int(std::ceil(std::clamp(f, 2.0f, 64.0f)));
            return n % 2 ? n + 1 : n;
        }
    }
    return 0;
}

Tessellation uniformQuad(Partitioning mode, float f) {
    const float edges[4] = {f, f, f, f};
    D3D11Tessellator ts(mode);
    Tessellation out;
    ts.tessellateQuad(processQuadFactors(edges, {mode, InsideReduction::Average}), out);
    return out;
}

Tessellation uniformTri(Partitioning mode, float f) {
    const float edges[3] = {f, f, f};
    D3D11Tessellator ts(mode);
    Tessellation out;
    ts.tessellateTri(processTriFactors(edges, {mode, InsideReduction::Average}), out);
    return out;
}

double signedArea(const Tessellation& t, std::size_t tri) {
    const DomainPoint a = t.points[t.indices[3 * tri]];
    const DomainPoint b = t.points[t.indices[3 * tri + 1]];
    const DomainPoint c = t.points[t.indices[3 * tri + 2]];
    return 0.5 *
           ((double(b.u) - a.u) * (double(c.v) - a.v) - (double(c.u) - a.u) * (double(b.v) - a.v));
}

// The triangles tile the domain: valid indices, one orientation, and areas that add up to the
// domain's (which, with one orientation, rules out overlaps). D3D11 emits zero-area triangles in
// degenerate transition regions (an inside factor of 1 against larger edges), so those are
// allowed only where `allowDegenerate`.
void expectTiling(const Tessellation& t, double domainArea, const std::string& what,
                  bool allowDegenerate = false) {
    ASSERT_FALSE(t.culled) << what;
    ASSERT_EQ(t.indices.size() % 3, 0u) << what;
    // Fixed-point rounding can leave a sliver (area below 2^-20) with either orientation.
    constexpr double kSliver = 1.0 / (1 << 20);
    double total = 0;
    for (std::size_t tri = 0; tri < t.triangleCount(); ++tri) {
        for (int k = 0; k < 3; ++k)
            ASSERT_LT(t.indices[3 * tri + std::size_t(k)], t.points.size()) << what;
        const double area = signedArea(t, tri);
        if (std::abs(area) < kSliver) {
            ASSERT_TRUE(allowDegenerate) << what << " triangle " << tri << " is degenerate";
        } else {
            ASSERT_GT(area, 0.0) << what << " triangle " << tri << " has the other winding";
        }
        total += area;
    }
    EXPECT_NEAR(total, domainArea, 1e-9) << what;
    // Every point is used, lies in the domain and is a multiple of 2^-16.
    std::vector<char> used(t.points.size());
    for (std::uint32_t i : t.indices) used[i] = 1;
    for (std::size_t i = 0; i < t.points.size(); ++i) {
        EXPECT_TRUE(used[i]) << what << " point " << i << " unused";
        const DomainPoint p = t.points[i];
        EXPECT_GE(p.u, 0.0f);
        EXPECT_GE(p.v, 0.0f);
        EXPECT_LE(p.u, 1.0f);
        EXPECT_LE(p.v, 1.0f);
        EXPECT_EQ(std::fmod(double(p.u) * 65536.0, 1.0), 0.0) << what;
        EXPECT_EQ(std::fmod(double(p.v) * 65536.0, 1.0), 0.0) << what;
    }
    // No point is emitted twice (except in degenerate transition regions).
    std::set<std::pair<float, float>> distinct;
    for (const DomainPoint& p : t.points) distinct.insert({p.u, p.v});
    if (!allowDegenerate) {
        EXPECT_EQ(distinct.size(), t.points.size()) << what;
    }
}

TEST(D3D11Tessellator, IntegerQuadCountsForEveryFactor) {
    for (int n = 1; n <= 64; ++n) {
        const Tessellation t = uniformQuad(Partitioning::Integer, float(n));
        EXPECT_EQ(t.points.size(), std::size_t((n + 1) * (n + 1))) << "factor " << n;
        EXPECT_EQ(t.triangleCount(), std::size_t(2 * n * n)) << "factor " << n;
        expectTiling(t, 1.0, "integer quad " + std::to_string(n));
    }
}

TEST(D3D11Tessellator, IntegerTriangleCountsForEveryFactor) {
    for (int n = 1; n <= 64; ++n) {
        const Tessellation t = uniformTri(Partitioning::Integer, float(n));
        const int h = n / 2;
        const std::size_t points = n % 2 == 0
                                       ? std::size_t(3 * h * (h + 1) + 1)
                                       : std::size_t(3 * n + 3 * ((n - 1) / 2) * ((n - 1) / 2));
        EXPECT_EQ(t.points.size(), points) << "factor " << n;
        EXPECT_EQ(t.triangleCount(), std::size_t(3 * n * n / 2)) << "factor " << n;
        expectTiling(t, 0.5, "integer triangle " + std::to_string(n));
    }
}

TEST(D3D11Tessellator, SpecExamples) {
    EXPECT_EQ(uniformTri(Partitioning::Integer, 4).points.size(), 19u);
    EXPECT_EQ(uniformTri(Partitioning::Integer, 4).triangleCount(), 24u);
    EXPECT_EQ(uniformTri(Partitioning::Integer, 63).points.size(), 3072u);
    EXPECT_EQ(uniformTri(Partitioning::Integer, 63).triangleCount(), 5953u);
    EXPECT_EQ(uniformQuad(Partitioning::Integer, 1).points.size(), 4u);
    EXPECT_EQ(uniformQuad(Partitioning::Integer, 1).triangleCount(), 2u);
}

TEST(D3D11Tessellator, EveryModeOverFractionalFactors) {
    for (Partitioning mode : kAllModes) {
        for (float f = 1.0f; f <= 64.0f; f += 0.25f) {
            const int n = segmentsFor(mode, f);
            const std::string what = std::string(partitioningName(mode)) + " " + std::to_string(f);
            const Tessellation q = uniformQuad(mode, f);
            EXPECT_EQ(q.points.size(), std::size_t((n + 1) * (n + 1))) << what;
            EXPECT_EQ(q.triangleCount(), std::size_t(2 * n * n)) << what;
            expectTiling(q, 1.0, "quad " + what);
            const Tessellation t = uniformTri(mode, f);
            EXPECT_EQ(t.triangleCount(), std::size_t(3 * n * n / 2)) << what;
            expectTiling(t, 0.5, "triangle " + what);
        }
    }
}

TEST(D3D11Tessellator, FractionalPointsMoveContinuouslyWithTheFactor) {
    // Fractional partitioning: a small change of factor moves points a little, never jumps.
    for (Partitioning mode : {Partitioning::FractionalOdd, Partitioning::FractionalEven}) {
        const Tessellation a = uniformQuad(mode, 5.20f);
        const Tessellation b = uniformQuad(mode, 5.21f);
        ASSERT_EQ(a.points.size(), b.points.size());
        for (std::size_t i = 0; i < a.points.size(); ++i) {
            EXPECT_NEAR(a.points[i].u, b.points[i].u, 0.01f);
            EXPECT_NEAR(a.points[i].v, b.points[i].v, 0.01f);
        }
    }
}

TEST(D3D11Tessellator, NonPositiveOrNaNEdgeFactorCullsThePatch) {
    const float bad[] = {0.0f, -0.0f, -1.0f, -std::numeric_limits<float>::infinity(),
                         std::numeric_limits<float>::quiet_NaN()};
    for (Partitioning mode : kAllModes) {
        D3D11Tessellator ts(mode);
        Tessellation out;
        for (float b : bad) {
            for (int edge = 0; edge < 4; ++edge) {
                QuadTessFactors q;
                for (float& e : q.edge) e = 5;
                q.inside[0] = q.inside[1] = 5;
                q.edge[edge] = b;
                ts.tessellateQuad(q, out);
                EXPECT_TRUE(out.culled) << partitioningName(mode) << " edge " << edge << " = " << b;
                EXPECT_TRUE(out.points.empty());
                EXPECT_TRUE(out.indices.empty());
            }
            for (int edge = 0; edge < 3; ++edge) {
                TriTessFactors t;
                for (float& e : t.edge) e = 5;
                t.inside = 5;
                t.edge[edge] = b;
                ts.tessellateTri(t, out);
                EXPECT_TRUE(out.culled);
            }
        }
    }
}

TEST(D3D11Tessellator, InsideFactorsAreClampedAndNeverCull) {
    for (Partitioning mode : kAllModes) {
        D3D11Tessellator ts(mode);
        Tessellation out;
        for (float inside : {0.0f, -3.0f, std::numeric_limits<float>::quiet_NaN(), 1e-7f,
                             std::numeric_limits<float>::infinity(), 1000.0f}) {
            QuadTessFactors q;
            for (float& e : q.edge) e = 4;
            q.inside[0] = q.inside[1] = inside;
            ts.tessellateQuad(q, out);
            EXPECT_FALSE(out.culled) << partitioningName(mode) << " inside " << inside;
            expectTiling(out, 1.0, std::string("quad inside ") + std::to_string(inside), true);
            TriTessFactors t;
            for (float& e : t.edge) e = 4;
            t.inside = inside;
            ts.tessellateTri(t, out);
            EXPECT_FALSE(out.culled);
            expectTiling(out, 0.5, std::string("tri inside ") + std::to_string(inside), true);
        }
    }
}

TEST(D3D11Tessellator, HugeAndTinyEdgeFactorsClampToTheModeRange) {
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(uniformQuad(Partitioning::Integer, inf).triangleCount(), 2u * 64 * 64);
    EXPECT_EQ(uniformQuad(Partitioning::FractionalOdd, inf).triangleCount(), 2u * 63 * 63);
    EXPECT_EQ(uniformQuad(Partitioning::FractionalEven, 1e-7f).triangleCount(), 2u * 2 * 2);
    EXPECT_EQ(uniformQuad(Partitioning::Integer, 1e-7f).triangleCount(), 2u);
    EXPECT_EQ(uniformTri(Partitioning::Integer, 1e-7f).triangleCount(), 1u);
}

// The parameters of the points on one edge of a quad, from its start corner.
std::vector<float> quadEdgeParams(const Tessellation& t, int d3dEdge) {
    std::vector<float> params;
    for (const DomainPoint& p : t.points) {
        switch (d3dEdge) {
            case 0:
                if (p.u == 0) params.push_back(p.v);
                break;
            case 1:
                if (p.v == 0) params.push_back(p.u);
                break;
            case 2:
                if (p.u == 1) params.push_back(p.v);
                break;
            case 3:
                if (p.v == 1) params.push_back(p.u);
                break;
        }
    }
    std::sort(params.begin(), params.end());
    return params;
}

TEST(D3D11Tessellator, EdgePointsDependOnlyOnTheEdgeFactorAndMirrorExactly) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> factor(1.0f, 64.0f);
    for (Partitioning mode : kAllModes) {
        D3D11Tessellator ts(mode);
        for (int trial = 0; trial < 200; ++trial) {
            const float shared = factor(rng);
            QuadTessFactors a, b;
            for (float& e : a.edge) e = factor(rng);
            for (float& e : b.edge) e = factor(rng);
            a.inside[0] = factor(rng);
            a.inside[1] = factor(rng);
            b.inside[0] = factor(rng);
            b.inside[1] = factor(rng);
            a.edge[2] = shared;  // patch A's u=1 edge is patch B's u=0 edge
            b.edge[0] = shared;
            Tessellation ta, tb;
            ts.tessellateQuad(a, ta);
            ts.tessellateQuad(b, tb);
            const std::vector<float> pa = quadEdgeParams(ta, 2), pb = quadEdgeParams(tb, 0);
            ASSERT_EQ(pa, pb) << partitioningName(mode) << " factor " << shared;
            // Read from the other end, the points are the exact complements.
            for (std::size_t i = 0; i < pa.size(); ++i)
                EXPECT_EQ(1.0f - pa[i], pa[pa.size() - 1 - i]);
            expectTiling(ta, 1.0, "random quad", true);
            // A triangle with the same edge factor puts the same points on its v=0 edge.
            TriTessFactors t;
            t.edge[0] = factor(rng);
            t.edge[1] = shared;
            t.edge[2] = factor(rng);
            t.inside = factor(rng);
            Tessellation tt;
            ts.tessellateTri(t, tt);
            std::vector<float> pt;
            for (const DomainPoint& p : tt.points)
                if (p.v == 0) pt.push_back(p.u);
            std::sort(pt.begin(), pt.end());
            EXPECT_EQ(pt, pa);
            expectTiling(tt, 0.5, "random triangle", true);
        }
    }
}

TEST(D3D11Tessellator, WindingOptionReversesEveryTriangle) {
    D3D11Tessellator cw(Partitioning::Integer, Winding::Clockwise);
    D3D11Tessellator ccw(Partitioning::Integer, Winding::CounterClockwise);
    QuadTessFactors q;
    q.edge[0] = 3;
    q.edge[1] = 5;
    q.edge[2] = 7;
    q.edge[3] = 2;
    q.inside[0] = 4;
    q.inside[1] = 6;
    Tessellation a, b;
    cw.tessellateQuad(q, a);
    ccw.tessellateQuad(q, b);
    ASSERT_EQ(a.indices.size(), b.indices.size());
    for (std::size_t tri = 0; tri < a.triangleCount(); ++tri)
        EXPECT_EQ(signedArea(a, tri), -signedArea(b, tri));
}

TEST(D3D11Tessellator, FixedPointConversionMatchesTheReferenceRounding) {
    EXPECT_EQ(floatToFixed16(1.0f), 0x10000u);
    EXPECT_EQ(floatToFixed16(0.5f), 0x8000u);
    EXPECT_EQ(floatToFixed16(64.0f), 0x400000u);
    EXPECT_EQ(floatToFixed16(-2.0f), 0u);
    EXPECT_EQ(floatToFixed16(std::numeric_limits<float>::quiet_NaN()), 0u);
    // Round to nearest even at 2^-16: 1.5 * 2^-16 rounds up to 2, 2.5 * 2^-16 down to 2.
    EXPECT_EQ(floatToFixed16(1.5f / 65536.0f), 2u);
    EXPECT_EQ(floatToFixed16(2.5f / 65536.0f), 2u);
    EXPECT_EQ(fixedToFloat16(0x18000u), 1.5f);
}

}  // namespace
}  // namespace patchsim
