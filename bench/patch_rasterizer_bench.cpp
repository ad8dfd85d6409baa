// The patch rasterizer's visibility step (hierarchies, tile tests, rays) on the default scene,
// with its counters as user counters, and its sample test efficiency at three blur levels.

#include <benchmark/benchmark.h>

#include "core/counters.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "rasterizer/patent/frame_rasterizer.h"
#include "tessellator/front_end.h"

namespace {

using namespace patchsim;

struct Prepared {
    std::unique_ptr<FrontEnd> frontEnd;
    Effects effects;
    std::vector<MovingMesh> meshes;
};

Prepared prepare(const SceneDesc& scene) {
    Prepared p;
    p.frontEnd = std::make_unique<FrontEnd>(scene);
    p.effects = detectEffects(scene, p.frontEnd->geometryMoves(), p.frontEnd->camera().moves());
    FrontEndWorkspace ws = p.frontEnd->makeWorkspace();
    TessellatedPatch patch;
    p.meshes.resize(p.frontEnd->patchCount());
    for (std::size_t i = 0; i < p.meshes.size(); ++i) {
        p.frontEnd->tessellate(i, patch, ws);
        toMovingMesh(patch, p.frontEnd->camera(), p.effects.motion, int(i), true, p.meshes[i]);
    }
    return p;
}

void visibility(benchmark::State& state, const SceneDesc& scene) {
    const Prepared p = prepare(scene);
    const Camera& camera = p.frontEnd->camera();
    const SampleGenerator samples(scene.film.seed, scene.film.samplesPerPixel, p.effects);
    const LensModel lens{p.effects.defocus ? scene.lens.apertureRadius : 0.0f,
                         scene.lens.focusDistance};
    const PatchRasterizer rasterizer(camera, lens, samples, p.effects, scene.rasterizer);
    RasterWork total;
    std::int64_t frames = 0;
    FrameRasterOptions singleThread;
    singleThread.threads = 1;
    for (auto _ : state) {
        VisibilityBuffer buffer(scene.film.width, scene.film.height, scene.film.samplesPerPixel,
                                camera.farPlane());
        const FrameRasterWork work =
            rasterizeFrame(p.meshes, rasterizer, {&buffer, nullptr, nullptr, 0}, singleThread);
        for (std::size_t i = 0; i < p.meshes.size(); ++i) total.add(work.patch(i));
        benchmark::DoNotOptimize(buffer.records().data());
        ++frames;
    }
    const auto perFrame = [&](std::int64_t count) { return double(count) / double(frames); };
    state.counters["STE"] = perFrame(total.visibilitySamples) / perFrame(total.samplesTested);
    state.counters["samples tested"] = perFrame(total.samplesTested);
    state.counters["rays"] = perFrame(total.raysCast);
    state.counters["ray-box/ray"] = perFrame(total.rayBoxTests) / perFrame(total.raysCast);
    state.counters["ray-tri/ray"] = perFrame(total.rayTriangleTests) / perFrame(total.raysCast);
    state.counters["tiles"] = perFrame(total.tilesInBounds);
    state.counters["plane tests"] = perFrame(total.planeTests);
    state.counters["groups"] = perFrame(total.groups);
    state.counters["patches"] = perFrame(total.patches);
    state.counters["hierarchy bytes/patch"] =
        perFrame(total.hierarchyBytes) / perFrame(total.patches);
    state.counters["peak hierarchy bytes"] = double(total.peakHierarchyBytes);
    state.counters["rays/s"] =
        benchmark::Counter(double(total.raysCast), benchmark::Counter::kIsRate);
}

void defaultScene(benchmark::State& state) {
    visibility(state, patchsim::defaultScene());
}
BENCHMARK(defaultScene)->Unit(benchmark::kMillisecond);

// The default scene with its motion scaled by 0.25, 1 and 4 (range(0) is the scale x 100).
void motionBlurLevel(benchmark::State& state) {
    SceneDesc scene = patchsim::defaultScene();
    const float scale = float(state.range(0)) / 100.0f;
    for (ObjectDesc& o : scene.objects) {
        o.close.translate = o.open.translate + scale * (o.close.translate - o.open.translate);
        o.close.rotateDegrees =
            o.open.rotateDegrees + scale * (o.close.rotateDegrees - o.open.rotateDegrees);
    }
    scene.lens.apertureRadius = 0;
    visibility(state, scene);
}
BENCHMARK(motionBlurLevel)->Arg(25)->Arg(100)->Arg(400)->Unit(benchmark::kMillisecond);

// Defocus only, aperture radius 0.03, 0.12 and 0.48 (range(0) is the radius x 100).
void defocusBlurLevel(benchmark::State& state) {
    SceneDesc scene = patchsim::defaultScene();
    for (ObjectDesc& o : scene.objects) o.close = o.open;
    scene.lens.apertureRadius = float(state.range(0)) / 100.0f;
    visibility(state, scene);
}
BENCHMARK(defocusBlurLevel)->Arg(3)->Arg(12)->Arg(48)->Unit(benchmark::kMillisecond);

// The patent's three bounds spaces for the tile tests (range(0): 0 3D, 1 2DH, 2 2D), the default
// scene; the samples are the same in all three (tests), the work is not.
void boundsSpace(benchmark::State& state) {
    SceneDesc scene = patchsim::defaultScene();
    scene.rasterizer.boundsSpace = BoundsSpace(state.range(0));
    state.SetLabel(boundsSpaceName(scene.rasterizer.boundsSpace));
    visibility(state, scene);
}
BENCHMARK(boundsSpace)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

// Small patches merged into shared hierarchies (range(0): merge_triangles_below; 0 never), on the
// default scene at tessellation factor 2, where every patch is a handful of triangles.
void mergeSmallPatches(benchmark::State& state) {
    SceneDesc scene = patchsim::defaultScene();
    scene.tessellation.targetEdgePixels = 0;  // fixed factor 2: 8 triangles per quad patch
    scene.tessellation.factor = 2.0f;
    scene.rasterizer.mergeTrianglesBelow = int(state.range(0));
    visibility(state, scene);
}
BENCHMARK(mergeSmallPatches)->Arg(0)->Arg(32)->Arg(256)->Unit(benchmark::kMillisecond);

// The hierarchy's boxes stored in a narrower format (issue 35; range(0): 0 fp32, 1 fp16, 2 bf16,
// 3 fixed16.8): the emulation's cost (rounding every node after its build) beside the extra
// tests the wider boxes let through. fp32 skips the rounding: its row is the default scene's.
void nodeFormat(benchmark::State& state) {
    SceneDesc scene = patchsim::defaultScene();
    const NumberFormat formats[] = {NumberFormat::fp32(), NumberFormat::fp16(),
                                    NumberFormat::bf16(), NumberFormat::fixed(16, 8)};
    scene.rasterizer.nodeFormat = formats[state.range(0)];
    state.SetLabel(formatName(scene.rasterizer.nodeFormat));
    visibility(state, scene);
}
BENCHMARK(nodeFormat)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

// Hierarchy size against the on-chip scratch budget (16 KiB in pipeline/hw/default.json): the
// default scene at a fixed tessellation factor (range(0)), patches split into groups as today.
void hierarchyBytes(benchmark::State& state) {
    SceneDesc scene = patchsim::defaultScene();
    scene.tessellation.targetEdgePixels = 0;
    scene.tessellation.factor = float(state.range(0));
    visibility(state, scene);
}
BENCHMARK(hierarchyBytes)->Arg(8)->Arg(16)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

// Cost growth: the default scene at 160x120, 4 spp and factor 8 (range(0) = 0), then with twice the
// samples per pixel (1), twice the pixels (2: 226x170) and twice the patches (3: every object
// twice, in place). Linear cost doubles the time of the base in each.
void costGrowth(benchmark::State& state) {
    SceneDesc scene = patchsim::defaultScene();
    scene.film.width = 160;
    scene.film.height = 120;
    scene.film.samplesPerPixel = 4;
    scene.tessellation.targetEdgePixels = 0;  // a fixed factor: the same triangles at any size
    scene.tessellation.factor = 8.0f;
    switch (state.range(0)) {
        case 1:
            scene.film.samplesPerPixel = 8;
            break;
        case 2:
            scene.film.width = 226;
            scene.film.height = 170;
            break;
        case 3: {
            const std::vector<ObjectDesc> objects = scene.objects;
            scene.objects.insert(scene.objects.end(), objects.begin(), objects.end());
            break;
        }
        default:
            break;
    }
    constexpr const char* kLabels[] = {"base", "2x spp", "2x pixels", "2x patches"};
    state.SetLabel(kLabels[state.range(0)]);
    visibility(state, scene);
}
BENCHMARK(costGrowth)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

}  // namespace
