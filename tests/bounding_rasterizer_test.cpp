#include "rasterizer/baselines/bounding_rasterizer.h"

#include <gtest/gtest.h>

#include <tuple>

#include "core/counters.h"
#include "core/error.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "tests/render_compare.h"
#include "tests/test_paths.h"

namespace patchsim {
namespace {

RenderResult renderWith(SceneDesc scene, const VisibilityMethod* method, int strata = 0,
                        TriangleBound bound = TriangleBound::Hull) {
    RenderOptions options;
    options.method = method;
    options.timeStrata = strata;
    options.triangleBound = bound;
    options.threads = 2;
    return renderScene(scene, options);
}

SceneDesc small(const std::string& path) {
    SceneDesc scene = readSceneFile(test::sourcePath(path));
    scene.film.width = 48;
    scene.film.height = 36;
    scene.film.samplesPerPixel = 4;
    return scene;
}

// The exact baselines give the patch method's visibility, sample for sample (and so the
// reference's), on every shipped scene: opaque, moving, defocused and transparent.
TEST(BoundingRasterizer, TriangleBBoxAndIntervalEqualThePatchMethodSampleForSample) {
    for (const std::string& path : test::sceneFiles()) {
        const SceneDesc scene = small(path.substr(test::sourcePath("").size()));
        const RenderResult patch = renderWith(scene, &methodNamed("patch"));
        const VisibilityMethod* bbox = &methodNamed("triangle-bbox");
        const VisibilityMethod* interval = &methodNamed("interval");
        for (auto [method, strata, bound] :
             {std::tuple{bbox, 0, TriangleBound::Hull}, std::tuple{bbox, 0, TriangleBound::Box},
              std::tuple{bbox, 0, TriangleBound::OrientedBox},
              std::tuple{interval, 0, TriangleBound::Hull},
              std::tuple{interval, 1, TriangleBound::Hull},
              std::tuple{interval, 7, TriangleBound::Hull}}) {
            const test::Comparison c =
                test::compare(patch, renderWith(scene, method, strata, bound));
            EXPECT_GT(c.hits, 0u) << path;
            EXPECT_EQ(c.mismatches, 0u) << path << " " << method->name() << " K=" << strata << " "
                                        << triangleBoundName(bound) << ": " << c.mismatches
                                        << " of " << c.samples << " samples differ";
        }
    }
}

// K = 0 is one stratum per sample of a pixel (Fatahalian et al.'s setting). The sampler
// stratifies time per pixel, so every pixel then has exactly one sample in each stratum, and
// each sample is tested only against its own stratum's bounds: fewer samples than at K = 4, the
// same visibility.
TEST(BoundingRasterizer, IntervalDefaultsToOneStratumPerSample) {
    SceneDesc scene = small("scenes/motion.json");
    scene.film.samplesPerPixel = 16;
    const Effects effects = detectEffects(scene, true, false);
    ASSERT_TRUE(effects.motion);
    const SampleGenerator samples(scene.film.seed, 16, effects);
    for (int y = 0; y < scene.film.height; ++y)
        for (int x = 0; x < scene.film.width; ++x) {
            int perStratum[16] = {};
            for (int s = 0; s < 16; ++s)
                ++perStratum[std::min(int(samples.sample(x, y, s).time * 16.0f), 15)];
            for (int k = 0; k < 16; ++k)
                ASSERT_EQ(perStratum[k], 1) << "pixel " << x << "," << y << " stratum " << k;
        }

    const VisibilityMethod* interval = &methodNamed("interval");
    auto run = [&](int strata, std::int64_t& tested) {
        CounterRegistry::instance().reset();
        RenderResult result = renderWith(scene, interval, strata);
        const CounterValues c = CounterRegistry::instance().snapshot();
        EXPECT_EQ(c[intervalTimeStrataCounter()], strata == 0 ? 16 : strata);
        tested = c.byName("IV/Samples tested");
        return result;
    };
    std::int64_t testedAtSpp = 0, testedAtFour = 0;
    const RenderResult atSpp = run(0, testedAtSpp);
    const RenderResult atFour = run(4, testedAtFour);
    EXPECT_LT(testedAtSpp, testedAtFour);
    const test::Comparison c = test::compare(renderWith(scene, &methodNamed("patch")), atSpp);
    EXPECT_GT(c.hits, 0u);
    EXPECT_EQ(c.mismatches, 0u) << c.mismatches << " of " << c.samples << " samples differ";
    EXPECT_EQ(test::compare(atFour, atSpp).mismatches, 0u);
}

// Without motion every stratum's bounds are the same: one stratum, whatever K asks for, so the
// interval method sets each triangle up once and tests what triangle-bbox's box does.
TEST(BoundingRasterizer, IntervalUsesOneStratumWhenNothingMoves) {
    const SceneDesc scene = small("scenes/static.json");
    for (int strata : {0, 8}) {
        CounterRegistry::instance().reset();
        renderWith(scene, &methodNamed("interval"), strata);
        renderWith(scene, &methodNamed("triangle-bbox"), strata, TriangleBound::Box);
        const CounterValues c = CounterRegistry::instance().snapshot();
        EXPECT_EQ(c[intervalTimeStrataCounter()], 1);
        EXPECT_EQ(c.byName("IV/Triangle setups"), c.byName("BB/Triangle setups"));
        EXPECT_EQ(c.byName("IV/Samples tested"), c.byName("BB/Samples tested"));
    }
    EXPECT_EQ(intervalTimeStrata(0, 16, true), 16);
    EXPECT_EQ(intervalTimeStrata(5, 16, true), 5);
    EXPECT_EQ(intervalTimeStrata(5, 16, false), 1);
}

// Interleaved is exact for its own samples: the patch method on the same interleaved sample set
// sees the same; only the sample set (one time per index in every pixel) makes it approximate.
TEST(BoundingRasterizer, InterleavedIsExactForItsOwnSamples) {
    SceneDesc scene = small("scenes/motion_defocus.json");
    const RenderResult interleaved = renderWith(scene, &methodNamed("interleaved"));
    scene.film.sampler = SamplePattern::Interleaved;
    const RenderResult patch = renderWith(scene, &methodNamed("patch"));
    const test::Comparison c = test::compare(patch, interleaved);
    EXPECT_GT(c.hits, 0u);
    EXPECT_EQ(c.mismatches, 0u);
    // The same time in every pixel for a sample index: strobing.
    for (int s = 0; s < 4; ++s) {
        const VisibilityRecord& a = interleaved.visibility->at(10, 10, s);
        const VisibilityRecord& b = interleaved.visibility->at(30, 20, s);
        if (a.hit() && b.hit()) {
            EXPECT_EQ(a.time, b.time);
        }
    }
}

// An accumulation buffer renders the frame once per sample index: its front end is charged once
// per pass (at the pass's one time, so half the two-ended kinds), and every pass's image is
// added into the accumulation buffer. The single-pass methods pay the front end once.
TEST(BoundingRasterizer, InterleavedPaysTheFrontEndAndAFullFramePerPass) {
    auto total = [](const RenderResult& r, Op op) {
        double sum = 0;
        for (const PatchOps& ops : r.patchOps) sum += ops[op];
        return sum;
    };
    SceneDesc scene = small("scenes/motion_defocus.json");
    const RenderResult once = renderWith(scene, &methodNamed("triangle-bbox"));
    ASSERT_GT(total(once, Op::Evaluations), 0);
    for (int spp : {1, 4, 9}) {
        scene.film.samplesPerPixel = spp;
        CounterRegistry::instance().reset();
        const RenderResult passes = renderWith(scene, &methodNamed("interleaved"));
        const CounterValues c = CounterRegistry::instance().snapshot();
        EXPECT_EQ(c.byName("IL/Passes"), spp);
        for (Op op :
             {Op::Patches, Op::EdgeFactors, Op::DomainPoints, Op::Triangles, Op::Evaluations})
            EXPECT_DOUBLE_EQ(total(passes, op), spp * total(once, op)) << opName(op) << " " << spp;
        for (Op op : {Op::ControlPoints, Op::StencilApplications})
            EXPECT_DOUBLE_EQ(total(passes, op), 0.5 * spp * total(once, op))
                << opName(op) << " " << spp;
        const double pixels = double(spp) * scene.film.width * scene.film.height;
        EXPECT_EQ(c.byName("IL/Accumulated pixels"), std::int64_t(pixels));
        EXPECT_DOUBLE_EQ(total(passes, Op::PostSamples), pixels);
        EXPECT_EQ(total(once, Op::PostSamples), 0);
    }
}

// Tighter bounds test fewer samples for the same visibility: interval's boxes per stratum below
// triangle-bbox's one box; and the patch method's advantage over that box grows with the motion.
TEST(BoundingRasterizer, TighterBoundsTestFewerSamplesAndThePatchMethodGainsWithMotion) {
    SceneDesc base = small("scenes/motion.json");
    base.objects.resize(1);  // the torus sliding across the screen
    base.film = {160, 120, 2, 1};
    auto tested = [&](const SceneDesc& scene, const VisibilityMethod* m) {
        CounterRegistry::instance().reset();
        renderWith(scene, m, 0, TriangleBound::Box);
        const CounterValues c = CounterRegistry::instance().snapshot();
        return double(c[m->sampleTestEfficiency().denominator]);
    };
    double previousRatio = 0;
    for (float scale : {0.25f, 1.0f, 4.0f}) {
        SceneDesc scene = base;
        for (ObjectDesc& o : scene.objects)
            o.close.translate = o.open.translate + scale * (o.close.translate - o.open.translate);
        const double bbox = tested(scene, &methodNamed("triangle-bbox"));
        const double interval = tested(scene, &methodNamed("interval"));
        const double patch = tested(scene, &methodNamed("patch"));
        EXPECT_LT(interval, bbox) << scale;
        const double ratio = bbox / patch;
        EXPECT_GT(ratio, previousRatio)
            << "motion x" << scale << ": bbox " << bbox << ", patch " << patch;
        previousRatio = ratio;
    }
    EXPECT_GT(previousRatio, 10.0) << "at four times the motion";
}

// The hull bound (McGuire et al.) visits the pixels the hull reaches, a subset of the box's, and
// ray-tests only the samples inside it: on every shipped scene with motion or defocus its visits
// are at most the box's tests, its image is the same, and it ray-tests under two thirds. The
// oriented box ray-tests no fewer than the hull and no more than the box. A static frame takes
// neither: every bound is the pixel box of its edge-function test (screen_triangle.h).
TEST(BoundingRasterizer, TheHullBoundRayTestsASubsetOfTheBoxSamples) {
    const VisibilityMethod* bbox = &methodNamed("triangle-bbox");
    for (const std::string& path : test::sceneFiles()) {
        const SceneDesc scene = small(path.substr(test::sourcePath("").size()));
        CounterRegistry::instance().reset();
        renderWith(scene, bbox, 0, TriangleBound::Box);
        const CounterValues box = CounterRegistry::instance().snapshot();
        if (box.byName("BB/Edge tests") > 0) {
            EXPECT_EQ(box.byName("BB/Ray-triangle tests"), 0) << path << ": a static frame";
            EXPECT_EQ(box.byName("BB/Samples tested"), box.byName("BB/Edge tests")) << path;
            // Its set-ups are edge-function set-ups (edge_setups), one per triangle with a screen
            // form, not bounds over a shutter span.
            EXPECT_GT(box.byName("BB/Screen triangle setups"), 0) << path;
            EXPECT_EQ(box.byName("BB/Triangle setups"), 0) << path;
            continue;
        }
        if (box.byName("BB/Lens edge tests") > 0) {
            EXPECT_EQ(box.byName("BB/Ray-triangle tests"), 0) << path << ": a defocus-only frame";
            EXPECT_EQ(box.byName("BB/Samples tested"), box.byName("BB/Lens edge tests")) << path;
            // Its set-ups are the lens test's (lens_edge_setups), one per triangle; the hull of
            // the vertices' circles of confusion narrows each row's pixels, which are then tested
            // whole (no per-sample hull test), with the same samples found.
            EXPECT_EQ(box.byName("BB/Lens triangle setups"), box.byName("TS/Triangles"))
                << path << ": one set-up per triangle, whatever the bands";
            EXPECT_EQ(box.byName("BB/Triangle setups"), 0) << path;
            CounterRegistry::instance().reset();
            renderWith(scene, bbox, 0, TriangleBound::Hull);
            const CounterValues hull = CounterRegistry::instance().snapshot();
            EXPECT_EQ(hull.byName("BB/Samples outside the hull"), 0) << path;
            EXPECT_LT(hull.byName("BB/Lens edge tests"), box.byName("BB/Lens edge tests")) << path;
            EXPECT_EQ(hull.byName("BB/Visibility samples"), box.byName("BB/Visibility samples"))
                << path;
            continue;
        }
        CounterRegistry::instance().reset();
        renderWith(scene, bbox, 0, TriangleBound::Hull);
        const CounterValues hull = CounterRegistry::instance().snapshot();
        EXPECT_EQ(box.byName("BB/Samples outside the hull"), 0) << path;
        EXPECT_LE(hull.byName("BB/Samples tested") + hull.byName("BB/Samples outside the hull"),
                  box.byName("BB/Samples tested"))
            << path;
        EXPECT_EQ(box.byName("BB/Visibility samples"), hull.byName("BB/Visibility samples"))
            << path;
        EXPECT_GT(hull.byName("BB/Samples outside the hull"), 0) << path;
        // The least-area rectangle holding the hull: between the two, with the same image.
        CounterRegistry::instance().reset();
        renderWith(scene, bbox, 0, TriangleBound::OrientedBox);
        const CounterValues oriented = CounterRegistry::instance().snapshot();
        EXPECT_LE(hull.byName("BB/Samples tested"), oriented.byName("BB/Samples tested")) << path;
        EXPECT_LE(oriented.byName("BB/Samples tested"), box.byName("BB/Samples tested")) << path;
        EXPECT_EQ(oriented.byName("BB/Visibility samples"), hull.byName("BB/Visibility samples"))
            << path;
        if (path.find("motion") != std::string::npos || path.find("defocus") != std::string::npos) {
            EXPECT_LT(3 * hull.byName("BB/Samples tested"), 2 * box.byName("BB/Samples tested"))
                << path << ": the hull ray-tests under two thirds of the box's samples";
        }
    }
}

// A triangle nearer than the near plane at both shutter ends is so at every time (linear motion,
// a convex half-space): culled after one setup, no sample tested, where its bounds used to be the
// whole screen. One that comes out in front during the shutter is kept, and the image is still
// the patch method's sample for sample.
TEST(BoundingRasterizer, TrianglesBehindTheCameraAtBothEndsAreCulledWithoutATest) {
    SceneDesc scene = small("scenes/motion.json");  // the camera at z = 6, looking down -z
    scene.tessellation.targetEdgePixels = 0;
    scene.tessellation.factor = 4;
    SceneDesc behind = scene;
    for (ObjectDesc& o : behind.objects) {
        o.open.translate.z += 20;
        o.close.translate.z += 20;
    }
    SceneDesc crossing = behind;  // the torus comes from behind the camera to its place
    crossing.objects[0].close.translate = scene.objects[0].close.translate;
    SceneDesc crossingInterleaved = crossing;
    crossingInterleaved.film.sampler = SamplePattern::Interleaved;
    const RenderResult patch = renderWith(crossing, &methodNamed("patch"));
    const RenderResult patchInterleaved = renderWith(crossingInterleaved, &methodNamed("patch"));
    for (const auto& [name, prefix] :
         {std::pair{"triangle-bbox", "BB/"}, std::pair{"interval", "IV/"},
          std::pair{"interleaved", "IL/"}}) {
        const VisibilityMethod* method = &methodNamed(name);
        const std::string p = prefix;
        CounterRegistry::instance().reset();
        renderWith(behind, method);
        CounterValues c = CounterRegistry::instance().snapshot();
        EXPECT_EQ(c.byName(p + "Samples tested"), 0) << name;
        EXPECT_EQ(c.byName(p + "Full-screen bounds"), 0) << name;
        EXPECT_GT(c.byName(p + "Triangle setups"), 0) << name;
        EXPECT_EQ(c.byName(p + "Triangles culled behind the camera"),
                  c.byName(p + "Triangle setups"))
            << name << ": one setup per culled triangle";

        CounterRegistry::instance().reset();
        const RenderResult result = renderWith(crossing, method);
        c = CounterRegistry::instance().snapshot();
        const std::int64_t culled = c.byName(p + "Triangles culled behind the camera");
        EXPECT_GT(culled, 0) << name << ": the icosahedron";
        EXPECT_GT(c.byName(p + "Samples tested"), 0) << name << ": the torus";
        const test::Comparison cmp =
            test::compare(method == &methodNamed("interleaved") ? patchInterleaved : patch, result);
        EXPECT_GT(cmp.hits, 0u) << name;
        EXPECT_EQ(cmp.mismatches, 0u) << name;
    }
}

// The samples and rays each band prepares ahead (61 bytes a sample with a static frame's sub-pixel
// positions; 65 with the interval method's stratum order) count against the memory budget with the
// film: a render whose film fits but whose bands' samples do not is refused before it starts,
// naming film.spp.
TEST(BoundingRasterizer, TheBandsPreparedSamplesCountAgainstTheMemoryBudget) {
    const SceneDesc scene = small("scenes/motion.json");  // 48 x 36 at 4 spp: 16 bands of 2-3 rows
    // Per sample 13 floats, the shear axes' byte and two floats of sub-pixel position (and the
    // interval method's two stratum entries); per band one row's candidate list: an index and a ray
    // end per candidate, padded by a vector of 16, and a 16-byte hit.
    const std::uint64_t rowSamples = 48u * 4u;
    const std::uint64_t candidates = (rowSamples + 16u) * 8u + rowSamples * 16u;
    EXPECT_EQ(boundingBandScratchBytes(48, 36, 4, Bounding::TriangleBBox, 2),
              2u * (3u * rowSamples * 61u + candidates));
    EXPECT_EQ(boundingBandScratchBytes(48, 36, 4, Bounding::Interval, 64),
              16u * (3u * rowSamples * 65u + candidates))
        << "no more bands at once than there are bands";
    for (const char* name : {"triangle-bbox", "interval", "interleaved"}) {
        const VisibilityMethod& method = methodNamed(name);
        const Bounding bounding =
            std::string(name) == "interval" ? Bounding::Interval : Bounding::TriangleBBox;
        RenderOptions options;
        options.method = &method;
        options.memoryBudgetBytes =
            filmBytes(scene.film) + boundingBandScratchBytes(48, 36, 4, bounding, 2);
        EXPECT_NO_THROW(method.check(scene, options, 2)) << name;
        options.memoryBudgetBytes -= 1;
        try {
            method.check(scene, options, 2);
            ADD_FAILURE() << name << ": one byte over the budget was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("film.spp"), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace patchsim
