#include "tests/render_compare.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

#include "core/counters.h"

namespace patchsim::test {

namespace {

std::vector<std::tuple<float, int, std::uint32_t>> layerList(const TransparentLayers* layers,
                                                             std::size_t i) {
    std::vector<std::tuple<float, int, std::uint32_t>> list;
    if (!layers) return list;
    for (int k = 0; k < layers->count(i); ++k) {
        const VisibilityRecord& r = layers->layers(i)[k].record;
        list.emplace_back(r.depth, r.patch, r.triangle);
    }
    std::sort(list.begin(), list.end());
    return list;
}

void expectFinite(const RenderResult& r, const std::string& what) {
    for (float v : r.frame.color.rgb) ASSERT_TRUE(std::isfinite(v)) << what << ": colour";
    for (const auto* aov : {&r.frame.depth, &r.frame.coverage, &r.frame.motionX, &r.frame.motionY})
        for (float v : *aov) ASSERT_TRUE(std::isfinite(v)) << what << ": AOV";
    for (const VisibilityRecord& rec : r.visibility->records()) {
        if (!rec.hit()) continue;
        ASSERT_TRUE(std::isfinite(rec.depth) && std::isfinite(rec.b1) && std::isfinite(rec.b2))
            << what;
    }
}

}  // namespace

Comparison compare(const RenderResult& a, const RenderResult& b) {
    Comparison c;
    for (std::size_t i = 0; i < a.visibility->records().size(); ++i) {
        const VisibilityRecord& x = a.visibility->records()[i];
        const VisibilityRecord& y = b.visibility->records()[i];
        ++c.samples;
        c.hits += x.hit();
        if (!x.hit() && y.hit()) ++c.falseRejects;
        if (x.patch != y.patch || (x.hit() && (x.triangle != y.triangle || x.depth != y.depth ||
                                               x.b1 != y.b1 || x.b2 != y.b2)))
            ++c.mismatches;
        else if (layerList(a.transparent.get(), i) != layerList(b.transparent.get(), i))
            ++c.mismatches;
    }
    return c;
}

Comparison expectStableAndExact(const SceneDesc& scene, const std::string& what) {
    auto render = [&](const VisibilityMethod* method, int threads, CounterValues* counters) {
        RenderOptions options;
        options.method = method;
        options.threads = threads;
        CounterRegistry::instance().reset();
        RenderResult r = renderScene(scene, options);
        if (counters) *counters = CounterRegistry::instance().snapshot();
        return r;
    };
    CounterValues countersOne, countersTwo, countersAgain;
    const RenderResult one = render(&methodNamed("patch"), 1, &countersOne);
    const RenderResult two = render(&methodNamed("patch"), 2, &countersTwo);
    const RenderResult again = render(&methodNamed("patch"), 2, &countersAgain);
    const RenderResult reference = render(&methodNamed("reference"), 2, nullptr);
    expectFinite(one, what);
    expectFinite(reference, what);
    const Comparison c = compare(one, reference);
    EXPECT_EQ(c.falseRejects, 0u) << what
                                  << ": samples the reference hits and the patch method missed";
    EXPECT_EQ(c.mismatches, 0u) << what << ": " << c.mismatches << " of " << c.samples
                                << " samples differ";
    EXPECT_EQ(one.frame.color.rgb, two.frame.color.rgb) << what << ": 1 and 2 threads differ";
    EXPECT_EQ(countersOne.raw(), countersTwo.raw())
        << what << ": counters differ between 1 and 2 threads";
    EXPECT_EQ(two.frame.color.rgb, again.frame.color.rgb) << what << ": runs differ";
    EXPECT_EQ(countersTwo.raw(), countersAgain.raw()) << what << ": counters differ between runs";
    // The hierarchy's boxes stored in narrower formats, rounded outward, and (in the 3D bounds
    // space) the tile planes computed in them with their error bounds (issue 35): the same
    // samples, in every format, fixed point's range exceeded included.
    for (const NumberFormat format :
         {NumberFormat::fp16(), NumberFormat::bf16(), NumberFormat::fixed(16, 8)}) {
        SceneDesc narrow = scene;
        narrow.rasterizer.nodeFormat = format;
        const bool planes = scene.rasterizer.boundsSpace == BoundsSpace::Camera3D;
        const bool screen = scene.rasterizer.boundsSpace == BoundsSpace::Screen2D;
        if (planes) narrow.rasterizer.planeFormat = format;
        if (screen) narrow.rasterizer.screenBoundsFormat = format;
        RenderOptions options;
        options.method = &methodNamed("patch");
        options.threads = 2;
        const RenderResult r = renderScene(narrow, options);
        const std::string in = what + ", nodes" +
                               (planes   ? " and planes"
                                : screen ? " and screen bounds"
                                         : "") +
                               " in " + formatName(format);
        expectFinite(r, in);
        const Comparison f = compare(r, reference);
        EXPECT_EQ(f.falseRejects, 0u) << in << ": samples the reference hits and it missed";
        EXPECT_EQ(f.mismatches, 0u) << in << ": " << f.mismatches << " samples differ";
    }
    return c;
}

namespace {

RenderResult renderOnTwoThreads(const SceneDesc& scene, const char* method) {
    RenderOptions options;
    options.threads = 2;
    options.method = &methodNamed(method);
    return renderScene(scene, options);
}

// The patch method's render of `scene` is finite and gives `reference`'s samples.
Comparison expectPatchEquals(const SceneDesc& scene, const RenderResult& reference,
                             const std::string& in) {
    const RenderResult patch = renderOnTwoThreads(scene, "patch");
    expectFinite(patch, in);
    const Comparison c = compare(patch, reference);
    EXPECT_EQ(c.falseRejects, 0u) << in << ": samples the reference hits and it missed";
    EXPECT_EQ(c.mismatches, 0u) << in << ": " << c.mismatches << " samples differ";
    return c;
}

}  // namespace

std::array<std::size_t, 3> expectNarrowRayTestsExact(const SceneDesc& scene,
                                                     const std::string& what) {
    const NumberFormat formats[] = {NumberFormat::fp16(), NumberFormat::bf16(),
                                    NumberFormat::fixed(16, 8)};
    const RenderResult fp32Reference = renderOnTwoThreads(scene, "reference");
    for (const NumberFormat format : formats) {
        SceneDesc boxes = scene;
        boxes.rasterizer.rayBoxFormat = format;
        expectPatchEquals(boxes, fp32Reference, what + ", ray-box tests in " + formatName(format));
    }
    std::array<std::size_t, 3> hits{};
    for (std::size_t k = 0; k < hits.size(); ++k) {
        SceneDesc narrow = scene;
        narrow.rasterizer.triangleFormat = formats[k];
        hits[k] = expectPatchEquals(narrow, renderOnTwoThreads(narrow, "reference"),
                                    what + ", triangle tests in " + formatName(formats[k]))
                      .hits;
    }
    return hits;
}

}  // namespace patchsim::test
