#include "tessellator/hull_shader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace patchsim {
namespace {

QuadTessFactors quad(Partitioning p, float a, float b, float c, float d,
                     InsideReduction r = InsideReduction::Average) {
    const float edges[4] = {a, b, c, d};
    return processQuadFactors(edges, {p, r});
}

TEST(HullShader, Pow2RoundsUpToAPowerOfTwo) {
    const QuadTessFactors f = quad(Partitioning::Pow2, 3, 5, 8, 33);
    EXPECT_EQ(f.edge[0], 4);
    EXPECT_EQ(f.edge[1], 8);
    EXPECT_EQ(f.edge[2], 8);
    EXPECT_EQ(f.edge[3], 64);
    EXPECT_EQ(quad(Partitioning::Pow2, 1e-7f, 1, 1, 1).edge[0], 1);
    EXPECT_EQ(quad(Partitioning::Pow2, 100, 1, 1, 1).edge[0], 64);
}

TEST(HullShader, IntegerRoundsUpAndClamps) {
    const QuadTessFactors f =
        quad(Partitioning::Integer, 1.2f, 63.01f, 1e-7f, std::numeric_limits<float>::infinity());
    EXPECT_EQ(f.edge[0], 2);
    EXPECT_EQ(f.edge[1], 64);
    EXPECT_EQ(f.edge[2], 1);
    EXPECT_EQ(f.edge[3], 64);
}

TEST(HullShader, FractionalRangesPerMode) {
    EXPECT_EQ(quad(Partitioning::FractionalOdd, 64, 1, 1, 1).edge[0], 63);
    EXPECT_EQ(quad(Partitioning::FractionalOdd, 0.5f, 1, 1, 1).edge[0], 1);
    EXPECT_EQ(quad(Partitioning::FractionalEven, 1, 2, 2, 2).edge[0], 2);
    EXPECT_EQ(quad(Partitioning::FractionalEven, 70, 2, 2, 2).edge[0], 64);
    EXPECT_EQ(quad(Partitioning::FractionalEven, 5.5f, 2, 2, 2).edge[0], 5.5f);
}

TEST(HullShader, InsideFactorsReduceTheOppositeEdges) {
    // Inside along u spans the v=0 and v=1 edges (D3D11 edges 1 and 3).
    const QuadTessFactors avg = quad(Partitioning::FractionalEven, 2, 4, 6, 8);
    EXPECT_EQ(avg.inside[0], 6);
    EXPECT_EQ(avg.inside[1], 4);
    const QuadTessFactors mx = quad(Partitioning::FractionalEven, 2, 4, 6, 8, InsideReduction::Max);
    EXPECT_EQ(mx.inside[0], 8);
    EXPECT_EQ(mx.inside[1], 6);
    const QuadTessFactors mn = quad(Partitioning::FractionalEven, 2, 4, 6, 8, InsideReduction::Min);
    EXPECT_EQ(mn.inside[0], 4);
    EXPECT_EQ(mn.inside[1], 2);
    const float tri[3] = {3, 6, 9};
    EXPECT_EQ(
        processTriFactors(tri, {Partitioning::FractionalEven, InsideReduction::Average}).inside, 6);
}

TEST(HullShader, CullingFactorsPassThrough) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_TRUE(std::isnan(quad(Partitioning::Integer, nan, 4, 4, 4).edge[0]));
    EXPECT_EQ(quad(Partitioning::Integer, -1, 4, 4, 4).edge[0], -1);
    EXPECT_EQ(quad(Partitioning::Integer, 0, 4, 4, 4).edge[0], 0);
}

TEST(HullShader, OddInsideFactorBelowThreeComesInToTheFrame) {
    // Integer factors 3,1,3,1: inside along u is avg(1,1)=1 (even: fine), along v avg(3,3)=3.
    const QuadTessFactors f = quad(Partitioning::FractionalOdd, 3, 1, 3, 1);
    EXPECT_GE(f.inside[0], 1.0f);
    EXPECT_EQ(f.inside[1], 3.0f);
    // The smaller odd axis is raised towards the other (up to 3) so the frame does not snap.
    EXPECT_EQ(f.inside[0], 3.0f);
}

}  // namespace
}  // namespace patchsim
