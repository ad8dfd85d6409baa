// A whole render in one process, as `patchsim render` does it without reading the scene file or
// writing images: front end, visibility, shading and resolve, on 1 and 2 threads (range(0)).
// Process start-up, the image module's load and file output are not in it; see
// docs/PERFORMANCE.md for the whole command timed from outside. Also the sampler alone: the
// default film's samples (320 x 240 x 16, time and lens) on one thread, which a render makes
// tile by tile inside its visibility step.

#include <benchmark/benchmark.h>

#include "core/counters.h"
#include "core/samples.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"

namespace {

using namespace patchsim;

void wholeRender(benchmark::State& state) {
    const SceneDesc scene = patchsim::defaultScene();
    RenderOptions options;
    options.threads = int(state.range(0));
    double frontEnd = 0, visibility = 0, shading = 0;
    for (auto _ : state) {
        CounterRegistry::instance().reset();
        const RenderResult r = renderScene(scene, options);
        frontEnd += r.frontEndSeconds;
        visibility += r.visibilitySeconds;
        shading += r.shadingSeconds;
        benchmark::DoNotOptimize(r.frame.color.rgb.data());
    }
    const auto perFrame = [&](double s) { return 1e3 * s / double(state.iterations()); };
    state.counters["front end ms"] = perFrame(frontEnd);
    state.counters["visibility ms"] = perFrame(visibility);
    state.counters["shading ms"] = perFrame(shading);
}
void defaultFilmSamples(benchmark::State& state) {
    const SceneDesc scene = patchsim::defaultScene();
    Effects effects;
    effects.motion = effects.defocus = true;
    const SampleGenerator generator(scene.film.seed, scene.film.samplesPerPixel, effects);
    for (auto _ : state) {
        const SampleTable table(generator, scene.film.width, scene.film.height, 1);
        benchmark::DoNotOptimize(table.pixel(0, 0));
    }
}
BENCHMARK(defaultFilmSamples)->Unit(benchmark::kMillisecond)->UseRealTime();

// Wall time per frame; the CPU column is every thread's time (MeasureProcessCPUTime), so CPU over
// wall on two threads shows how busy the second core was.
BENCHMARK(wholeRender)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace
