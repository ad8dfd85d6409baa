#include "rasterizer/patent/hierarchy_orders.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "core/scene_reader.h"
#include "tessellator/front_end.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

// Every patch of a scene as the rasterizer gets it.
std::vector<MovingMesh> sceneMeshes(const SceneDesc& scene) {
    const FrontEnd fe(scene);
    FrontEndWorkspace ws = fe.makeWorkspace();
    std::vector<MovingMesh> meshes(fe.patchCount());
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        TessellatedPatch patch;
        fe.tessellate(i, patch, ws);
        toMovingMesh(patch, fe.camera(), true, int(i), true, meshes[i]);
    }
    return meshes;
}

std::vector<const MovingMesh*> pointers(const std::vector<MovingMesh>& meshes) {
    std::vector<const MovingMesh*> p;
    for (const MovingMesh& m : meshes) p.push_back(&m);
    return p;
}

void expectSameOrder(const HierarchyOrder& a, const HierarchyOrder& b, std::size_t unit) {
    EXPECT_EQ(a.triangles, b.triangles) << "unit " << unit;
    EXPECT_EQ(a.groupBegin, b.groupBegin) << "unit " << unit;
    // The shared leaf vertex tables name the vertices this unit's own mesh would.
    ASSERT_EQ(a.leafTables.size(), b.leafTables.size()) << "unit " << unit;
    for (std::size_t g = 0; g < a.leafTables.size(); ++g) {
        EXPECT_EQ(a.leafTables[g].vertices, b.leafTables[g].vertices) << "unit " << unit;
        EXPECT_EQ(a.leafTables[g].vertexBegin, b.leafTables[g].vertexBegin) << "unit " << unit;
        EXPECT_EQ(a.leafTables[g].corners, b.leafTables[g].corners) << "unit " << unit;
    }
}

// At one fixed factor every quad patch of a cage has the same pattern: the frame orders a few
// meshes instead of every one, and each unit's shared order is the one its own mesh gives.
TEST(HierarchyOrders, SharedOrdersEqualEachMeshsOwnAtAFixedFactor) {
    SceneDesc scene = defaultScene();
    scene.tessellation.targetEdgePixels = 0;
    scene.tessellation.factor = 8.0f;
    const std::vector<MovingMesh> meshes = sceneMeshes(scene);
    for (int threads : {1, 2}) {
        const HierarchyOrders orders(pointers(meshes), 32, 4, threads);
        for (std::size_t u = 0; u < meshes.size(); ++u)
            expectSameOrder(orders.of(u), hierarchyOrder(meshes[u], 32, 4), u);
        EXPECT_LE(orders.ordersMade() * 4, meshes.size()) << meshes.size() << " units";
        EXPECT_GE(orders.ordersMade(), 2u);  // quads and the icosahedron's triangles differ
    }
}

// With adaptive factors patterns repeat less, and no unit takes another pattern's order.
TEST(HierarchyOrders, AdaptiveFactorsShareOnlyEqualPatterns) {
    const std::vector<MovingMesh> meshes = sceneMeshes(defaultScene());
    const HierarchyOrders orders(pointers(meshes), 256, 4, 2);
    for (std::size_t u = 0; u < meshes.size(); ++u)
        expectSameOrder(orders.of(u), hierarchyOrder(meshes[u], 256, 4), u);
    EXPECT_GT(orders.ordersMade(), 1u);
    EXPECT_LE(orders.ordersMade(), meshes.size());
}

TEST(HierarchyOrders, OneDifferentDomainBitIsAnotherPattern) {
    SceneDesc scene = defaultScene();
    scene.tessellation.targetEdgePixels = 0;
    scene.tessellation.factor = 4.0f;
    std::vector<MovingMesh> meshes = sceneMeshes(scene);
    ASSERT_TRUE(sameTessellationPattern(meshes[0], meshes[1]));
    std::vector<MovingMesh> two{meshes[0], meshes[1]};
    // Swap two vertices' domain positions in the second mesh (and its triangles' references), so
    // it has the same triangles in another pattern: its order differs.
    std::swap(two[1].domain[0], two[1].domain[1]);
    EXPECT_FALSE(sameTessellationPattern(two[0], two[1]));
    const HierarchyOrders orders(pointers(two), 8, 4, 1);
    EXPECT_EQ(orders.ordersMade(), 2u);
    expectSameOrder(orders.of(1), hierarchyOrder(two[1], 8, 4), 1);
}

// A patch culled to nothing has no domain or index data (null pointers): it has a pattern of its
// own, shared with other empty ones, and an empty order.
TEST(HierarchyOrders, EmptyMeshesShareAnEmptyOrder) {
    SceneDesc scene = defaultScene();
    scene.tessellation.targetEdgePixels = 0;
    scene.tessellation.factor = 2.0f;
    const std::vector<MovingMesh> meshes{MovingMesh{}, sceneMeshes(scene)[0], MovingMesh{}};
    EXPECT_TRUE(sameTessellationPattern(meshes[0], meshes[2]));
    EXPECT_FALSE(sameTessellationPattern(meshes[0], meshes[1]));
    const HierarchyOrders orders(pointers(meshes), 8, 4, 2);
    EXPECT_EQ(orders.ordersMade(), 2u);
    EXPECT_TRUE(orders.of(2).triangles.empty());
    expectSameOrder(orders.of(1), hierarchyOrder(meshes[1], 8, 4), 1);
}

// A hierarchy built from its group of hierarchyOrder equals one built from the triangles in any
// order: the same boxes and the same leaf lists.
TEST(HierarchyOrders, BuildOrderedEqualsBuild) {
    const std::vector<MovingMesh> meshes = sceneMeshes(defaultScene());
    for (std::size_t u = 0; u < meshes.size(); u += 7) {
        const MovingMesh& mesh = meshes[u];
        const HierarchyOrder order = hierarchyOrder(mesh, 64, 4);
        for (std::size_t g = 0; g + 1 < order.groupBegin.size(); ++g) {
            const std::uint32_t* group = order.triangles.data() + order.groupBegin[g];
            const std::size_t count = order.groupBegin[g + 1] - order.groupBegin[g];
            std::vector<std::uint32_t> reversed(group, group + count);
            std::reverse(reversed.begin(), reversed.end());
            PatchHierarchy built, ordered, withTable;
            built.build(mesh, reversed.data(), count, 4);
            ordered.buildOrdered(mesh, group, count, 4);
            withTable.buildOrdered(mesh, group, count, 4, &order.leafTables[g]);
            ASSERT_EQ(built.nodeCount(), ordered.nodeCount());
            for (int n = 0; n < built.nodeCount(); ++n)
                EXPECT_EQ(std::memcmp(&built.node(n), &ordered.node(n), sizeof(LBBox)), 0)
                    << "unit " << u << " group " << g << " node " << n;
            for (int leaf = 0; leaf < built.leafCount(); ++leaf) {
                std::size_t a, b;
                const std::uint32_t* ta = built.leafTriangles(leaf, a);
                const std::uint32_t* tb = ordered.leafTriangles(leaf, b);
                ASSERT_EQ(a, b);
                std::vector<std::uint32_t> sa(ta, ta + a), sb(tb, tb + b);
                std::sort(sa.begin(), sa.end());
                std::sort(sb.begin(), sb.end());
                EXPECT_EQ(sa, sb) << "unit " << u << " group " << g << " leaf " << leaf;
                // The order's leaf vertex table is the one the hierarchy would make itself.
                std::size_t va, vb;
                const std::uint32_t* made = ordered.leafVertices(leaf, va);
                const std::uint32_t* shared = withTable.leafVertices(leaf, vb);
                ASSERT_EQ(va, vb);
                EXPECT_TRUE(std::equal(made, made + va, shared));
                EXPECT_TRUE(std::equal(ordered.leafCorners(leaf), ordered.leafCorners(leaf) + 3 * b,
                                       withTable.leafCorners(leaf)));
            }
        }
    }
}

}  // namespace
}  // namespace patchsim
