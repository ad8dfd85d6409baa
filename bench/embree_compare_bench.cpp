// The same visibility work, side by side: every sample of the default scene's frame resolved by
// the patch rasterizer (hierarchies, tile tests, rays from branch nodes) and by Embree 3 tracing
// one motion-blurred ray per sample through a BVH over the same tessellated, camera-space
// triangles (two time steps, linear motion, the same rays: same origins, directions and times).
// Built only when CMake finds Embree 3 (Debian's libembree-dev).

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include "pipeline/core/counters.h"
#include "pipeline/core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "rasterizer/frame_rasterizer.h"
#include "rasterizer/sample_rays.h"
#include "tessellator/front_end.h"

namespace {

using namespace patchsim;

// The scenes compared (range(0)): 0 the default scene (6,036 moving triangles at its adaptive
// factors); 1 the same at a fixed tessellation factor of 32 (58 patches: 115,424 moving
// triangles); 2 docs/performance/scale_1m.json (1,269,760 moving triangles, 1920x1080, 16 spp,
// lens).
SceneDesc comparedScene(std::int64_t variant) {
    if (variant == 2)
        return readSceneFile(std::string(PATCHSIM_SOURCE_DIR) + "/docs/performance/scale_1m.json");
    SceneDesc scene = patchsim::defaultScene();
    if (variant == 1) {
        scene.tessellation.targetEdgePixels = 0;
        scene.tessellation.factor = 32.0f;
    }

    return scene;
}

struct Frame {
    SceneDesc scene;
    std::unique_ptr<FrontEnd> frontEnd;
    Effects effects;
    std::vector<MovingMesh> meshes;
    std::unique_ptr<SampleGenerator> samples;
    std::unique_ptr<SampleTable> table;
    LensModel lens;

    explicit Frame(std::int64_t variant) : scene(comparedScene(variant)) {
        frontEnd = std::make_unique<FrontEnd>(scene);
        effects = detectEffects(scene, frontEnd->geometryMoves(), frontEnd->camera().moves());
        FrontEndWorkspace ws = frontEnd->makeWorkspace();
        TessellatedPatch patch;
        meshes.resize(frontEnd->patchCount());
        for (std::size_t i = 0; i < meshes.size(); ++i) {
            frontEnd->tessellate(i, patch, ws);
            toMovingMesh(patch, frontEnd->camera(), effects.motion, int(i), true, meshes[i]);
        }
        samples =
            std::make_unique<SampleGenerator>(scene.film.seed, scene.film.samplesPerPixel, effects);
        table = std::make_unique<SampleTable>(*samples, scene.film.width, scene.film.height, 0);
        lens = {scene.lens.apertureRadius, scene.lens.focusDistance};
    }
    std::int64_t sampleCount() const {
        return std::int64_t(scene.film.width) * scene.film.height * scene.film.samplesPerPixel;
    }
};

std::size_t triangleCount(const Frame& f) {
    std::size_t n = 0;
    for (const MovingMesh& m : f.meshes) n += m.triangleCount();
    return n;
}

// Made on first use: the large frame costs a second and a gigabyte, only when it runs.
const Frame& frame(std::int64_t variant) {
    static std::unique_ptr<Frame> frames[3];
    std::unique_ptr<Frame>& f = frames[variant];
    if (!f) f = std::make_unique<Frame>(variant);
    return *f;
}

void patchRasterizer(benchmark::State& state) {
    const Frame& f = frame(state.range(0));
    const Camera& camera = f.frontEnd->camera();
    const PatchRasterizer rasterizer(camera, f.lens, *f.samples, f.effects, f.scene.rasterizer);
    std::int64_t hits = 0;
    FrameRasterOptions singleThread;
    singleThread.threads = 1;
    singleThread.sampleTable = f.table.get();
    singleThread.opaqueStartsEmpty = true;
    // The output buffer is made and cleared outside the timed region (Embree's loop keeps none).
    VisibilityBuffer buffer(f.scene.film.width, f.scene.film.height, f.scene.film.samplesPerPixel,
                            camera.farPlane());
    for (auto _ : state) {
        rasterizeFrame(f.meshes, rasterizer, {&buffer, nullptr, nullptr, 0}, singleThread);
        state.PauseTiming();
        hits = 0;
        for (const VisibilityRecord& r : buffer.records()) hits += r.hit();
        std::fill(buffer.mutableRecords().begin(), buffer.mutableRecords().end(),
                  VisibilityRecord{});
        state.ResumeTiming();
    }
    state.counters["samples/s"] =
        benchmark::Counter(double(f.sampleCount()), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["covered samples"] = double(hits);
    state.counters["triangles"] = double(triangleCount(f));
}
BENCHMARK(patchRasterizer)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

void embree(benchmark::State& state) {
    const Frame& f = frame(state.range(0));
    const Camera& camera = f.frontEnd->camera();
    RTCDevice device = rtcNewDevice("threads=1");
    RTCScene scene = rtcNewScene(device);
    for (const MovingMesh& m : f.meshes) {
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryTimeStepCount(geometry, 2);
        for (unsigned step = 0; step < 2; ++step) {
            auto* v = static_cast<float*>(
                rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, step, RTC_FORMAT_FLOAT3,
                                        3 * sizeof(float), m.position0.size()));
            const std::vector<Vec3>& p = step == 0 ? m.position0 : m.position1;
            for (std::size_t i = 0; i < p.size(); ++i) {
                v[3 * i] = p[i].x;
                v[3 * i + 1] = p[i].y;
                v[3 * i + 2] = p[i].z;
            }
        }
        auto* idx = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(unsigned), m.triangleCount()));
        std::copy(m.indices.begin(), m.indices.end(), idx);
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(scene, geometry);
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(scene);
    std::int64_t hits = 0;
    for (auto _ : state) {
        hits = 0;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (int y = 0; y < f.scene.film.height; ++y) {
            for (int x = 0; x < f.scene.film.width; ++x) {
                const Sample* pixel = f.table->pixel(x, y);
                const Vec2* disk = f.table->disk(x, y);
                for (int s = 0; s < f.scene.film.samplesPerPixel; ++s) {
                    const Vec2 raster = Vec2(float(x), float(y)) + pixel[s].pixelOffset;
                    const Ray ray = makeCameraRay(camera, rasterToScreen(camera, raster), disk[s],
                                                  pixel[s].time, f.lens);
                    RTCRayHit rh;
                    rh.ray.org_x = ray.origin.x;
                    rh.ray.org_y = ray.origin.y;
                    rh.ray.org_z = ray.origin.z;
                    rh.ray.dir_x = ray.direction.x;
                    rh.ray.dir_y = ray.direction.y;
                    rh.ray.dir_z = ray.direction.z;
                    rh.ray.tnear = ray.lambdaMin;
                    rh.ray.tfar = ray.lambdaMax;
                    rh.ray.time = ray.time;
                    rh.ray.mask = ~0u;
                    rh.ray.flags = 0;
                    rh.ray.id = 0;
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(scene, &context, &rh);
                    hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
                }
            }
        }
    }
    state.counters["samples/s"] =
        benchmark::Counter(double(f.sampleCount()), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["covered samples"] = double(hits);
    state.counters["triangles"] = double(triangleCount(f));
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
}
BENCHMARK(embree)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

}  // namespace
