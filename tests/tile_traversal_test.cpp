#include "rasterizer/patent/tile_traversal.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/scene_reader.h"
#include "rasterizer/patent/patch_rasterizer.h"
#include "rasterizer/patent/tile_frustum.h"
#include "tessellator/front_end.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

void expectSameWalk(const TileTraversal& a, const RasterWork& workA, const TileTraversal& b,
                    const RasterWork& workB) {
    ASSERT_EQ(a.overlaps, b.overlaps);
    ASSERT_EQ(a.leafMask, b.leafMask);
    ASSERT_EQ(a.firstSplitNode, b.firstSplitNode);
    ASSERT_EQ(a.times, b.times);
    for (int j = 0; j < kMaxLeavesPerHierarchy; ++j) {
        if (a.leafMask >> j & 1u) {
            ASSERT_EQ(a.leafTimes[std::size_t(j)], b.leafTimes[std::size_t(j)]);
        }
    }
    EXPECT_EQ(workA.planeTests, workB.planeTests);
    EXPECT_EQ(workA.timeIntervals, workB.timeIntervals);
    EXPECT_EQ(workA.frustumNodeVisits, workB.frustumNodeVisits);
    EXPECT_EQ(workA.tilesRejectedSpace, workB.tilesRejectedSpace);
    EXPECT_EQ(workA.tilesRejectedTime, workB.tilesRejectedTime);
}

// The vector walk (side planes in SIMD lanes) gives the scalar walk's leaves, time intervals,
// first split and counts, tile for tile, with and without a lens, motion, time refinement and a
// far plane pulled in by the z-buffer, on full hierarchies of the greatest depth, on ones whose
// last leaves are empty, and on a single leaf.
TEST(TileTraversal, VectorWalkEqualsTheScalarWalk) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/motion_defocus.json"));
    scene.film = {64, 48, 1, 1};
    // 512 triangles a patch: groups of 256 fill a hierarchy of the greatest depth.
    scene.tessellation.targetEdgePixels = 0;
    scene.tessellation.factor = 16.0f;
    const FrontEnd fe(scene);
    const Camera& camera = fe.camera();
    FrontEndWorkspace ws = fe.makeWorkspace();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::size_t walks = 0, overlapping = 0, deepWalks = 0;
    for (std::size_t i = 0; i < fe.patchCount(); ++i) {
        TessellatedPatch patch;
        fe.tessellate(i, patch, ws);
        MovingMesh mesh;
        toMovingMesh(patch, camera, true, int(i), true, mesh);
        std::vector<std::uint32_t> all(mesh.triangleCount());
        for (std::size_t k = 0; k < all.size(); ++k) all[k] = std::uint32_t(k);
        for (const std::size_t count : {std::size_t(256), std::size_t(37), std::size_t(3)}) {
            PatchHierarchy h;
            h.build(mesh, all.data(), std::min(all.size(), count), 4);
            for (int tile = 0; tile < 24; ++tile) {
                // Around a vertex of the patch, so that most tiles see it.
                const int size = 1 << (tile % 4);
                Vec2 raster;
                const auto vertex = std::size_t(unit(rng) * float(mesh.position0.size() - 1));
                if (!camera.cameraToRaster(mesh.position0[vertex], raster)) continue;
                const int x = std::clamp(int(raster.x) - size / 2, 0, camera.width() - size);
                const int y = std::clamp(int(raster.y) - size / 2, 0, camera.height() - size);
                const LensModel lens{tile % 3 == 0 ? 0.0f : scene.lens.apertureRadius,
                                     scene.lens.focusDistance};
                const float far = tile % 2 ? camera.farPlane() : 2.0f + 10.0f * unit(rng);
                const TileFrustum frustum =
                    makeTileFrustum(camera, lens, {x, y, x + size, y + size}, far);
                for (bool motion : {true, false})
                    for (TimeRefinement refine : {TimeRefinement::Off, TimeRefinement::Leaves,
                                                  TimeRefinement::EveryLevel}) {
                        RasterWork vectorWork, scalarWork;
                        const TileTraversal v =
                            traverseTile(h, frustum, motion, refine, vectorWork);
                        const TileTraversal s =
                            traverseTileScalar(h, frustum, motion, refine, scalarWork);
                        expectSameWalk(v, vectorWork, s, scalarWork);
                        if (HasFailure()) return;
                        ++walks;
                        overlapping += v.overlaps;
                        deepWalks += s.overlaps && h.depth() == kMaxHierarchyDepth;
                    }
            }
        }
    }
    EXPECT_GT(deepWalks, 100u) << "too few walks reach a leaf of a hierarchy of 64 leaves";
    EXPECT_GT(walks, 1000u);
    EXPECT_GT(overlapping, walks / 3) << "too few walks reach a leaf to say anything";
}

}  // namespace
}  // namespace patchsim
