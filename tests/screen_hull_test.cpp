#include "rasterizer/common/screen_hull.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace patchsim {
namespace {

TEST(ScreenHull, HullOfPointsDropsInteriorAndCollinearPoints) {
    ScreenHull hull;
    for (auto [x, y] : {std::pair{0.0, 0.0},
                        {2.0, 0.0},
                        {2.0, 2.0},
                        {0.0, 2.0},
                        {1.0, 1.0},
                        {1.0, 0.0},
                        {0.5, 1.5}})
        ASSERT_TRUE(hull.addBlurredPoint(x, y, 0.0));
    ASSERT_TRUE(hull.build(0.0));
    EXPECT_EQ(hull.cornerCount(), 4);
    EXPECT_DOUBLE_EQ(hull.area(), 4.0);
    EXPECT_TRUE(hull.contains(Vec2(1.0f, 1.0f)));
    EXPECT_TRUE(hull.contains(Vec2(2.0f, 2.0f)));  // on a corner
    EXPECT_FALSE(hull.contains(Vec2(2.01f, 1.0f)));
    EXPECT_DOUBLE_EQ(hull.lower(0), 0.0);
    EXPECT_DOUBLE_EQ(hull.upper(1), 2.0);
}

TEST(ScreenHull, TheMarginPushesEveryEdgeOut) {
    ScreenHull hull;
    for (auto [x, y] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}})
        hull.addBlurredPoint(x, y, 0.0);
    ASSERT_TRUE(hull.build(0.1));
    EXPECT_TRUE(hull.contains(Vec2(0.55f, 0.55f)));  // 0.07 beyond the hypotenuse
    EXPECT_FALSE(hull.contains(Vec2(0.6f, 0.6f)));   // 0.14 beyond
    EXPECT_TRUE(hull.contains(Vec2(-0.09f, 0.5f)));
    EXPECT_FALSE(hull.contains(Vec2(-0.11f, 0.5f)));
}

TEST(ScreenHull, ABlurredPointGoesInAsItsSquare) {
    ScreenHull hull;
    hull.addBlurredPoint(1.0, 2.0, 0.5);
    ASSERT_TRUE(hull.build(0.0));
    EXPECT_EQ(hull.cornerCount(), ScreenHull::kPointsPerBlurredPoint);
    EXPECT_DOUBLE_EQ(hull.area(), 1.0);
    EXPECT_TRUE(hull.contains(Vec2(1.49f, 2.49f)));  // the square's corner region
    EXPECT_FALSE(hull.contains(Vec2(1.51f, 2.0f)));
    EXPECT_DOUBLE_EQ(hull.lower(0), 0.5);
    EXPECT_DOUBLE_EQ(hull.upper(1), 2.5);
}

// The least-area rectangle of a rotated rectangle is that rectangle, not its screen box; of any
// point set it holds every point and its area lies between the hull's and the screen box's.
TEST(ScreenHull, TheOrientedBoxIsTheLeastAreaRectangleHoldingTheHull) {
    const double c = std::cos(0.5), s = std::sin(0.5);
    ScreenHull rotated;
    for (auto [u, v] : {std::pair{0.0, 0.0}, {4.0, 0.0}, {4.0, 1.0}, {0.0, 1.0}, {2.0, 0.5}})
        rotated.addBlurredPoint(u * c - v * s, u * s + v * c, 0.0);
    ASSERT_TRUE(rotated.buildOrientedBox(0.0));
    EXPECT_EQ(rotated.cornerCount(), 4);
    EXPECT_NEAR(rotated.area(), 4.0, 1e-12);
    const double boxArea =
        (rotated.upper(0) - rotated.lower(0)) * (rotated.upper(1) - rotated.lower(1));
    EXPECT_GT(boxArea, 8.0);

    std::mt19937 rng(5);
    std::uniform_real_distribution<double> coord(-3.0, 3.0), spread(0.0, 0.3);
    for (int trial = 0; trial < 200; ++trial) {
        ScreenHull hull, box;
        std::vector<std::pair<double, double>> points;
        for (int k = 0; k < 6; ++k) {
            const double x = coord(rng), y = 0.3 * coord(rng) + 0.5 * x, r = spread(rng);
            hull.addBlurredPoint(x, y, r);
            box.addBlurredPoint(x, y, r);
            for (double dx : {-r, r})
                for (double dy : {-r, r}) points.push_back({x + dx, y + dy});
        }
        ASSERT_TRUE(hull.build(0.0));
        ASSERT_TRUE(box.buildOrientedBox(1e-6));  // above the points' rounding to float
        EXPECT_GE(box.area(), hull.area() * (1 - 1e-12));
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (auto [x, y] : points) {
            lo[0] = std::min(lo[0], x), hi[0] = std::max(hi[0], x);
            lo[1] = std::min(lo[1], y), hi[1] = std::max(hi[1], y);
        }
        EXPECT_LE(box.area(), (hi[0] - lo[0]) * (hi[1] - lo[1]) * (1 + 1e-12))
            << "no larger than the points' screen box";
        for (auto [x, y] : points) EXPECT_TRUE(box.contains(Vec2(float(x), float(y)))) << trial;
    }
}

TEST(ScreenHull, APointOrASegmentHasNoHull) {
    ScreenHull point;
    point.addBlurredPoint(1.0, 1.0, 0.0);
    point.addBlurredPoint(1.0, 1.0, 0.0);
    EXPECT_FALSE(point.build(0.01));
    ScreenHull segment;
    for (int k = 0; k < 4; ++k) segment.addBlurredPoint(k, 2.0 * k, 0.0);
    EXPECT_FALSE(segment.build(0.01));
}

TEST(ScreenHull, RefusesPointsBeyondItsCapacity) {
    ScreenHull hull;
    for (int k = 0; k < ScreenHull::kMaxPoints / ScreenHull::kPointsPerBlurredPoint; ++k)
        EXPECT_TRUE(hull.addBlurredPoint(k, k * k, 0.5));
    EXPECT_FALSE(hull.addBlurredPoint(0.0, 0.0, 0.5));
    EXPECT_FALSE(hull.build(0.0)) << "a refused point leaves no hull";
}

// A number that is not finite never reaches the sort; the hull is refused and the caller keeps
// its box.
TEST(ScreenHull, RefusesNumbersThatAreNotFinite) {
    for (double bad : {double(NAN), double(INFINITY)}) {
        ScreenHull hull;
        hull.addBlurredPoint(0.0, 0.0, 0.1);
        hull.addBlurredPoint(1.0, 0.0, 0.1);
        EXPECT_FALSE(hull.addBlurredPoint(bad, 1.0, 0.0));
        EXPECT_FALSE(hull.build(0.01));
        ScreenHull spread;
        spread.addBlurredPoint(0.0, 0.0, 0.1);
        EXPECT_FALSE(spread.addBlurredPoint(1.0, 1.0, bad));
        EXPECT_FALSE(spread.build(0.01));
    }
}

// Walking a hull row by row finds every point inside it: random hulls, random points of them,
// each point's row range holds it.
TEST(ScreenHull, RowRangesHoldEveryPointOfRandomHulls) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int trial = 0; trial < 300; ++trial) {
        ScreenHull hull;
        double px[6], py[6];
        for (int k = 0; k < 6; ++k) {
            px[k] = 4 * u(rng) - 2, py[k] = 4 * u(rng) - 2;
            hull.addBlurredPoint(px[k], py[k], trial % 2 ? 0.0 : 0.3 * u(rng));
        }
        if (!hull.build(1e-4)) continue;
        for (int s = 0; s < 200; ++s) {
            double w[6], sum = 0, x = 0, y = 0;
            for (double& wk : w) sum += wk = -std::log(u(rng) + 1e-300);
            for (int k = 0; k < 6; ++k) x += w[k] / sum * px[k], y += w[k] / sum * py[k];
            ASSERT_TRUE(hull.contains(Vec2(float(x), float(y))));
            const double row = std::floor(y * 8) / 8;  // rows an eighth high
            double xa = 0, xb = 0;
            ASSERT_TRUE(hull.xRangeInStrip(row, row + 0.125, xa, xb)) << trial << " " << s;
            EXPECT_LE(xa, x) << trial << " " << s;
            EXPECT_GE(xb, x) << trial << " " << s;
        }
    }
}

TEST(ScreenHull, RectanglesSeparatedByAHullEdgeAreRejected) {
    ScreenHull hull;
    for (auto [x, y] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}})
        hull.addBlurredPoint(x, y, 0.0);
    ASSERT_TRUE(hull.build(0.0));
    EXPECT_TRUE(hull.overlapsRect(0.2, 0.2, 0.3, 0.3));
    EXPECT_TRUE(hull.overlapsRect(-1.0, -1.0, 2.0, 2.0));   // holds the hull
    EXPECT_FALSE(hull.overlapsRect(0.6, 0.6, 0.9, 0.9));    // inside the box, beyond the edge
    EXPECT_TRUE(hull.overlapsRect(0.5, 0.5, 0.9, 0.9));     // touches the hypotenuse
    EXPECT_FALSE(hull.overlapsRect(1.01, -0.5, 2.0, 0.5));  // right of the box
}

// A strip's x range holds every point of the hull in the strip, and no more than the margin
// beyond them.
TEST(ScreenHull, StripRangesHoldTheHullsPointsInTheStrip) {
    ScreenHull hull;
    for (auto [x, y] : {std::pair{0.0, 0.0}, {4.0, 1.0}, {1.0, 3.0}}) hull.addBlurredPoint(x, y, 0);
    const double margin = 0.01;
    ASSERT_TRUE(hull.build(margin));
    double xa = 0, xb = 0;
    EXPECT_FALSE(hull.xRangeInStrip(3.5, 4.0, xa, xb));
    EXPECT_FALSE(hull.xRangeInStrip(-1.0, -0.02, xa, xb));
    for (double y0 = -0.25; y0 < 3.25; y0 += 0.25) {
        ASSERT_TRUE(hull.xRangeInStrip(y0, y0 + 0.25, xa, xb)) << y0;
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i <= 400; ++i)
            for (int j = 0; j <= 50; ++j) {
                const double x = -0.5 + 5.0 * i / 400.0, y = y0 + 0.25 * j / 50.0;
                // Inside the hull itself (margin 0): the triangle's three edge functions.
                const bool inside =
                    4.0 * y - x >= 0 && 2.0 * (x - 4.0) + 3.0 * (y - 1.0) <= 0 && y - 3.0 * x <= 0;
                if (!inside) continue;
                lo = std::min(lo, x);
                hi = std::max(hi, x);
            }
        if (lo > hi) continue;
        EXPECT_LE(xa, lo) << y0;
        EXPECT_GE(xb, hi) << y0;
        // Beyond by at most the margin, plus the margin's reach along the shallowest edge (x
        // changes 4 per unit of y) and the grid's step.
        EXPECT_GT(xa, lo - 0.07) << y0;
        EXPECT_LT(xb, hi + 0.07) << y0;
    }
}

// The bound's claim: every image of a moving triangle, at any time and from any point of the
// lens's square [-R, R]^2 (which holds the disk), lies in the hull of its vertices' blur squares
// at the shutter's ends.
TEST(ScreenHull, HoldsEveryImageOfAMovingDefocusedTriangle) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float radius = 0.2f, focus = 4.0f;
    int inside = 0;
    for (int trial = 0; trial < 200; ++trial) {
        Vec3 ends[3][2];
        ScreenHull hull;
        for (auto& vertex : ends)
            for (Vec3& p : vertex) {
                p = Vec3(4.0f * u(rng) - 2.0f, 4.0f * u(rng) - 2.0f, -(1.0f + 9.0f * u(rng)));
                const float depth = -p.z;
                hull.addBlurredPoint(p.x / depth, p.y / depth,
                                     radius * std::abs(1.0f / depth - 1.0f / focus));
            }
        ASSERT_TRUE(hull.build(1e-6));
        for (int s = 0; s < 500; ++s) {
            const float t = u(rng);
            float b1 = u(rng), b2 = u(rng);
            if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
            const float w[3] = {1 - b1 - b2, b1, b2};
            Vec3 p(0.0f);
            for (int k = 0; k < 3; ++k) p += w[k] * ((1 - t) * ends[k][0] + t * ends[k][1]);
            const Vec2 lens(radius * (2.0f * u(rng) - 1.0f), radius * (2.0f * u(rng) - 1.0f));
            const float depth = -p.z;
            const Vec2 image = (Vec2(p.x, p.y) - lens) / depth + lens / focus;
            ASSERT_TRUE(hull.contains(image)) << trial << " " << s;
            ++inside;
        }
    }
    EXPECT_EQ(inside, 200 * 500);
}

}  // namespace
}  // namespace patchsim
