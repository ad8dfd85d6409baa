#include "rasterizer/patent/patch_rasterizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <tuple>

#include "core/counters.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "rasterizer/baselines/reference_rasterizer.h"
#include "tests/render_compare.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

SceneDesc smallScene(SceneDesc scene, int width = 48, int height = 36, int spp = 4) {
    scene.film.width = width;
    scene.film.height = height;
    scene.film.samplesPerPixel = spp;
    return scene;
}

RenderResult renderWith(const SceneDesc& scene, const VisibilityMethod* method, int threads = 1) {
    RenderOptions options;
    options.method = method;
    options.threads = threads;
    return renderScene(scene, options);
}

using test::compare;
using test::Comparison;

double totalOps(const RenderResult& r, Op op) {
    PatchOps total;
    for (const PatchOps& p : r.patchOps) total.add(p);
    return total[op];
}

TEST(PatchRasterizer, MatchesTheReferenceOnEveryShippedScene) {
    for (const std::string& path : test::sceneFiles()) {
        const SceneDesc scene = smallScene(readSceneFile(path));
        const RenderResult patch = renderWith(scene, &methodNamed("patch"));
        const RenderResult reference = renderWith(scene, &methodNamed("reference"));
        const Comparison c = compare(patch, reference);
        EXPECT_GT(c.hits, c.samples / 20) << path << ": the scene should cover the frame";
        EXPECT_EQ(c.mismatches, 0u)
            << path << ": " << c.mismatches << " of " << c.samples << " samples differ";
    }
}

TEST(PatchRasterizer, EveryOptionGivesTheReferenceVisibility) {
    const SceneDesc base =
        smallScene(readSceneFile(test::sourcePath("scenes/motion_defocus.json")));
    const RenderResult reference = renderWith(base, &methodNamed("reference"));
    std::vector<std::pair<std::string, RasterizerOptions>> variants;
    for (BranchMethod m : {BranchMethod::Root, BranchMethod::FirstSplit, BranchMethod::Bitmask}) {
        RasterizerOptions o;
        o.branchMethod = m;
        variants.push_back({branchMethodName(m), o});
    }
    RasterizerOptions o;
    o.timeRefinement = false;
    variants.push_back({"no time refinement", o});
    o = {};
    o.zCulling = false;
    variants.push_back({"no z culling", o});
    for (int tile : {1, 4, 16, 32}) {
        o = {};
        o.tileSize = tile;
        variants.push_back({"tile " + std::to_string(tile), o});
    }
    for (int leaf : {1, 2, 8}) {
        o = {};
        o.leafSize = leaf;
        o.maxTrianglesPerGroup = 64 * leaf;
        variants.push_back({"leaf " + std::to_string(leaf), o});
    }
    o = {};
    o.boundsLevel = 3;
    variants.push_back({"bounds level 3", o});
    o = {};
    o.maxTrianglesPerGroup = 16;
    variants.push_back({"groups of 16", o});
    for (BoundsSpace space : {BoundsSpace::Homogeneous2D, BoundsSpace::Screen2D}) {
        for (bool refine : {true, false}) {
            o = {};
            o.boundsSpace = space;
            o.timeRefinement = refine;
            variants.push_back(
                {std::string(boundsSpaceName(space)) + (refine ? "" : " spatial"), o});
        }
    }
    o = {};
    o.mergeTrianglesBelow = 64;
    variants.push_back({"merged below 64", o});
    // Boxes stored in narrower formats, rounded outward (issue 35), in every bounds space.
    for (const char* format : {"fp16", "bf16", "fixed12.6"})
        for (BoundsSpace space :
             {BoundsSpace::Camera3D, BoundsSpace::Homogeneous2D, BoundsSpace::Screen2D}) {
            o = {};
            ASSERT_TRUE(parseNumberFormat(format, o.nodeFormat));
            o.boundsSpace = space;
            variants.push_back({std::string(format) + " " + boundsSpaceName(space), o});
        }
    for (const auto& [name, options] : variants) {
        SceneDesc scene = base;
        scene.rasterizer = options;
        const RenderResult patch = renderWith(scene, &methodNamed("patch"));
        EXPECT_EQ(compare(patch, reference).mismatches, 0u) << name;
    }
}

// A bar 80 units wide: only its x bounds leave a narrow fixed-point range, so its screen bounds
// reach millions of pixels while its depth stays in front of the camera. `moving`: it also moves
// half a unit across the shutter.
SceneDesc eightyUnitBar(bool moving) {
    nlohmann::json scene = nlohmann::json::parse(
        R"({"camera": {"position": [0, 0, 6], "look_at": [0, 0, 0], "fov_y_degrees": 40},
            "film": {"width": 48, "height": 36, "spp": 4, "seed": 2},
            "objects": [{"cage": "catmark_cube_creases1.obj",
                         "open": {"translate": [0, 0, 3], "scale": [40, 0.4, 0.4]}}]})");
    if (moving) {
        scene["shutter"] = {{"open", 0}, {"close", 1}};
        scene["objects"][0]["close"] = {{"translate", {0.5, 0.2, 3}}, {"scale", {40, 0.4, 0.4}}};
    }
    return parseScene(scene.dump(), "bar.json", test::sourcePath("scenes/cages"));
}

// Node formats so narrow that most bounds leave their range and open to the largest float: rays
// at exactly t = 0 or 1 (defocus without motion, a grid sampler's times) weigh a box end by zero,
// and bounds far off screen reach the tile binning; neither may lose a hit (an infinite bound
// made NaN slabs and an undefined float-to-int conversion before 2026-12-07).
TEST(PatchRasterizer, NodeBoundsOutOfAFormatsRangeLoseNoHit) {
    SceneDesc grid = smallScene(readSceneFile(test::sourcePath("scenes/motion.json")));
    grid.film.sampler = SamplePattern::Grid;
    const SceneDesc scenes[] = {smallScene(readSceneFile(test::sourcePath("scenes/defocus.json"))),
                                smallScene(readSceneFile(test::sourcePath("scenes/static.json"))),
                                grid, eightyUnitBar(false)};
    for (const SceneDesc& base : scenes) {
        const RenderResult reference = renderWith(base, &methodNamed("reference"));
        for (const char* format : {"fixed2.0", "fixed4.4", "fixed2.30"})
            for (BoundsSpace space :
                 {BoundsSpace::Camera3D, BoundsSpace::Homogeneous2D, BoundsSpace::Screen2D}) {
                SceneDesc scene = base;
                ASSERT_TRUE(parseNumberFormat(format, scene.rasterizer.nodeFormat));
                scene.rasterizer.boundsSpace = space;
                const Comparison c = compare(renderWith(scene, &methodNamed("patch")), reference);
                EXPECT_GT(c.hits, 0u);
                EXPECT_EQ(c.mismatches, 0u)
                    << base.path << " " << format << " " << boundsSpaceName(space);
            }
    }
}

// The tile planes and leaf time intervals computed in a narrower format (rasterizer.plane_format,
// issue 35), and the ray-box tests (rasterizer.ray_box_format), each distance bounded by its
// rounding error: the hits are the reference's, with
// time refinement at the leaves and at every level, on blurred, static and grid-timed frames and
// on the 80-unit bar, whose distances leave fixed4.4's range (the test then gives its planes
// up); the narrower the format, the more the tile tests let through. A 2D bounds space, which
// has no 3D planes, is refused.
TEST(PatchRasterizer, PlaneAndRayBoxFormatsLoseNoHitAndOnlyLetMoreThrough) {
    SceneDesc grid = smallScene(readSceneFile(test::sourcePath("scenes/motion.json")));
    grid.film.sampler = SamplePattern::Grid;
    const SceneDesc scenes[] = {
        smallScene(readSceneFile(test::sourcePath("scenes/motion_defocus.json"))),
        smallScene(readSceneFile(test::sourcePath("scenes/static.json"))), grid,
        eightyUnitBar(true)};
    for (const SceneDesc& base : scenes) {
        const RenderResult reference = renderWith(base, &methodNamed("reference"));
        const RenderResult fp32 = renderWith(base, &methodNamed("patch"));
        for (const char* format : {"fp16", "bf16", "fixed16.8", "fixed4.4"})
            for (bool everyLevel : {true, false}) {
                SceneDesc scene = base;
                ASSERT_TRUE(parseNumberFormat(format, scene.rasterizer.planeFormat));
                scene.rasterizer.interiorTimeRefinement = everyLevel;
                const RenderResult patch = renderWith(scene, &methodNamed("patch"));
                const Comparison c = compare(patch, reference);
                EXPECT_GT(c.hits, 0u);
                EXPECT_EQ(c.mismatches, 0u) << base.path << " " << format << " " << everyLevel;
                EXPECT_GE(totalOps(patch, Op::RayBoxTests), totalOps(fp32, Op::RayBoxTests))
                    << base.path << " " << format;
            }
    }
    // The ray-box tests in the format (rasterizer.ray_box_format), bounded: the same hits, in
    // every bounds space, with more rays reaching the triangles the narrower the format.
    for (const SceneDesc& base : scenes) {
        const RenderResult reference = renderWith(base, &methodNamed("reference"));
        const RenderResult fp32 = renderWith(base, &methodNamed("patch"));
        for (const char* format : {"fp16", "bf16", "fixed16.8", "fixed4.4"})
            for (BoundsSpace space :
                 {BoundsSpace::Camera3D, BoundsSpace::Homogeneous2D, BoundsSpace::Screen2D}) {
                SceneDesc scene = base;
                ASSERT_TRUE(parseNumberFormat(format, scene.rasterizer.rayBoxFormat));
                scene.rasterizer.boundsSpace = space;
                const RenderResult patch = renderWith(scene, &methodNamed("patch"));
                const Comparison c = compare(patch, reference);
                EXPECT_EQ(c.mismatches, 0u)
                    << base.path << " ray boxes in " << format << " " << boundsSpaceName(space);
                if (space == BoundsSpace::Camera3D) {
                    EXPECT_GE(totalOps(patch, Op::RayTriangleTests),
                              totalOps(fp32, Op::RayTriangleTests))
                        << base.path << " " << format;
                }
            }
    }
    SceneDesc flat = scenes[0];
    flat.rasterizer.planeFormat = NumberFormat::fp16();
    flat.rasterizer.boundsSpace = BoundsSpace::Screen2D;
    try {
        renderWith(flat, &methodNamed("patch"));
        ADD_FAILURE() << "a plane format with 2D bounds was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "rasterizer.plane_format");
    }
}

// Positions rounded on their way to the rasterizer (rasterizer.vertex_format, issue 35): every
// method gets the same rounded meshes, so the patch method and triangle-bbox still equal the
// reference sample for sample, and the image moves away from fp32's, further the fewer bits.
TEST(PatchRasterizer, AVertexFormatRoundsEveryMethodsGeometryAlike) {
    SceneDesc scene = smallScene(readSceneFile(test::sourcePath("scenes/motion_defocus.json")));
    const RenderResult exact = renderWith(scene, &methodNamed("patch"));
    double previous = 0;
    for (const char* format : {"fp16", "bf16"}) {
        ASSERT_TRUE(parseNumberFormat(format, scene.rasterizer.vertexFormat));
        const RenderResult reference = renderWith(scene, &methodNamed("reference"));
        const RenderResult patch = renderWith(scene, &methodNamed("patch"), 2);
        const RenderResult bbox = renderWith(scene, &methodNamed("triangle-bbox"));
        EXPECT_EQ(compare(patch, reference).mismatches, 0u) << format;
        EXPECT_EQ(compare(bbox, reference).mismatches, 0u) << format;
        const std::size_t moved = compare(patch, exact).mismatches;
        EXPECT_GT(moved, previous) << format << ": samples whose nearest hit changed";
        previous = double(moved);
    }
}

// The 2D bounds space's projected nodes stored in a narrower format, rounded outward
// (rasterizer.screen_bounds_format, issue 35; fixed point in pixels): the reference's hits on
// blurred, static and grid-timed frames, and the coarser the format, the more the 2D tile tests
// let through. Rounded to nearest, the verifier's naive variant, the same boxes lose cases
// (TileTestVerifier tests); any other bounds space is refused.
TEST(PatchRasterizer, ScreenBoundsFormatsLoseNoHitAndOnlyLetMoreThrough) {
    SceneDesc grid = smallScene(readSceneFile(test::sourcePath("scenes/motion.json")));
    grid.film.sampler = SamplePattern::Grid;
    const SceneDesc scenes[] = {
        smallScene(readSceneFile(test::sourcePath("scenes/motion_defocus.json"))),
        smallScene(readSceneFile(test::sourcePath("scenes/static.json"))), grid};
    for (SceneDesc base : scenes) {
        base.rasterizer.boundsSpace = BoundsSpace::Screen2D;
        const RenderResult reference = renderWith(base, &methodNamed("reference"));
        const RenderResult fp32 = renderWith(base, &methodNamed("patch"));
        double previous = totalOps(fp32, Op::RayBoxTests);
        for (const char* format : {"fp16", "bf16", "fixed16.8", "fixed16.2"}) {
            SceneDesc scene = base;
            ASSERT_TRUE(parseNumberFormat(format, scene.rasterizer.screenBoundsFormat));
            const RenderResult patch = renderWith(scene, &methodNamed("patch"), 2);
            const Comparison c = compare(patch, reference);
            EXPECT_GT(c.hits, 0u);
            EXPECT_EQ(c.mismatches, 0u) << base.path << " screen bounds in " << format;
            EXPECT_EQ(formatName(patch.formats.screenBounds), format);
            if (std::string(format) == "bf16" || std::string(format) == "fixed16.2") {
                EXPECT_GE(totalOps(patch, Op::RayBoxTests), previous) << base.path << " " << format;
            }
            // A static frame tests its samples with edge functions, not rays.
            if (std::string(format) == "fixed16.2" && totalOps(fp32, Op::RayBoxTests) > 0) {
                EXPECT_GT(totalOps(patch, Op::RayBoxTests), totalOps(fp32, Op::RayBoxTests))
                    << base.path << ": quarter-pixel steps let nothing more through";
            }
            previous = totalOps(patch, Op::RayBoxTests);
        }
    }
    SceneDesc solid = scenes[0];
    solid.rasterizer.screenBoundsFormat = NumberFormat::fp16();
    try {
        renderWith(solid, &methodNamed("patch"));
        ADD_FAILURE() << "a screen bounds format with 3D bounds was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "rasterizer.screen_bounds_format");
    }
}

// The ray-triangle tests in a narrower format (rasterizer.triangle_format, issue 35): the patch
// method and the reference test alike, so they still agree sample for sample; the image moves away
// from fp32's, further the fewer bits; the render reports the format.
TEST(PatchRasterizer, ATriangleFormatRoundsThePatchMethodAndTheReferenceAlike) {
    SceneDesc scene = smallScene(readSceneFile(test::sourcePath("scenes/motion_defocus.json")));
    const RenderResult exact = renderWith(scene, &methodNamed("patch"));
    double previous = 0;
    for (const char* format : {"fp16", "bf16"}) {
        ASSERT_TRUE(parseNumberFormat(format, scene.rasterizer.triangleFormat));
        const RenderResult reference = renderWith(scene, &methodNamed("reference"));
        const RenderResult patch = renderWith(scene, &methodNamed("patch"), 2);
        EXPECT_EQ(compare(patch, reference).mismatches, 0u) << format;
        EXPECT_EQ(formatName(patch.formats.triangles), format);
        // The bounding baselines test in fp32 (their culling is not grown for a narrower test).
        const RenderResult bbox = renderWith(scene, &methodNamed("triangle-bbox"));
        EXPECT_EQ(formatName(bbox.formats.triangles), "fp32");
        EXPECT_EQ(compare(bbox, exact).mismatches, 0u) << format;
        const std::size_t moved = compare(patch, exact).mismatches;
        EXPECT_GT(moved, previous) << format << ": samples whose nearest hit changed";
        previous = double(moved);
    }
}

std::int64_t counted(const char* name) {
    return CounterRegistry::instance().snapshot().byName(name);
}

// Merging small patches: fewer hierarchies, the same samples; bounds spaces: the same samples,
// and 2D converts every node while 3D converts none.
TEST(PatchRasterizer, MergedPatchesAndEveryBoundsSpaceGiveTheSameSamples) {
    SceneDesc scene = smallScene(readSceneFile(test::sourcePath("scenes/motion_defocus.json")));
    scene.tessellation.targetEdgePixels = 0;  // small patches: factor 2
    scene.tessellation.factor = 2.0f;
    const RenderResult reference = renderWith(scene, &methodNamed("reference"));
    CounterRegistry::instance().reset();
    const RenderResult alone = renderWith(scene, &methodNamed("patch"));
    const std::int64_t groupsAlone = counted("RS/Groups");
    EXPECT_EQ(counted("RS/Patches merged"), 0);
    EXPECT_EQ(counted("RS/Nodes converted"), 0);
    for (int below : {16, 64, 256}) {
        scene.rasterizer.mergeTrianglesBelow = below;
        CounterRegistry::instance().reset();
        const RenderResult merged = renderWith(scene, &methodNamed("patch"), 2);
        EXPECT_EQ(compare(merged, reference).mismatches, 0u) << below;
        EXPECT_GT(counted("RS/Patches merged"), 0) << below;
        EXPECT_LT(counted("RS/Groups"), groupsAlone) << below;
        EXPECT_EQ(counted("RS/Patches"), std::int64_t(alone.patches)) << below;
    }
    scene.rasterizer.mergeTrianglesBelow = 0;
    for (BoundsSpace space : {BoundsSpace::Homogeneous2D, BoundsSpace::Screen2D}) {
        scene.rasterizer.boundsSpace = space;
        CounterRegistry::instance().reset();
        const RenderResult r = renderWith(scene, &methodNamed("patch"));
        EXPECT_EQ(compare(r, reference).mismatches, 0u) << boundsSpaceName(space);
        EXPECT_EQ(counted("RS/Nodes converted"), counted("RS/Nodes built"));
    }
}

// Random moving, defocused torus patches: transforms, lens and focus drawn from a fixed seed.
TEST(PatchRasterizer, MatchesTheReferenceOnRandomMovingDefocusedPatches) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int trial = 0; trial < 12; ++trial) {
        SceneDesc scene;
        scene.path = "random";
        scene.film = {40, 30, 4, std::uint64_t(trial)};
        scene.camera.open = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}};
        scene.camera.close = scene.camera.open;
        scene.lens = {trial % 3 == 0 ? 0.0f : 0.3f * (u(rng) + 1.0f),
                      3.0f + 2.0f * (u(rng) + 1.0f)};
        scene.tessellation.factor = 3.0f + 2.5f * (u(rng) + 1.0f);
        scene.tessellation.partitioning = Partitioning::FractionalOdd;
        ObjectDesc torus;
        torus.cagePath = test::sourcePath("scenes/cages/catmark_torus.obj");
        torus.open.translate = {u(rng), u(rng), u(rng)};
        torus.open.rotateDegrees = {90.0f * u(rng), 90.0f * u(rng), 90.0f * u(rng)};
        torus.close.translate = torus.open.translate + 1.5f * Vec3(u(rng), u(rng), 2.0f * u(rng));
        torus.close.rotateDegrees = torus.open.rotateDegrees + 40.0f * Vec3(u(rng), u(rng), u(rng));
        scene.objects.push_back(torus);
        scene.rasterizer.boundsSpace = BoundsSpace(trial % 3);
        const RenderResult patch = renderWith(scene, &methodNamed("patch"));
        const RenderResult reference = renderWith(scene, &methodNamed("reference"));
        const Comparison c = compare(patch, reference);
        EXPECT_EQ(c.mismatches, 0u) << "trial " << trial;
    }
}

// A torus that flies through the near plane and the camera plane during the frame.
TEST(PatchRasterizer, PatchCrossingTheCameraPlaneMatchesTheReference) {
    for (float aperture : {0.0f, 0.2f}) {
        SceneDesc scene;
        scene.path = "crossing";
        scene.film = {40, 30, 8, 5};
        scene.camera.open = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}};
        scene.camera.close = scene.camera.open;
        scene.lens = {aperture, 4.0f};
        scene.tessellation.factor = 6;
        ObjectDesc torus;
        torus.cagePath = test::sourcePath("scenes/cages/catmark_torus.obj");
        torus.open.translate = {0.3f, 0.2f, 0.0f};
        torus.open.rotateDegrees = {80, 0, 0};
        torus.close = torus.open;
        torus.close.translate = {0.3f, 0.2f, 7.0f};
        scene.objects.push_back(torus);
        CounterRegistry::instance().reset();
        const RenderResult patch = renderWith(scene, &methodNamed("patch"));
        const CounterValues counters = CounterRegistry::instance().snapshot();
        const RenderResult reference = renderWith(scene, &methodNamed("reference"));
        const Comparison c = compare(patch, reference);
        EXPECT_GT(counters[rasterCounters().fullScreenBounds], 0);
        EXPECT_GT(c.hits, 0u);
        EXPECT_EQ(c.mismatches, 0u) << "aperture " << aperture;
        for (float v : patch.frame.color.rgb) ASSERT_TRUE(std::isfinite(v));
    }
}

TEST(PatchRasterizer, ImagesAndCountersDoNotDependOnTheThreadCount) {
    const SceneDesc scene =
        smallScene(readSceneFile(test::sourcePath("scenes/motion_defocus.json")), 64, 48, 4);
    CounterRegistry::instance().reset();
    const RenderResult one = renderWith(scene, &methodNamed("patch"), 1);
    const CounterValues countersOne = CounterRegistry::instance().snapshot();
    CounterRegistry::instance().reset();
    const RenderResult two = renderWith(scene, &methodNamed("patch"), 2);
    const CounterValues countersTwo = CounterRegistry::instance().snapshot();
    EXPECT_EQ(one.frame.color.rgb, two.frame.color.rgb);
    EXPECT_EQ(countersOne.raw(), countersTwo.raw());
}

// A static frame is rasterized as one (screen_pass.h): no time work, and no ray, box or
// ray-triangle test; its samples are tested with edge functions, each triangle set up per tile.
TEST(PatchRasterizer, StaticSceneDoesNoTimeWorkAndCastsNoRay) {
    CounterRegistry::instance().reset();
    const SceneDesc scene = smallScene(readSceneFile(test::sourcePath("scenes/static.json")));
    renderWith(scene, &methodNamed("patch"));
    const CounterValues c = CounterRegistry::instance().snapshot();
    const RasterCounters& rs = rasterCounters();
    EXPECT_EQ(c[rs.timeIntervals], 0);
    EXPECT_EQ(c[rs.samplesRejectedTime], 0);
    EXPECT_EQ(c[rs.tilesRejectedTime], 0);
    EXPECT_EQ(c[rs.raysCast], 0);
    EXPECT_EQ(c[rs.rayBoxTests], 0);
    EXPECT_EQ(c[rs.rayTriangleTests], 0);
    EXPECT_GT(c[rs.screenTriangleSetups], 0);
    EXPECT_GT(c[rs.edgeTests], c[rs.visibilitySamples]);
    EXPECT_GT(c[rs.visibilitySamples], 0);
    // ...and the samples carry no time.
    const SampleGenerator samples(1, 4, Effects{});
    for (int s = 0; s < 4; ++s) EXPECT_EQ(samples.sample(3, 4, s).time, 0.0f);
}

TEST(PatchRasterizer, MotionSceneNarrowsTimeAndRejectsSamplesByTime) {
    CounterRegistry::instance().reset();
    renderWith(smallScene(readSceneFile(test::sourcePath("scenes/motion.json"))),
               &methodNamed("patch"));
    const CounterValues c = CounterRegistry::instance().snapshot();
    EXPECT_GT(c[rasterCounters().timeIntervals], 0);
    EXPECT_GT(c[rasterCounters().samplesRejectedTime], 0);
}

TEST(PatchRasterizer, WritesABlurredImage) {
    const SceneDesc scene = smallScene(defaultScene(), 80, 60, 8);
    const RenderResult r = renderWith(scene, &methodNamed("patch"));
    ASSERT_EQ(r.frame.color.width, 80);
    double sum = 0;
    std::size_t partial = 0;  // pixels whose samples disagree: blur (or an edge)
    for (int y = 0; y < 60; ++y) {
        for (int x = 0; x < 80; ++x) {
            const Vec3 c = r.frame.color.get(x, y);
            ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
            sum += c.x + c.y + c.z;
            int hits = 0;
            for (int s = 0; s < 8; ++s) hits += r.visibility->at(x, y, s).hit();
            partial += hits > 0 && hits < 8;
        }
    }
    EXPECT_GT(sum, 0.0);
    EXPECT_GT(partial, 200u) << "motion and defocus blur make wide partially covered regions";
}

}  // namespace
}  // namespace patchsim
