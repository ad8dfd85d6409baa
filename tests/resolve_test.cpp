#include "backend/shading/resolve.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>

#include "backend/images/image.h"
#include "core/counters.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "rasterizer/patent/raster_work.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

// A bilinear quad, 20 x 20 units in the z = 0 plane: fills the view of a camera 5 units away.
std::string quadCage() {
    const std::string path = test::temporaryDirectory() + "/bilinear_quad.obj";
    std::ofstream(path) << "v -10 -10 0\nv 10 -10 0\nv 10 10 0\nv -10 10 0\nf 1 2 3 4\n";
    return path;
}

ObjectDesc quad(const std::string& cage, Vec3 color, float opacity, float z) {
    ObjectDesc o;
    o.cagePath = cage;
    o.scheme = SubdivisionScheme::Bilinear;
    o.open.translate = {0, 0, z};
    o.close = o.open;
    o.material.color = o.material.closeColor = color;
    o.material.opacity = o.material.closeOpacity = opacity;
    o.material.unlit = true;
    return o;
}

SceneDesc quadScene() {
    SceneDesc scene;
    scene.path = "quads";
    scene.film = {24, 16, 4, 3};
    scene.camera.open = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}};
    scene.camera.close = scene.camera.open;
    scene.tessellation.factor = 2;
    scene.objects.push_back(quad(quadCage(), {0.2f, 0.4f, 0.6f}, 1.0f, 0.0f));
    return scene;
}

TEST(Resolve, OpaqueQuadFillingTheScreenGivesItsColourExactly) {
    const RenderResult r = renderScene(quadScene(), {});
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x) {
            const Vec3 c = r.frame.color.get(x, y);
            EXPECT_NEAR(c.x, 0.2f, 1e-6f);
            EXPECT_NEAR(c.y, 0.4f, 1e-6f);
            EXPECT_NEAR(c.z, 0.6f, 1e-6f);
            EXPECT_FLOAT_EQ(r.frame.coverage[std::size_t(y * 24 + x)], 1.0f);
            EXPECT_NEAR(r.frame.depth[std::size_t(y * 24 + x)], 5.0f, 1e-4f);
            EXPECT_EQ(r.frame.motionX[std::size_t(y * 24 + x)], 0.0f);
        }
}

TEST(Resolve, HalfTransparentLayerBlendsExactly) {
    SceneDesc scene = quadScene();
    scene.objects.push_back(quad(scene.objects[0].cagePath, {1.0f, 0.0f, 0.0f}, 0.5f, 1.0f));
    const RenderResult r = renderScene(scene, {});
    ASSERT_TRUE(r.effects.transparency);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x) {
            const Vec3 c = r.frame.color.get(x, y);
            EXPECT_NEAR(c.x, 0.5f * 1.0f + 0.5f * 0.2f, 1e-6f);
            EXPECT_NEAR(c.y, 0.5f * 0.0f + 0.5f * 0.4f, 1e-6f);
            EXPECT_NEAR(c.z, 0.5f * 0.0f + 0.5f * 0.6f, 1e-6f);
        }
    // Two layers: 0.25 green nearest, then 0.5 red, then the opaque quad.
    scene.objects.push_back(quad(scene.objects[0].cagePath, {0.0f, 1.0f, 0.0f}, 0.25f, 2.0f));
    const RenderResult two = renderScene(scene, {});
    const Vec3 red = 0.5f * Vec3(1, 0, 0) + 0.5f * Vec3(0.2f, 0.4f, 0.6f);
    const Vec3 expected = 0.25f * Vec3(0, 1, 0) + 0.75f * red;
    const Vec3 c = two.frame.color.get(5, 7);
    EXPECT_NEAR(c.x, expected.x, 1e-6f);
    EXPECT_NEAR(c.y, expected.y, 1e-6f);
    EXPECT_NEAR(c.z, expected.z, 1e-6f);
}

TEST(Resolve, TransparencyDoesNotDependOnPatchOrder) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/transparency.json"));
    scene.film = {64, 48, 8, 4};
    const RenderResult inOrder = renderScene(scene, {});
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        RenderOptions shuffled;
        shuffled.patchOrderSeed = seed;
        const RenderResult r = renderScene(scene, shuffled);
        EXPECT_EQ(r.frame.color.rgb, inOrder.frame.color.rgb) << "order seed " << seed;
    }
}

TEST(Resolve, LayerOverflowIsCountedAndKeepsTheNearest) {
    SceneDesc scene = quadScene();
    scene.objects.push_back(quad(scene.objects[0].cagePath, {1.0f, 0.0f, 0.0f}, 0.5f, 1.0f));
    scene.objects.push_back(quad(scene.objects[0].cagePath, {0.0f, 1.0f, 0.0f}, 0.5f, 2.0f));
    RenderOptions options;
    options.maxLayers = 1;
    CounterRegistry::instance().reset();
    const RenderResult r = renderScene(scene, options);
    EXPECT_EQ(CounterRegistry::instance().snapshot()[rasterCounters().transparentOverflow],
              24 * 16 * 4);
    // Only the nearest (green, at z = 2) is kept over the opaque quad.
    const Vec3 c = r.frame.color.get(3, 3);
    EXPECT_NEAR(c.x, 0.5f * 0.2f, 1e-6f);
    EXPECT_NEAR(c.y, 0.5f + 0.5f * 0.4f, 1e-6f);
}

TEST(Resolve, BoxAndGaussianFiltersAgainstHandComputedValues) {
    // 3 x 3 pixels, one sample each: only the centre pixel's sample is white.
    VisibilityBuffer layout(3, 3, 1, 100.0f);
    const SampleGenerator samples(9, 1, Effects{});
    std::vector<float> colors(9 * 3, 0.0f);
    for (int k = 0; k < 3; ++k) colors[layout.index(1, 1, 0) * 3 + std::size_t(k)] = 1.0f;
    ResolveOptions box;
    const Image b = filterSamples(colors, layout, samples, box);
    EXPECT_EQ(b.get(1, 1).x, 1.0f);
    EXPECT_EQ(b.get(0, 0).x, 0.0f);
    ResolveOptions gauss;
    gauss.filter = ResolveFilter::Gaussian;
    const Image g = filterSamples(colors, layout, samples, gauss);
    // Centre pixel: w(centre sample) / sum of w over the samples within 1.5 px of (1.5, 1.5).
    double numerator = 0, denominator = 0;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) {
            const Vec2 p = Vec2(float(x), float(y)) + samples.sample(x, y, 0).pixelOffset;
            const double r2 = double(glm::dot(p - Vec2(1.5f), p - Vec2(1.5f)));
            if (r2 > 1.5 * 1.5) continue;
            const double w = std::exp(-r2 / (2 * 0.5 * 0.5));
            denominator += w;
            if (x == 1 && y == 1) numerator = w;
        }
    EXPECT_NEAR(g.get(1, 1).x, numerator / denominator, 1e-6);
    EXPECT_GT(g.get(0, 1).x, 0.0f);  // the white sample reaches the neighbours
    EXPECT_LT(g.get(1, 1).x, 1.0f);
    // A constant image stays constant under both filters (weights normalised).
    std::vector<float> constant(9 * 3, 0.25f);
    EXPECT_NEAR(filterSamples(constant, layout, samples, gauss).get(2, 0).y, 0.25f, 1e-7f);
}

TEST(Resolve, PerPixelPrimitiveShadingReusesColours) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/static.json"));
    scene.film = {64, 48, 8, 1};
    CounterRegistry::instance().reset();
    renderScene(scene, {});
    const CounterValues perFragment = CounterRegistry::instance().snapshot();
    RenderOptions options;
    options.resolve.shadingRate = ShadingRate::PerPixelPrimitive;
    CounterRegistry::instance().reset();
    renderScene(scene, options);
    const CounterValues perPixel = CounterRegistry::instance().snapshot();
    const ShadingCounters& ps = shadingCounters();
    EXPECT_EQ(perFragment[ps.reused], 0);
    EXPECT_GT(perPixel[ps.reused], 0);
    EXPECT_EQ(perPixel[ps.invocations] + perPixel[ps.reused], perFragment[ps.invocations]);
}

// The box filter makes the AOVs and counts the shading work in its shading pass, the Gaussian in
// passes of their own: the same AOVs bit for bit, and per patch the same pixel-shader invocations,
// which add up to the PS counter, on one thread and on two, at both shading rates. The opaque
// torus moves too, so its hits have motion vectors.
TEST(Resolve, FusedBoxPassGivesTheAovsAndShadingWorkOfSeparatePasses) {
    SceneDesc scene = readSceneFile(test::sourcePath("scenes/transparency.json"));
    scene.film = {64, 48, 8, 5};
    scene.objects[0].close.translate += Vec3(0.5f, 0.0f, 0.0f);
    for (ShadingRate rate : {ShadingRate::PerFragment, ShadingRate::PerPixelPrimitive}) {
        std::vector<RenderResult> results;
        for (ResolveFilter filter : {ResolveFilter::Box, ResolveFilter::Gaussian})
            for (int threads : {1, 2}) {
                RenderOptions options;
                options.threads = threads;
                options.resolve.shadingRate = rate;
                options.resolve.filter = filter;
                CounterRegistry::instance().reset();
                results.push_back(renderScene(scene, options));
                const std::vector<double>& shaded = results.back().frame.shadedPerPatch;
                ASSERT_EQ(shaded.size(), results.back().patches);
                double total = 0;
                for (double n : shaded) total += n;
                EXPECT_GT(total, 0);
                EXPECT_EQ(std::int64_t(total),
                          CounterRegistry::instance().snapshot()[shadingCounters().invocations]);
            }
        const ResolvedFrame& box = results.front().frame;
        EXPECT_TRUE(
            std::any_of(box.motionX.begin(), box.motionX.end(), [](float m) { return m != 0.0f; }));
        for (const RenderResult& r : results) {
            EXPECT_EQ(r.frame.shadedPerPatch, box.shadedPerPatch);
            EXPECT_EQ(r.frame.depth, box.depth);
            EXPECT_EQ(r.frame.coverage, box.coverage);
            EXPECT_EQ(r.frame.motionX, box.motionX);
            EXPECT_EQ(r.frame.motionY, box.motionY);
        }
    }
}

// Nothing moves but the material changes over the shutter: samples need times, and each pixel is
// the material averaged over the shutter (stratified times: within a stratum's worth).
TEST(Resolve, MaterialThatChangesOverTheShutterInAStillScene) {
    SceneDesc scene = quadScene();
    scene.film.samplesPerPixel = 16;
    MaterialDesc& m = scene.objects[0].material;
    m.color = {1, 0, 0};
    m.closeColor = {0, 0, 1};
    const RenderResult colour = renderScene(scene, {});
    EXPECT_FALSE(colour.effects.motion);
    EXPECT_TRUE(colour.effects.shadingVaries);
    EXPECT_NE(describeMode(colour.effects).find("shading over time"), std::string::npos);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x) {
            EXPECT_NEAR(colour.frame.color.get(x, y).x, 0.5f, 1.0f / 16);
            EXPECT_NEAR(colour.frame.color.get(x, y).z, 0.5f, 1.0f / 16);
        }
    // Opacity falling from 1 to 0.1: on average 0.55 of the colour over the background.
    m.color = m.closeColor = {1, 1, 1};
    m.closeOpacity = 0.1f;
    const RenderResult fading = renderScene(scene, {});
    EXPECT_TRUE(fading.effects.transparency);
    const float expected = 0.55f * 1.0f + 0.45f * kBackground.x;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x) EXPECT_NEAR(fading.frame.color.get(x, y).x, expected, 0.06f);
    // Switched off with the rest of the shutter's time: the material at shutter open.
    RenderOptions still;
    still.overrides.disableMotion = true;
    const RenderResult off = renderScene(scene, still);
    EXPECT_FALSE(off.effects.timeSamples());
    EXPECT_NEAR(off.frame.color.get(3, 3).x, 1.0f, 1e-6f);
}

// A lit surface under a camera that swings round it is shaded with the camera of each sample's
// time, not with the nearer shutter end's.
TEST(Resolve, ShadingUsesTheCameraAtTheSampleTime) {
    SceneDesc scene = quadScene();
    scene.camera.close = {{5, 0, 0.5f}, {0, 0, 0}, {0, 1, 0}};
    scene.objects[0].material.unlit = false;
    const FrontEnd fe(scene);
    const Camera& camera = fe.camera();
    SurfaceAttributes a;
    a.normal = {0, 0, 1};
    a.color = {1, 1, 1};
    a.surfaceUV = {0.01f, 0.01f};
    const ShadingContext context{&fe, nullptr, nullptr, &camera};
    const float t = 0.3f;
    const CameraKey k{lerp(scene.camera.open.position, scene.camera.close.position, t),
                      lerp(scene.camera.open.lookAt, scene.camera.close.lookAt, t),
                      {0, 1, 0}};
    const Mat4 view = glm::lookAt(k.position, k.lookAt, k.up);
    EXPECT_LT(std::abs(camera.worldToCameraAt(t)[0][0] - view[0][0]), 1e-6f);
    Vec3 n = glm::normalize(Vec3(view * Vec4(a.normal, 0.0f)));
    if (n.z < 0) n = -n;
    const float lambert = std::max(0.0f, glm::dot(n, glm::normalize(Vec3(0.4f, 0.6f, 0.7f))));
    EXPECT_NEAR(shadeFragment(context, a, t).x, 0.15f + 0.85f * lambert, 1e-5f);
    EXPECT_GT(std::abs(shadeFragment(context, a, t).x - shadeFragment(context, a, 0.0f).x), 0.01f);
}

TEST(Resolve, ExrCarriesNamedAovChannels) {
    SceneDesc scene = quadScene();
    scene.objects[0].close.translate = {2.0f, 0.0f, 0.0f};  // moves right: positive motion.x
    const RenderResult r = renderScene(scene, {});
    const std::string path = test::temporaryDirectory() + "/aov.exr";
    writeExrWithAovs(r.frame, path);
    const std::vector<std::string> names = readChannelNames(path);
    EXPECT_EQ(names,
              (std::vector<std::string>{"R", "G", "B", "Z", "coverage", "motion.x", "motion.y"}));
    // 2 units at depth 5 with a 40-degree field of view over 16 pixels of height.
    const float pixelsPerUnit = 16.0f / (2.0f * 5.0f * std::tan(glm::radians(20.0f)));
    EXPECT_NEAR(r.frame.motionX[std::size_t(8 * 24 + 12)], 2.0f * pixelsPerUnit, 1e-3f);
    EXPECT_NEAR(r.frame.motionY[std::size_t(8 * 24 + 12)], 0.0f, 1e-4f);
}

// A transparent surface has motion vectors: a sample's motion is that of the surface contributing
// most to its colour (its opacity times what the surfaces in front let through; ties to the
// nearer), what a one-velocity-per-pixel reconstruction filter must blur the pixel with.
TEST(Resolve, MotionIsThatOfTheSurfaceThatDominatesTheSample) {
    // 2 units right at depth 4 (a quad at z = 1), over 16 pixels of a 40-degree height.
    const float motion = 2.0f * 16.0f / (2.0f * 4.0f * std::tan(glm::radians(20.0f)));
    const std::size_t centre = 8 * 24 + 12;
    for (const bool overOpaque : {true, false}) {
        for (const float opacity : {0.25f, 0.5f, 0.75f}) {
            SceneDesc scene = quadScene();
            ObjectDesc glass = quad(scene.objects[0].cagePath, {1, 0, 0}, opacity, 1.0f);
            glass.close.translate = {2.0f, 0.0f, 1.0f};
            if (overOpaque)
                scene.objects.push_back(glass);
            else
                scene.objects = {glass};
            const RenderResult r = renderScene(scene, {});
            // Over the still quad the glass dominates from 0.5 (ties to the nearer); over the
            // empty background, which has no motion, likewise.
            const float expected = opacity >= 0.5f ? motion : 0.0f;
            EXPECT_NEAR(r.frame.motionX[centre], expected, 1e-3f)
                << "opacity " << opacity << (overOpaque ? " over the quad" : " alone");
            EXPECT_NEAR(r.frame.motionY[centre], 0.0f, 1e-4f);
            // Depth stays the opaque hits' (none over the empty background).
            EXPECT_NEAR(r.frame.depth[centre], overOpaque ? 5.0f : 0.0f, 1e-4f);
        }
    }
}

}  // namespace
}  // namespace patchsim
