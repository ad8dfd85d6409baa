// A whole render in one process, as `patchsim render` does it without reading the scene file or
// writing images: front end, visibility, shading and resolve, on 1 and 2 threads (range(0)).
// Process start-up (loading OpenImageIO's shared libraries) and file output are not in it; see
// docs/PERFORMANCE.md for the whole command timed from outside.

#include <benchmark/benchmark.h>

#include "pipeline/core/counters.h"
#include "pipeline/core/scene_reader.h"
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
BENCHMARK(wholeRender)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
