#include "rasterizer/patent/screen_pass.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <random>

#include "core/counters.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "tests/render_compare.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

RenderResult renderWith(const SceneDesc& scene, const char* method) {
    RenderOptions options;
    options.method = &methodNamed(method);
    options.threads = 1;
    return renderScene(scene, options);
}

// A static torus, turned and placed at random, at a random tessellation.
SceneDesc randomStaticScene(std::mt19937& rng, int trial) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    SceneDesc scene;
    scene.path = "random static";
    scene.film = {72, 54, 4, std::uint64_t(trial)};
    scene.camera.open = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}};
    scene.camera.close = scene.camera.open;
    // From triangles of a few pixels to some over 8 (the kernel's float and double lanes).
    scene.tessellation.factor = 1.5f + 3.0f * (u(rng) + 1.0f);
    scene.tessellation.partitioning = Partitioning::FractionalOdd;
    ObjectDesc torus;
    torus.cagePath = test::sourcePath("scenes/cages/catmark_torus.obj");
    torus.open.translate = {u(rng), u(rng), 1.5f * u(rng)};
    torus.open.rotateDegrees = {90.0f * u(rng), 90.0f * u(rng), 90.0f * u(rng)};
    torus.close = torus.open;
    scene.objects.push_back(torus);
    return scene;
}

// The eye inside a large static cube, tessellated coarsely, seen through `lens`.
SceneDesc eyeInsideACube(const LensDesc& lens) {
    SceneDesc scene;
    scene.path = "crossing";
    scene.film = {40, 30, 8, 5};
    scene.camera.open = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}};
    scene.camera.close = scene.camera.open;
    scene.lens = lens;
    scene.tessellation.factor = 2;
    ObjectDesc cube;
    cube.cagePath = test::sourcePath("scenes/cages/bilinear_cube.obj");
    cube.open.translate = {0.3f, 0.2f, 4.0f};
    cube.open.rotateDegrees = {10, 20, 0};
    cube.open.scale = {6, 6, 6};
    cube.close = cube.open;
    scene.objects.push_back(cube);
    return scene;
}

// The edge-function kernel on every SIMD target the host runs gives the reference's samples
// (which the scalar test decides), on random static tori of small and large triangles.
TEST(ScreenPass, EverySimdTargetGivesTheReferenceSamples) {
    std::mt19937 rng(5);
    std::vector<SceneDesc> scenes;
    for (int trial = 0; trial < 6; ++trial) scenes.push_back(randomStaticScene(rng, trial));
    std::vector<RenderResult> references;
    for (const SceneDesc& scene : scenes) references.push_back(renderWith(scene, "reference"));
    const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
    ASSERT_FALSE(targets.empty());
    for (std::int64_t target : targets) {
        hwy::SetSupportedTargetsForTest(target);
        for (std::size_t k = 0; k < scenes.size(); ++k) {
            CounterRegistry::instance().reset();
            const RenderResult patch = renderWith(scenes[k], "patch");
            const CounterValues c = CounterRegistry::instance().snapshot();
            const test::Comparison cmp = test::compare(patch, references[k]);
            EXPECT_GT(cmp.hits, 0u);
            EXPECT_EQ(cmp.mismatches, 0u) << hwy::TargetName(target) << " trial " << k;
            EXPECT_GT(c[rasterCounters().edgeTests], 0);
            EXPECT_EQ(c[rasterCounters().raysCast], 0) << "every vertex is in front of the eye";
        }
    }
    hwy::SetSupportedTargetsForTest(0);
}

// The eye inside a large static cube, tessellated coarsely: the faces' triangles with a vertex
// behind the eye have no screen form and take the tile's rays, as the reference's do, next to
// triangles tested with edge functions; the samples still agree, for the patch method and the
// bounding baselines.
TEST(ScreenPass, TrianglesThroughTheCameraPlaneTakeRaysAndMatchTheReference) {
    SceneDesc scene = eyeInsideACube(LensDesc{});
    const RenderResult reference = renderWith(scene, "reference");
    // The large triangles take the kernel's double lanes: on every SIMD target.
    for (std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        CounterRegistry::instance().reset();
        const RenderResult patch = renderWith(scene, "patch");
        const CounterValues c = CounterRegistry::instance().snapshot();
        const test::Comparison cmp = test::compare(patch, reference);
        EXPECT_GT(cmp.hits, 0u);
        EXPECT_EQ(cmp.mismatches, 0u) << hwy::TargetName(target);
        EXPECT_GT(c[rasterCounters().raysCast], 0) << "some triangles should have no screen form";
        EXPECT_GT(c[rasterCounters().edgeTests], 0);
    }
    hwy::SetSupportedTargetsForTest(0);
    for (const char* bounding : {"triangle-bbox", "interval"}) {
        const test::Comparison b = test::compare(renderWith(scene, bounding), reference);
        EXPECT_EQ(b.mismatches, 0u) << bounding;
    }
    // The interleaved method samples its own pattern: the patch method on that pattern.
    scene.film.sampler = SamplePattern::Interleaved;
    const test::Comparison b =
        test::compare(renderWith(scene, "interleaved"), renderWith(scene, "patch"));
    EXPECT_GT(b.hits, 0u);
    EXPECT_EQ(b.mismatches, 0u) << "interleaved";
}

// A defocus-only frame (a lens, nothing moving) is tested with the lens edge functions
// (lens_triangle.h): on every SIMD target the patch method's kernel gives the reference's samples,
// which the scalar test decides, on random static tori seen through lenses focused in front of,
// on and behind them; no ray is cast and no time work is done; and the bounding baselines, which
// use the same test, give the same samples.
TEST(ScreenPass, EverySimdTargetGivesTheReferenceSamplesThroughALens) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> aperture(0.05f, 0.4f), focus(2.0f, 9.0f);
    std::vector<SceneDesc> scenes;
    for (int trial = 0; trial < 6; ++trial) {
        SceneDesc scene = randomStaticScene(rng, trial);
        scene.lens = {aperture(rng), focus(rng)};
        scenes.push_back(scene);
    }
    std::vector<RenderResult> references;
    for (const SceneDesc& scene : scenes) references.push_back(renderWith(scene, "reference"));
    for (std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        for (std::size_t k = 0; k < scenes.size(); ++k) {
            CounterRegistry::instance().reset();
            const RenderResult patch = renderWith(scenes[k], "patch");
            const CounterValues c = CounterRegistry::instance().snapshot();
            const test::Comparison cmp = test::compare(patch, references[k]);
            EXPECT_GT(cmp.hits, 0u);
            EXPECT_EQ(cmp.mismatches, 0u) << hwy::TargetName(target) << " trial " << k;
            const RasterCounters& rs = rasterCounters();
            EXPECT_GT(c[rs.lensEdgeTests], c[rs.visibilitySamples]);
            EXPECT_GT(c[rs.lensTriangleSetups], 0);
            EXPECT_EQ(c[rs.edgeTests], 0);
            EXPECT_EQ(c[rs.raysCast], 0) << "every vertex is in front of the lens";
            EXPECT_EQ(c[rs.rayBoxTests], 0);
            EXPECT_EQ(c[rs.timeIntervals], 0);
        }
    }
    hwy::SetSupportedTargetsForTest(0);
    for (std::size_t k = 0; k < scenes.size(); ++k)
        for (const char* bounding : {"triangle-bbox", "interval"}) {
            const test::Comparison b =
                test::compare(renderWith(scenes[k], bounding), references[k]);
            EXPECT_EQ(b.mismatches, 0u) << bounding << " trial " << k;
        }
    // The interleaved method samples its own pattern (one lens point per pass, tested over the
    // pixels seen from it): the patch method on that pattern.
    SceneDesc scene = scenes[0];
    scene.film.sampler = SamplePattern::Interleaved;
    const test::Comparison b =
        test::compare(renderWith(scene, "interleaved"), renderWith(scene, "patch"));
    EXPECT_GT(b.hits, 0u);
    EXPECT_EQ(b.mismatches, 0u) << "interleaved";
}

// The eye inside a large static cube seen through a lens: the triangles with a vertex behind the
// lens plane have no lens form and take the tile's rays, as the reference's do, beside triangles
// tested with the lens edge functions; the samples agree.
TEST(ScreenPass, TrianglesThroughTheLensPlaneTakeRaysAndMatchTheReference) {
    const SceneDesc scene = eyeInsideACube(LensDesc{0.2f, 3.0f});
    const RenderResult reference = renderWith(scene, "reference");
    CounterRegistry::instance().reset();
    const RenderResult patch = renderWith(scene, "patch");
    const CounterValues c = CounterRegistry::instance().snapshot();
    const test::Comparison cmp = test::compare(patch, reference);
    EXPECT_GT(cmp.hits, 0u);
    EXPECT_EQ(cmp.mismatches, 0u);
    EXPECT_GT(c[rasterCounters().raysCast], 0) << "some triangles should have no lens form";
    EXPECT_GT(c[rasterCounters().lensEdgeTests], 0);
    for (const char* bounding : {"triangle-bbox", "interval"}) {
        const test::Comparison b = test::compare(renderWith(scene, bounding), reference);
        EXPECT_EQ(b.mismatches, 0u) << bounding;
    }
}

}  // namespace
}  // namespace patchsim
