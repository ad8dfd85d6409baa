#include "rasterizer/ray_stream.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cstring>

#include "pipeline/core/counters.h"
#include "pipeline/core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "rasterizer/z_culling.h"
#include "tests/patch_setup.h"
#include "tests/render_compare.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

// The kernels run on whichever SIMD target the host has; each must give the same samples and the
// same counts (no fused multiply-adds, per-lane results equal to the scalar tests).
TEST(RayStream, EverySimdTargetGivesTheSameSamplesAndCounts) {
    const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
    ASSERT_FALSE(targets.empty());
    for (const char* path : {"scenes/motion_defocus.json", "scenes/transparency.json"}) {
        SceneDesc scene = readSceneFile(test::sourcePath(path));
        scene.film.width = 48;
        scene.film.height = 36;
        scene.film.samplesPerPixel = 4;
        RenderOptions options;
        options.threads = 1;
        std::unique_ptr<RenderResult> first;
        CounterValues firstCounts;
        for (std::int64_t target : targets) {
            hwy::SetSupportedTargetsForTest(target);
            EXPECT_STREQ(rayStreamTarget(), hwy::TargetName(target));
            CounterRegistry::instance().reset();
            auto result = std::make_unique<RenderResult>(renderScene(scene, options));
            const CounterValues counts = CounterRegistry::instance().snapshot();
            if (!first) {
                first = std::move(result);
                firstCounts = counts;
                continue;
            }
            EXPECT_EQ(test::compare(*first, *result).mismatches, 0u)
                << path << " on " << hwy::TargetName(target);
            EXPECT_EQ(first->frame.color.rgb, result->frame.color.rgb) << path;
            EXPECT_EQ(firstCounts.raw(), counts.raw())
                << path << ": counts on " << hwy::TargetName(target);
        }
        hwy::SetSupportedTargetsForTest(0);
    }
    std::printf("SIMD targets compared: %zu\n", targets.size());
}

// With z culling a pass starts from the ray ends as the tile holds them (TileRays::rayEnd), so
// after every pass each ray must still end at its sample's depth bound: where the pass found a
// nearer hit, at that hit's.
TEST(RayStream, WithZCullingEveryRayEndsAtItsDepthBoundAfterEachPass) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/motion_defocus.json"));
    scene.film = {64, 48, 4, 1};
    const test::PatchSetup setup(scene);
    const PatchRasterizer& rasterizer = setup.rasterizer;
    ASSERT_TRUE(rasterizer.options().zCulling);
    FrontEndWorkspace ws = setup.fe.makeWorkspace();
    std::vector<MovingMesh> meshes;
    std::vector<PatchRasterizer::Group> groups(setup.fe.patchCount());
    RasterWork work;
    for (std::size_t i = 0; i < setup.fe.patchCount(); ++i) {
        meshes.push_back(setup.mesh(i, ws));
        const HierarchyOrder all = hierarchyOrder(meshes[i], int(meshes[i].triangleCount()),
                                                  rasterizer.options().leafSize);
        rasterizer.prepareGroup(meshes[i], all.triangles.data(), all.triangles.size(), groups[i],
                                work);
    }
    const TileGrid& grid = rasterizer.tileGrid();
    VisibilityBuffer buffer(grid.width, grid.height, scene.film.samplesPerPixel,
                            setup.fe.camera().farPlane());
    const TileRayFrame frame{&setup.fe.camera(),
                             setup.lens,
                             {&setup.samples, nullptr},
                             scene.film.samplesPerPixel,
                             setup.effects.timeSamples(),
                             grid.tileSize,
                             false,
                             false};
    TileRays rays(frame);
    const VisibilityTargets targets{&buffer, nullptr, nullptr, 0};
    const auto endsAtDepthBound = [&rays](int i) {
        const float depth = rays.bestDepth[i];
        const float bound = depth < rays.farDepth() ? depth : rays.farDepth();
        const float end = rayEndAtDepth(bound, rays.depthPerLambda());
        return std::memcmp(&end, &rays.rayEnd[i], sizeof end) == 0;
    };
    std::size_t passes = 0, shortened = 0, wrong = 0;
    for (int ty = 0; ty < grid.tilesY(); ++ty)
        for (int tx = 0; tx < grid.tilesX(); ++tx) {
            rays.load(grid.rect(tx, ty), buffer);
            for (int i = 0; i < rays.count(); ++i) wrong += !endsAtDepthBound(i);
            for (std::size_t g = 0; g < groups.size(); ++g) {
                const TileRange& covered = groups[g].tiles;
                if (tx < covered.x0 || tx >= covered.x1 || ty < covered.y0 || ty >= covered.y1)
                    continue;
                rasterizer.rasterizeTile(meshes[g], groups[g], tx, ty, rays, targets, work);
                ++passes;
                for (int i = 0; i < rays.count(); ++i) {
                    wrong += !endsAtDepthBound(i);
                    shortened += rays.bestDepth[i] < rays.farDepth();
                }
            }
            rays.store(buffer, nullptr);
        }
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(passes, 100u);
    EXPECT_GT(shortened, 1000u) << "the passes should find hits";
}

}  // namespace
}  // namespace patchsim
