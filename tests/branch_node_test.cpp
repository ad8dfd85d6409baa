#include "rasterizer/patent/branch_node.h"

#include <gtest/gtest.h>

#include "core/scene_reader.h"
#include "rasterizer/patent/patch_rasterizer.h"
#include "rasterizer/patent/tile_frustum.h"
#include "rasterizer/patent/tile_traversal.h"
#include "tessellator/front_end.h"
#include "tests/patch_setup.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

TEST(BranchNode, BitmaskFindsTheLowestNodeAboveEveryLeaf) {
    // Depth 3: leaves are nodes 7..14 (leaf j is node 7 + j).
    EXPECT_EQ(bitmaskBranchNode(0b00000001, 3), 7);  // one leaf: the leaf itself
    EXPECT_EQ(bitmaskBranchNode(0b00000011, 3), 3);  // leaves 0, 1: their parent
    EXPECT_EQ(bitmaskBranchNode(0b00000110, 3), 1);  // leaves 1, 2: parents 3, 4 meet at 1
    EXPECT_EQ(bitmaskBranchNode(0b00110000, 3), 5);  // leaves 4, 5: parent 5
    EXPECT_EQ(bitmaskBranchNode(0b10000001, 3), 0);  // both ends: the root
    EXPECT_EQ(bitmaskBranchNode(0b11110000, 3), 2);  // the right half
    EXPECT_EQ(bitmaskBranchNode(1, 0), 0);           // a single-leaf tree
    EXPECT_EQ(bitmaskBranchNode(std::uint64_t(1) << 63, 6), 63 + 63);  // the last of 64 leaves
}

TEST(BranchNode, MethodsPickRootFirstSplitOrBitmask) {
    TileTraversal t;
    t.overlaps = true;
    t.leafMask = 0b00001100;
    t.firstSplitNode = 1;
    EXPECT_EQ(branchNode(BranchMethod::Root, t, 3), 0);
    EXPECT_EQ(branchNode(BranchMethod::FirstSplit, t, 3), 1);
    EXPECT_EQ(branchNode(BranchMethod::Bitmask, t, 3), 4);
}

// On real tiles, the bitmask node lies in the first-split node's subtree (never above it), and
// is deeper in some tiles.
TEST(BranchNode, BitmaskIsNeverAboveFirstSplitOnARealScene) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/motion_defocus.json"));
    scene.film = {96, 72, 4, 1};
    const test::PatchSetup setup(scene);
    const PatchRasterizer& rasterizer = setup.rasterizer;
    const FrontEnd& fe = setup.fe;
    FrontEndWorkspace ws = fe.makeWorkspace();
    std::size_t compared = 0, strictlyBelow = 0;
    RasterWork work;
    for (std::size_t i = 0; i < fe.patchCount(); ++i) {
        const MovingMesh mesh = setup.mesh(i, ws);
        // The whole patch as one group.
        const HierarchyOrder all =
            hierarchyOrder(mesh, int(mesh.triangleCount()), rasterizer.options().leafSize);
        PatchRasterizer::Group group;
        rasterizer.prepareGroup(mesh, all.triangles.data(), all.triangles.size(), group, work);
        for (int ty = group.tiles.y0; ty < group.tiles.y1; ++ty)
            for (int tx = group.tiles.x0; tx < group.tiles.x1; ++tx) {
                const TileFrustum frustum =
                    makeTileFrustum(fe.camera(), setup.lens, rasterizer.tileGrid().rect(tx, ty),
                                    fe.camera().farPlane());
                const TileTraversal t =
                    traverseTile(group.hierarchy, frustum, true, TimeRefinement::Leaves, work);
                if (!t.overlaps) continue;
                ++compared;
                const int bitmask = branchNode(BranchMethod::Bitmask, t, group.hierarchy.depth());
                int node = bitmask;
                while (node > t.firstSplitNode) node = (node - 1) / 2;
                EXPECT_EQ(node, t.firstSplitNode);
                strictlyBelow += bitmask != t.firstSplitNode;
            }
    }
    EXPECT_GT(compared, 100u);
    EXPECT_GT(strictlyBelow, 0u) << "the bitmask method should find deeper nodes in some tiles";
}

}  // namespace
}  // namespace patchsim
