#include "rasterizer/ray_stream.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cstring>

#include "pipeline/core/counters.h"
#include "pipeline/core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "rasterizer/branch_node.h"
#include "rasterizer/tile_traversal.h"
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

// A small frame of a shipped scene made ready for passes: its patches' meshes and groups (one
// group per patch), a visibility buffer and the tile rays' frame.
struct GroupedFrame {
    SceneDesc scene;
    test::PatchSetup setup;
    std::vector<MovingMesh> meshes;
    std::vector<PatchRasterizer::Group> groups;
    VisibilityBuffer buffer;
    TileRayFrame frame;
    RasterWork work;

    explicit GroupedFrame(const char* path, FilmDesc film)
        : scene(withFilm(readSceneFile(test::sourcePath(path)), film)),
          setup(scene),
          groups(setup.fe.patchCount()),
          buffer(film.width, film.height, film.samplesPerPixel, setup.fe.camera().farPlane()),
          frame{&setup.fe.camera(),
                setup.lens,
                {&setup.samples, nullptr},
                film.samplesPerPixel,
                setup.effects.timeSamples(),
                setup.rasterizer.tileGrid().tileSize,
                false,
                false} {
        FrontEndWorkspace ws = setup.fe.makeWorkspace();
        const int leafSize = setup.rasterizer.options().leafSize;
        for (std::size_t i = 0; i < setup.fe.patchCount(); ++i) {
            meshes.push_back(setup.mesh(i, ws));
            const HierarchyOrder all =
                hierarchyOrder(meshes[i], int(meshes[i].triangleCount()), leafSize);
            setup.rasterizer.prepareGroup(meshes[i], all.triangles.data(), all.triangles.size(),
                                          groups[i], work);
        }
    }

    static SceneDesc withFilm(SceneDesc desc, FilmDesc film) {
        desc.film = film;
        return desc;
    }

    // `visit(tx, ty, g)` for every group g whose bounds cover tile (tx, ty), the tile's rays
    // loaded into `rays` from the buffer, and written back after the tile's last group.
    template <class Visit>
    void forEachCoveredTile(TileRays& rays, const Visit& visit) {
        const TileGrid& grid = setup.rasterizer.tileGrid();
        for (int ty = 0; ty < grid.tilesY(); ++ty)
            for (int tx = 0; tx < grid.tilesX(); ++tx) {
                rays.load(grid.rect(tx, ty), buffer);
                for (std::size_t g = 0; g < groups.size(); ++g) {
                    const TileRange& covered = groups[g].tiles;
                    if (tx >= covered.x0 && tx < covered.x1 && ty >= covered.y0 && ty < covered.y1)
                        visit(tx, ty, g);
                }
                rays.store(buffer, nullptr);
            }
    }
};

// With z culling a pass starts from the ray ends as the tile holds them (TileRays::rayEnd), so
// after every pass each ray must still end at its sample's depth bound: where the pass found a
// nearer hit, at that hit's.
TEST(RayStream, WithZCullingEveryRayEndsAtItsDepthBoundAfterEachPass) {
    GroupedFrame f("scenes/motion_defocus.json", {64, 48, 4, 1});
    const PatchRasterizer& rasterizer = f.setup.rasterizer;
    ASSERT_TRUE(rasterizer.options().zCulling);
    TileRays rays(f.frame);
    const VisibilityTargets targets{&f.buffer, nullptr, nullptr, 0};
    const auto endsAtDepthBound = [&rays](int i) {
        const float depth = rays.bestDepth[i];
        const float bound = depth < rays.farDepth() ? depth : rays.farDepth();
        const float end = rayEndAtDepth(bound, rays.depthPerLambda());
        return std::memcmp(&end, &rays.rayEnd[i], sizeof end) == 0;
    };
    std::size_t passes = 0, shortened = 0, wrong = 0;
    int lastTile = -1;
    f.forEachCoveredTile(rays, [&](int tx, int ty, std::size_t g) {
        if (tx + 1000 * ty != lastTile) {  // the tile as loaded, before its first pass
            for (int i = 0; i < rays.count(); ++i) wrong += !endsAtDepthBound(i);
            lastTile = tx + 1000 * ty;
        }
        rasterizer.rasterizeTile(f.meshes[g], f.groups[g], tx, ty, rays, targets, f.work);
        ++passes;
        for (int i = 0; i < rays.count(); ++i) {
            wrong += !endsAtDepthBound(i);
            shortened += rays.bestDepth[i] < rays.farDepth();
        }
    });
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(passes, 100u);
    EXPECT_GT(shortened, 1000u) << "the passes should find hits";
}

// What a pass counts at its start: it tests exactly the tile's samples whose time lies in the
// union of the overlapping leaves' intervals (the branch node's range), casts one ray for each,
// tests each against the branch node's box, and rejects the tile's other samples by time.
TEST(RayStream, APassTestsTheSamplesInItsLeavesTimesAndCastsARayForEach) {
    for (const char* path : {"scenes/motion_defocus.json", "scenes/static.json"}) {
        GroupedFrame f(path, {64, 48, 4, 1});
        const PatchRasterizer& rasterizer = f.setup.rasterizer;
        const Camera& camera = f.setup.fe.camera();
        TileRays rays(f.frame);
        std::size_t passes = 0, narrowed = 0;
        f.forEachCoveredTile(rays, [&](int tx, int ty, std::size_t g) {
            const PatchHierarchy& h = f.groups[g].hierarchy;
            const float farDepth =
                rasterizer.options().zCulling ? rays.farthestDepthBound() : camera.farPlane();
            RasterWork walkWork;
            const TileTraversal traversal = traverseTile(
                h, f.groups[g].nodes,
                {&camera, f.setup.lens, rasterizer.tileGrid().rect(tx, ty), farDepth},
                f.setup.effects.motion, timeRefinementOf(rasterizer.options()), walkWork);
            if (!traversal.overlaps) return;
            TimeRange hull = TimeRange::empty();
            for (int j = 0; j < h.leafCount(); ++j)
                if (traversal.leafMask >> j & 1u) hull.extend(traversal.leafTimes[std::size_t(j)]);
            std::int64_t inHull = 0;
            for (int i = 0; i < rays.count(); ++i)
                inHull += rays.time[i] >= hull.lower && rays.time[i] <= hull.upper;
            const int branch = branchNode(rasterizer.options().branchMethod, traversal, h.depth());
            RasterWork pass;
            traceRayStream(
                rays, {&f.meshes[g], &h, &traversal, branch, rasterizer.options().zCulling}, pass);
            ++passes;
            narrowed += inHull < rays.count();
            ASSERT_EQ(pass.samplesTested, inHull) << path << " tile " << tx << "," << ty;
            ASSERT_EQ(pass.raysCast, inHull);
            ASSERT_EQ(pass.samplesRejectedTime, rays.count() - inHull);
            ASSERT_GE(pass.rayBoxTests, inHull);
            ASSERT_EQ(pass.branchDepthSum, h.levelOf(branch));
        });
        EXPECT_GT(passes, 50u) << path;
        if (f.setup.effects.motion) {
            EXPECT_GT(narrowed, passes / 10) << path << ": time should narrow many passes";
        }
    }
}

}  // namespace
}  // namespace patchsim
