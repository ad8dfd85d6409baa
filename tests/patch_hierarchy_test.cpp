#include "rasterizer/patent/patch_hierarchy.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "core/scene_reader.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

// A moving grid of n x n quads (2 n^2 triangles) with random wobble, as the tessellator makes.
MovingMesh movingGrid(int n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.2f, 0.2f);
    MovingMesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const Vec3 p(float(i), float(j), -5.0f + u(rng));
            m.position0.push_back(p);
            m.position1.push_back(p + Vec3(1.5f + u(rng), u(rng), u(rng)));
            m.domain.push_back(Vec2(float(i) / float(n), float(j) / float(n)));
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::uint32_t a = std::uint32_t(j * (n + 1) + i);
            m.indices.insert(m.indices.end(), {a, a + 1, a + std::uint32_t(n) + 2});
            m.indices.insert(m.indices.end(),
                             {a, a + std::uint32_t(n) + 2, a + std::uint32_t(n) + 1});
        }
    return m;
}

bool contains(const Box3& outer, const Box3& inner) {
    return glm::all(glm::lessThanEqual(outer.lower, inner.lower)) &&
           glm::all(glm::greaterThanEqual(outer.upper, inner.upper));
}

TEST(PatchHierarchy, CompleteTreeOfLeavesHoldingEveryTriangleOnce) {
    const MovingMesh mesh = movingGrid(8, 1);  // 128 triangles
    for (int leafSize : {1, 2, 4, 8}) {
        std::vector<std::uint32_t> all(mesh.triangleCount());
        for (std::size_t k = 0; k < all.size(); ++k) all[k] = std::uint32_t(k);
        PatchHierarchy h;
        h.build(mesh, all.data(), all.size(), leafSize);
        EXPECT_EQ(h.nodeCount(), 2 * h.leafCount() - 1);
        EXPECT_LE(h.leafCount(), kMaxLeavesPerHierarchy);
        std::vector<std::uint32_t> seen;
        for (int leaf = 0; leaf < h.leafCount(); ++leaf) {
            std::size_t count;
            const std::uint32_t* tris = h.leafTriangles(leaf, count);
            if (h.leafCount() < kMaxLeavesPerHierarchy) {
                EXPECT_LE(count, std::size_t(leafSize));
            }
            seen.insert(seen.end(), tris, tris + count);
        }
        std::sort(seen.begin(), seen.end());
        EXPECT_EQ(seen, all) << "leaf size " << leafSize;
    }
}

// A leaf's vertex table names each corner's mesh vertex, lists each vertex once, and only those
// its triangles use; a grid's leaf shares corners, so it has fewer vertices than corners.
TEST(PatchHierarchy, LeafVerticesAreEachLeafsDistinctCorners) {
    const MovingMesh mesh = movingGrid(8, 1);  // 128 triangles
    for (int leafSize : {1, 4, 64}) {
        std::vector<std::uint32_t> all(mesh.triangleCount());
        for (std::size_t k = 0; k < all.size(); ++k) all[k] = std::uint32_t(k);
        PatchHierarchy h;
        h.build(mesh, all.data(), all.size(), leafSize);
        std::size_t shared = 0;
        for (int leaf = 0; leaf < h.leafCount(); ++leaf) {
            std::size_t count, vertexCount;
            const std::uint32_t* tris = h.leafTriangles(leaf, count);
            const std::uint32_t* vertices = h.leafVertices(leaf, vertexCount);
            const std::uint8_t* corners = h.leafCorners(leaf);
            std::vector<std::uint32_t> used;
            for (std::size_t k = 0; k < count; ++k)
                for (std::size_t c = 0; c < 3; ++c) {
                    ASSERT_LT(corners[3 * k + c], vertexCount) << "leaf " << leaf;
                    EXPECT_EQ(vertices[corners[3 * k + c]], mesh.indices[3 * tris[k] + c])
                        << "leaf " << leaf << " triangle " << k << " corner " << c;
                    used.push_back(mesh.indices[3 * tris[k] + c]);
                }
            std::sort(used.begin(), used.end());
            used.erase(std::unique(used.begin(), used.end()), used.end());
            std::vector<std::uint32_t> listed(vertices, vertices + vertexCount);
            std::sort(listed.begin(), listed.end());
            EXPECT_EQ(listed, used) << "leaf " << leaf;
            shared += 3 * count - vertexCount;
        }
        if (leafSize > 1) {
            EXPECT_GT(shared, 0u) << "leaf size " << leafSize;
        }
    }
}

// Every node's moving box holds its children's, and a leaf's holds its triangles at any time:
// a vertex blended to t lies in the box blended to t, bit for bit (no rounding can escape).
TEST(PatchHierarchy, MovingBoxesBoundTheirTrianglesAtEveryTime) {
    const MovingMesh mesh = movingGrid(6, 2);
    std::vector<std::uint32_t> all(mesh.triangleCount());
    for (std::size_t k = 0; k < all.size(); ++k) all[k] = std::uint32_t(k);
    PatchHierarchy h;
    h.build(mesh, all.data(), all.size(), 4);
    for (int node = 0; node < PatchHierarchy::firstLeaf(h.depth()); ++node)
        for (int child : {2 * node + 1, 2 * node + 2})
            if (!h.node(child).empty()) {
                EXPECT_TRUE(contains(h.node(node).bounds0, h.node(child).bounds0));
                EXPECT_TRUE(contains(h.node(node).bounds1, h.node(child).bounds1));
            }
    for (int leaf = 0; leaf < h.leafCount(); ++leaf) {
        std::size_t count;
        const std::uint32_t* tris = h.leafTriangles(leaf, count);
        const LBBox& box = h.node(PatchHierarchy::firstLeaf(h.depth()) + leaf);
        for (float t : {0.0f, 0.1f, 0.37f, 0.5f, 0.9999f, 1.0f}) {
            const Box3 at = box.at(t);
            for (std::size_t k = 0; k < count; ++k)
                for (int c = 0; c < 3; ++c) {
                    const Vec3 v = mesh.vertexAt(mesh.indices[3 * tris[k] + std::size_t(c)], t);
                    ASSERT_TRUE(glm::all(glm::lessThanEqual(at.lower, v)) &&
                                glm::all(glm::lessThanEqual(v, at.upper)))
                        << "leaf " << leaf << " t " << t;
                }
        }
    }
}

TEST(PatchHierarchy, LargePatchesSplitIntoGroupsByTheDomainGrid) {
    const MovingMesh mesh = movingGrid(16, 3);  // 512 triangles
    std::vector<std::uint32_t> order, begin;
    splitIntoGroups(mesh, 100, order, begin);
    ASSERT_EQ(begin.size(), 9u);  // 8 groups (a power of two) of at most 100
    for (std::size_t g = 0; g + 1 < begin.size(); ++g) EXPECT_LE(begin[g + 1] - begin[g], 100u);
    std::vector<std::uint32_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < sorted.size(); ++k) ASSERT_EQ(sorted[k], k);
    // Groups are compact in the domain: each group's centroids span at most half of u or v.
    for (std::size_t g = 0; g + 1 < begin.size(); ++g) {
        Vec2 lo(1e9f), hi(-1e9f);
        for (std::uint32_t k = begin[g]; k < begin[g + 1]; ++k) {
            const std::uint32_t* v = &mesh.indices[3 * std::size_t(order[k])];
            const Vec2 c = (mesh.domain[v[0]] + mesh.domain[v[1]] + mesh.domain[v[2]]) / 3.0f;
            lo = glm::min(lo, c);
            hi = glm::max(hi, c);
        }
        EXPECT_LE(std::min(hi.x - lo.x, hi.y - lo.y), 0.5f) << "group " << g;
    }
}

TEST(PatchHierarchy, BytesAreNodesAndLeafLists) {
    const MovingMesh mesh = movingGrid(4, 4);  // 32 triangles
    std::vector<std::uint32_t> all(32);
    for (std::size_t k = 0; k < all.size(); ++k) all[k] = std::uint32_t(k);
    PatchHierarchy h;
    h.build(mesh, all.data(), all.size(), 4);  // 8 leaves, 15 nodes
    EXPECT_EQ(h.depth(), 3);
    EXPECT_EQ(h.bytes(), 15 * sizeof(LBBox) + 32 * 2 + 9 * 2);
    EXPECT_EQ(h.levelOf(0), 0);
    EXPECT_EQ(h.levelOf(2), 1);
    EXPECT_EQ(h.levelOf(PatchHierarchy::firstLeaf(3)), 3);
    h.storeNodesIn(NumberFormat::fp16());  // 12 bounds of 16 bits a node
    EXPECT_EQ(h.bytes(), 15 * 24 + 32 * 2 + 9 * 2);
    h.storeNodesIn(NumberFormat::fixed(10, 6));
    EXPECT_EQ(h.bytes(), 15 * 24 + 32 * 2 + 9 * 2);
}

// Vertices (at either shutter end) outside their leaf's stored box.
int verticesOutsideTheirLeaf(const PatchHierarchy& h, const MovingMesh& mesh) {
    int outside = 0;
    for (int j = 0; j < h.leafCount(); ++j) {
        const LBBox& box = h.node(PatchHierarchy::firstLeaf(h.depth()) + j);
        std::size_t count = 0;
        const std::uint32_t* triangles = h.leafTriangles(j, count);
        for (std::size_t k = 0; k < count; ++k)
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t v =
                    mesh.indices[3 * std::size_t(triangles[k]) + std::size_t(c)];
                outside += !contains(box.bounds0, {mesh.position0[v], mesh.position0[v]});
                outside += !contains(box.bounds1, {mesh.position1[v], mesh.position1[v]});
            }
    }
    return outside;
}

// A narrower ray-triangle test (rasterizer.triangle_format) grows every leaf by the test's reach
// at its distance, and the interior nodes with them; fp32 changes nothing. The reach scales with
// the format's unit: about 2^13 times fp32's for fp16, 2^3 more again for bf16.
TEST(PatchHierarchy, ANarrowerTriangleTestGrowsEveryLeafByItsReach) {
    const MovingMesh mesh = movingGrid(8, 5);
    std::vector<std::uint32_t> all(128);
    for (std::size_t k = 0; k < all.size(); ++k) all[k] = std::uint32_t(k);
    PatchHierarchy exact;
    exact.build(mesh, all.data(), all.size(), 2);
    PatchHierarchy same = exact;
    same.growForTriangleTest(NumberFormat::fp32(), 0.5f);
    for (int i = 0; i < exact.nodeCount(); ++i) {
        EXPECT_EQ(same.node(i).bounds0.lower, exact.node(i).bounds0.lower);
        EXPECT_EQ(same.node(i).bounds1.upper, exact.node(i).bounds1.upper);
    }
    EXPECT_EQ(triangleTestReach(NumberFormat::fp32(), 10.0f), 0.0f);
    EXPECT_EQ(triangleTestReach(NumberFormat::fp16(), 10.0f), 4 * 0x1p-7f);  // ulp(10) = 2^-7
    EXPECT_EQ(triangleTestReach(NumberFormat::bf16(), 10.0f), 4 * 0x1p-4f);
    EXPECT_EQ(triangleTestReach(NumberFormat::fixed(16, 8), 3.0f), 64 * 0x1p-8f * 4);
    for (const NumberFormat format : {NumberFormat::fp16(), NumberFormat::fixed(16, 8)}) {
        PatchHierarchy grown = exact;
        grown.growForTriangleTest(format, 0.5f);
        const int first = PatchHierarchy::firstLeaf(exact.depth());
        for (int i = 0; i < exact.nodeCount(); ++i) {
            const Box3 &in = exact.node(i).bounds0, &out = grown.node(i).bounds0;
            ASSERT_TRUE(contains(out, in)) << formatName(format) << " node " << i;
            if (i < first) {
                EXPECT_TRUE(contains(out, grown.node(2 * i + 1).bounds0));
                EXPECT_TRUE(contains(out, grown.node(2 * i + 2).bounds0));
                continue;
            }
            const Vec3 far = glm::max(glm::abs(exact.node(i).bounds0.lower),
                                      glm::abs(exact.node(i).bounds0.upper));
            const Vec3 far1 = glm::max(glm::abs(exact.node(i).bounds1.lower),
                                       glm::abs(exact.node(i).bounds1.upper));
            const float distance = std::max(far.x + far.y + far.z, far1.x + far1.y + far1.z) + 0.5f;
            const float reach = triangleTestReach(format, distance);
            EXPECT_GT(reach, 0.0f);
            EXPECT_EQ(out.lower.x, in.lower.x - reach) << formatName(format) << " leaf " << i;
            EXPECT_EQ(out.upper.z, in.upper.z + reach) << formatName(format) << " leaf " << i;
        }
    }
}

// Issue 35: boxes stored in a narrower format, each bound rounded outward, hold the exact boxes
// and are the format's values; the naive variant (round to nearest) cuts vertices off their
// leaves, so samples that hit those corners would be lost.
TEST(PatchHierarchy, BoxesStoredInANarrowerFormatRoundOutward) {
    const MovingMesh mesh = movingGrid(8, 11);  // 128 triangles, coordinates up to 10
    std::vector<std::uint32_t> all(128);
    for (std::size_t k = 0; k < all.size(); ++k) all[k] = std::uint32_t(k);
    PatchHierarchy exact;
    exact.build(mesh, all.data(), all.size(), 2);
    for (const NumberFormat format : {NumberFormat::fp16(), NumberFormat::bf16(),
                                      NumberFormat::fixed(8, 4), NumberFormat::fixed(4, 8)}) {
        const std::string name = formatName(format);
        PatchHierarchy stored = exact;
        stored.storeNodesIn(format);
        EXPECT_EQ(stored.nodeFormat(), format);
        int widened = 0, unbounded = 0;
        for (int i = 0; i < exact.nodeCount(); ++i) {
            for (const auto& [outer, inner] :
                 {std::pair{stored.node(i).bounds0, exact.node(i).bounds0},
                  std::pair{stored.node(i).bounds1, exact.node(i).bounds1}}) {
                ASSERT_TRUE(contains(outer, inner)) << name << " node " << i;
                for (int a = 0; a < 3; ++a)
                    for (const float v : {outer.lower[a], outer.upper[a]}) {
                        if (std::abs(v) == std::numeric_limits<float>::max()) {
                            ++unbounded;
                            continue;
                        }
                        EXPECT_EQ(roundTo(v, format), v) << name;
                    }
                widened += outer.lower != inner.lower || outer.upper != inner.upper;
            }
        }
        EXPECT_GT(widened, 0) << name;
        EXPECT_EQ(verticesOutsideTheirLeaf(stored, mesh), 0) << name;
        // fixed4.8 holds [-8, 8): the grid's far side (up to 10) is out of range, so those bounds
        // open to infinity instead of saturating inward.
        EXPECT_EQ(unbounded > 0, format == NumberFormat::fixed(4, 8)) << name;

        PatchHierarchy naive = exact;
        naive.storeNodesIn(format, Rounding::Nearest);
        if (format.kind != NumberFormat::Kind::Fixed || format.integerBits > 4) {
            EXPECT_GT(verticesOutsideTheirLeaf(naive, mesh), 0) << name << " rounded to nearest";
        }
    }
    PatchHierarchy same = exact;
    same.storeNodesIn(NumberFormat::fp32());
    for (int i = 0; i < exact.nodeCount(); ++i) {
        EXPECT_EQ(same.node(i).bounds0.lower, exact.node(i).bounds0.lower);
        EXPECT_EQ(same.node(i).bounds1.upper, exact.node(i).bounds1.upper);
    }
}

}  // namespace
}  // namespace patchsim
