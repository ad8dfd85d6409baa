// Front-end throughput: the D3D11 tessellator alone, HS + TS + DS per patch on a scene, and the
// set-up of a scene's objects (cages read, vertex stage, OpenSubdiv topology and Bfr surfaces).

#include <benchmark/benchmark.h>

#include "core/scene_reader.h"
#include "tessellator/front_end.h"

namespace {

using namespace patchsim;

void tessellateQuad(benchmark::State& state, Partitioning mode) {
    D3D11Tessellator ts(mode);
    Tessellation out;
    QuadTessFactors f;
    const float factor = float(state.range(0)) - 0.3f;  // fractional modes get a fraction
    for (float& e : f.edge) e = factor;
    f.inside[0] = f.inside[1] = factor;
    std::int64_t points = 0;
    for (auto _ : state) {
        ts.tessellateQuad(f, out);
        points += std::int64_t(out.points.size());
        benchmark::DoNotOptimize(out.indices.data());
    }
    state.counters["points/s"] = benchmark::Counter(double(points), benchmark::Counter::kIsRate);
    state.counters["triangles"] = double(out.triangleCount());
}

void tessellateTri(benchmark::State& state, Partitioning mode) {
    D3D11Tessellator ts(mode);
    Tessellation out;
    TriTessFactors f;
    const float factor = float(state.range(0)) - 0.3f;
    for (float& e : f.edge) e = factor;
    f.inside = factor;
    std::int64_t points = 0;
    for (auto _ : state) {
        ts.tessellateTri(f, out);
        points += std::int64_t(out.points.size());
        benchmark::DoNotOptimize(out.indices.data());
    }
    state.counters["points/s"] = benchmark::Counter(double(points), benchmark::Counter::kIsRate);
    state.counters["triangles"] = double(out.triangleCount());
}

BENCHMARK_CAPTURE(tessellateQuad, integer, Partitioning::Integer)->Arg(4)->Arg(16)->Arg(64);
BENCHMARK_CAPTURE(tessellateQuad, fractional_odd, Partitioning::FractionalOdd)
    ->Arg(4)
    ->Arg(16)
    ->Arg(64);
BENCHMARK_CAPTURE(tessellateTri, integer, Partitioning::Integer)->Arg(4)->Arg(16)->Arg(64);
BENCHMARK_CAPTURE(tessellateTri, fractional_even, Partitioning::FractionalEven)
    ->Arg(4)
    ->Arg(16)
    ->Arg(64);

// HS + TS + DS over every patch of a shipped scene, one thread.
void frontEndScene(benchmark::State& state, const char* scene) {
    const FrontEnd fe(readSceneFile(std::string(PATCHSIM_SOURCE_DIR) + "/" + scene));
    FrontEndWorkspace ws = fe.makeWorkspace();
    TessellatedPatch patch;
    std::int64_t points = 0, patches = 0;
    for (auto _ : state) {
        for (std::size_t i = 0; i < fe.patchCount(); ++i) {
            fe.tessellate(i, patch, ws);
            points += std::int64_t(patch.tessellation.points.size());
        }
        patches += std::int64_t(fe.patchCount());
    }
    state.counters["patches/s"] = benchmark::Counter(double(patches), benchmark::Counter::kIsRate);
    state.counters["DS points/s"] = benchmark::Counter(double(points), benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(frontEndScene, static, "scenes/static.json")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(frontEndScene, motion_defocus, "scenes/motion_defocus.json")
    ->Unit(benchmark::kMillisecond);

// Building a scene's FrontEnd on 1 and 2 threads: the default scene (its creased cube's six
// irregular faces cost most) and the rook, a creased cage of 777 faces whose Bfr surfaces are
// nearly all of its front end.
void frontEndSetUp(benchmark::State& state, const char* path, bool cage) {
    const std::string file = std::string(PATCHSIM_SOURCE_DIR) + "/" + path;
    const SceneDesc scene = cage ? sceneForCage(file) : readSceneFile(file);
    const int threads = int(state.range(0));
    std::int64_t patches = 0;
    for (auto _ : state) {
        const FrontEnd fe(scene, threads);
        patches += std::int64_t(fe.patchCount());
        benchmark::DoNotOptimize(&fe);
    }
    state.counters["patches/s"] = benchmark::Counter(double(patches), benchmark::Counter::kIsRate);
}

void onOneAndTwoThreads(benchmark::internal::Benchmark* b) {
    b->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK_CAPTURE(frontEndSetUp, default, "scenes/default.json", false)->Apply(onOneAndTwoThreads);
BENCHMARK_CAPTURE(frontEndSetUp, rook, "scenes/cages/catmark_rook.obj", true)
    ->Apply(onOneAndTwoThreads);

}  // namespace
