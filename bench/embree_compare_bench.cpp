// The same visibility work, side by side: every sample of a frame resolved by the patch rasterizer
// (hierarchies, tile tests, rays from branch nodes) and by Embree 3 tracing one ray per sample
// through a BVH over the same tessellated, camera-space triangles (two time steps and linear
// motion when anything moves; the same rays: same origins, directions and times).
//
// Embree traces each frame three ways (one ray at a time; a pixel's samples as a coherent 16-ray
// packet; a band's rows as one coherent stream), so every row can be compared with its fastest.
//
// Both read the frame's samples from one table made before timing (the sampler is not
// visibility work); each makes its rays inside its timed loop. Embree's BVH is built outside its
// timed loop, the patch rasterizer's hierarchies inside. Arguments: scene, blur level, lens,
// threads (docs/PERFORMANCE.md). Built only when CMake finds Embree 3 (Debian's libembree-dev).

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <memory>
#include <string>

#include "core/counters.h"
#include "core/parallel.h"
#include "core/scene_reader.h"
#include "pipeline/driver/render.h"
#include "rasterizer/patent/frame_rasterizer.h"
#include "tessellator/front_end.h"

namespace {

using namespace patchsim;

constexpr const char* kSceneNames[] = {"default", "factor32", "scale1m"};
constexpr const char* kBlurNames[] = {"none", "moderate", "large"};
// Object motion at each blur level, as a fraction of the scene's own (which moves the torus by
// about a quarter of the frame's width over the shutter: large).
constexpr float kMotionScale[] = {0.0f, 0.25f, 1.0f};

// The scenes: 0 the default scene (320x240, 16 spp, 6,036 triangles at its adaptive factors);
// 1 the same at a fixed tessellation factor of 32 (115,424 triangles); 2
// docs/performance/scale_1m.json (1920x1080, 16 spp, 1,269,760 triangles). Blur scales each
// object's motion; without a lens the aperture is 0.
SceneDesc comparedScene(int scene, int blur, bool lens) {
    SceneDesc s =
        scene == 2
            ? readSceneFile(std::string(PATCHSIM_SOURCE_DIR) + "/docs/performance/scale_1m.json")
            : patchsim::defaultScene();
    if (scene == 1) {
        s.tessellation.targetEdgePixels = 0;
        s.tessellation.factor = 32.0f;
    }
    const float k = kMotionScale[blur];
    for (ObjectDesc& o : s.objects) {
        o.close.translate = o.open.translate + k * (o.close.translate - o.open.translate);
        o.close.rotateDegrees =
            o.open.rotateDegrees + k * (o.close.rotateDegrees - o.open.rotateDegrees);
        o.close.scale = o.open.scale + k * (o.close.scale - o.open.scale);
    }
    if (!lens) s.lens.apertureRadius = 0.0f;
    return s;
}

struct Frame {
    SceneDesc scene;
    std::unique_ptr<FrontEnd> frontEnd;
    Effects effects;
    std::vector<MovingMesh> meshes;
    std::unique_ptr<SampleGenerator> samples;
    std::unique_ptr<SampleTable> table;
    LensModel lens;
    std::size_t triangles = 0;

    explicit Frame(const SceneDesc& s) : scene(s) {
        frontEnd = std::make_unique<FrontEnd>(scene);
        effects = detectEffects(scene, frontEnd->geometryMoves(), frontEnd->camera().moves());
        meshes.resize(frontEnd->patchCount());
        std::vector<FrontEndWorkspace> workspaces;
        for (int w = 0; w < 2; ++w) workspaces.push_back(frontEnd->makeWorkspace());
        parallelFor(meshes.size(), 2, [&](int w, std::size_t i) {
            TessellatedPatch patch;
            frontEnd->tessellate(i, patch, workspaces[std::size_t(w)]);
            toMovingMesh(patch, frontEnd->camera(), effects.motion, int(i), true, meshes[i]);
        });
        for (const MovingMesh& m : meshes) triangles += m.triangleCount();
        samples =
            std::make_unique<SampleGenerator>(scene.film.seed, scene.film.samplesPerPixel, effects);
        table = std::make_unique<SampleTable>(*samples, scene.film.width, scene.film.height, 2);
        lens = {effects.defocus ? scene.lens.apertureRadius : 0.0f, scene.lens.focusDistance};
    }
    std::int64_t sampleCount() const {
        return std::int64_t(scene.film.width) * scene.film.height * scene.film.samplesPerPixel;
    }
};

// One frame at a time (the largest takes gigabytes): benchmarks are registered frame by frame.
const Frame& frame(int scene, int blur, bool lens) {
    static std::unique_ptr<Frame> cached;
    static int key = -1;
    const int wanted = scene * 100 + blur * 10 + int(lens);
    if (key != wanted) {
        cached.reset();
        cached = std::make_unique<Frame>(comparedScene(scene, blur, lens));
        key = wanted;
    }
    return *cached;
}

void reportCommon(benchmark::State& state, const Frame& f, std::int64_t hits) {
    state.counters["samples/s"] =
        benchmark::Counter(double(f.sampleCount()), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["covered samples"] = double(hits);
    state.counters["triangles"] = double(f.triangles);
}

// The modelled hardware's choices the study rows change; 0 keeps the scene's own (the defaults).
struct DesignPoint {
    int tileSize = 0;
    int leafSize = 0;
    int trianglesPerGroup = 0;
};

void patchRasterizer(benchmark::State& state, int scene, int blur, bool lens, int threads,
                     DesignPoint design) {
    const Frame& f = frame(scene, blur, lens);
    const Camera& camera = f.frontEnd->camera();
    RasterizerOptions rasterizerOptions = f.scene.rasterizer;
    if (design.tileSize > 0) rasterizerOptions.tileSize = design.tileSize;
    if (design.leafSize > 0) rasterizerOptions.leafSize = design.leafSize;
    if (design.trianglesPerGroup > 0)
        rasterizerOptions.maxTrianglesPerGroup = design.trianglesPerGroup;
    const PatchRasterizer rasterizer(camera, f.lens, *f.samples, f.effects, rasterizerOptions);
    FrameRasterOptions options;
    options.threads = threads;
    options.sampleTable = f.table.get();
    options.opaqueStartsEmpty = true;
    // The output buffer is made and cleared outside the timed region (Embree's loop keeps none).
    VisibilityBuffer buffer(f.scene.film.width, f.scene.film.height, f.scene.film.samplesPerPixel,
                            camera.farPlane(), 2);
    std::int64_t hits = 0;
    RasterWork work;
    for (auto _ : state) {
        const FrameRasterWork frameWork =
            rasterizeFrame(f.meshes, rasterizer, {&buffer, nullptr, nullptr, 0}, options);
        state.PauseTiming();
        work = {};
        for (std::size_t i = 0; i < f.meshes.size(); ++i) work.add(frameWork.patch(i));
        hits = 0;
        for (const VisibilityRecord& r : buffer.records()) hits += r.hit();
        std::fill(buffer.mutableRecords().begin(), buffer.mutableRecords().end(),
                  VisibilityRecord{});
        state.ResumeTiming();
    }
    reportCommon(state, f, hits);
    state.counters["STE"] =
        double(work.visibilitySamples) / double(std::max<std::int64_t>(work.samplesTested, 1));
    state.counters["rays/sample"] = double(work.raysCast) / double(f.sampleCount());
    state.counters["ray-box/ray"] =
        double(work.rayBoxTests) / double(std::max<std::int64_t>(work.raysCast, 1));
    state.counters["ray-tri/ray"] =
        double(work.rayTriangleTests) / double(std::max<std::int64_t>(work.raysCast, 1));
}

RTCScene buildEmbreeScene(RTCDevice device, const Frame& f) {
    const bool moves = f.effects.motion;
    RTCScene scene = rtcNewScene(device);
    for (const MovingMesh& m : f.meshes) {
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        const unsigned steps = moves ? 2 : 1;
        rtcSetGeometryTimeStepCount(geometry, steps);
        for (unsigned step = 0; step < steps; ++step) {
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
    return scene;
}

// How Embree is asked to trace (docs/PERFORMANCE.md): one ray at a time; a pixel's samples as
// coherent packets of 16; a band's rows as one coherent stream. The packet and stream calls are
// Embree's own fast paths for primary rays, which share an origin region and a direction.
enum class EmbreeApi : std::uint8_t { OneRay, Packet16, Stream };
constexpr const char* kApiNames[] = {"embree", "embreePacket16", "embreeStream"};
constexpr int kBand = 8;  // rows a worker takes at a time

// Sample s of pixel (x, y) as Embree's ray.
template <class RayHit>
void setRay(RayHit& rh, const Frame& f, int x, int y, int s) {
    const Camera& camera = f.frontEnd->camera();
    const Sample& sample = f.table->pixel(x, y)[s];
    const Vec2 raster = Vec2(float(x), float(y)) + sample.pixelOffset;
    const Ray ray = makeCameraRay(camera, rasterToScreen(camera, raster), f.table->disk(x, y)[s],
                                  sample.time, f.lens);
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
}

// Every sample of rows [y0, y1) traced one ray at a time; returns the hits.
std::int64_t traceRows(RTCScene scene, const Frame& f, int y0, int y1) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    std::int64_t hits = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < f.scene.film.width; ++x)
            for (int s = 0; s < f.scene.film.samplesPerPixel; ++s) {
                RTCRayHit rh;
                setRay(rh, f, x, y, s);
                rtcIntersect1(scene, &context, &rh);
                hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
    return hits;
}

// The same, a pixel's samples as packets of 16 (lanes past the pixel's last sample invalid).
std::int64_t tracePackets(RTCScene scene, const Frame& f, int y0, int y1) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    const int spp = f.scene.film.samplesPerPixel;
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[16];
    std::int64_t hits = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < f.scene.film.width; ++x)
            for (int first = 0; first < spp; first += 16) {
                const int lanes = std::min(16, spp - first);
                for (int lane = 0; lane < 16; ++lane) valid[lane] = lane < lanes ? -1 : 0;
                for (int lane = 0; lane < lanes; ++lane) {
                    RTCRayHit one;
                    setRay(one, f, x, y, first + lane);
                    packet.ray.org_x[lane] = one.ray.org_x;
                    packet.ray.org_y[lane] = one.ray.org_y;
                    packet.ray.org_z[lane] = one.ray.org_z;
                    packet.ray.dir_x[lane] = one.ray.dir_x;
                    packet.ray.dir_y[lane] = one.ray.dir_y;
                    packet.ray.dir_z[lane] = one.ray.dir_z;
                    packet.ray.tnear[lane] = one.ray.tnear;
                    packet.ray.tfar[lane] = one.ray.tfar;
                    packet.ray.time[lane] = one.ray.time;
                    packet.ray.mask[lane] = one.ray.mask;
                    packet.ray.flags[lane] = 0;
                    packet.ray.id[lane] = unsigned(lane);
                    packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
                    packet.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
                }
                rtcIntersect16(valid, scene, &context, &packet);
                for (int lane = 0; lane < lanes; ++lane)
                    hits += packet.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID;
            }
    return hits;
}

// The same, a band's rows as one coherent stream of rays in `stream` (the band's sample count).
std::int64_t traceStream(RTCScene scene, const Frame& f, int y0, int y1,
                         std::vector<RTCRayHit>& stream) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    const int spp = f.scene.film.samplesPerPixel;
    std::size_t n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < f.scene.film.width; ++x)
            for (int s = 0; s < spp; ++s) setRay(stream[n++], f, x, y, s);
    rtcIntersect1M(scene, &context, stream.data(), unsigned(n), sizeof(RTCRayHit));
    std::int64_t hits = 0;
    for (std::size_t i = 0; i < n; ++i) hits += stream[i].hit.geomID != RTC_INVALID_GEOMETRY_ID;
    return hits;
}

void embree(benchmark::State& state, int sceneIndex, int blur, bool lens, int threads,
            EmbreeApi api) {
    const Frame& f = frame(sceneIndex, blur, lens);
    const std::string config = "threads=" + std::to_string(threads);
    RTCDevice device = rtcNewDevice(config.c_str());
    RTCScene scene = buildEmbreeScene(device, f);
    // Rows in bands of 8 taken by the next free worker, like the patch rasterizer's tiles.
    const int height = f.scene.film.height;
    const int bands = (height + kBand - 1) / kBand;
    std::vector<std::int64_t> bandHits(static_cast<std::size_t>(bands), 0);
    // A stream buffer per worker, made before timing.
    std::vector<std::vector<RTCRayHit>> streams(
        api == EmbreeApi::Stream ? std::size_t(resolveThreadCount(threads)) : 0,
        std::vector<RTCRayHit>(std::size_t(kBand) * std::size_t(f.scene.film.width) *
                               std::size_t(f.scene.film.samplesPerPixel)));
    std::int64_t hits = 0;
    for (auto _ : state) {
        parallelFor(std::size_t(bands), threads, [&](int worker, std::size_t b) {
            const int y0 = int(b) * kBand, y1 = std::min(y0 + kBand, height);
            switch (api) {
                case EmbreeApi::OneRay:
                    bandHits[b] = traceRows(scene, f, y0, y1);
                    break;
                case EmbreeApi::Packet16:
                    bandHits[b] = tracePackets(scene, f, y0, y1);
                    break;
                case EmbreeApi::Stream:
                    bandHits[b] = traceStream(scene, f, y0, y1, streams[std::size_t(worker)]);
                    break;
            }
        });
        hits = 0;
        for (std::int64_t h : bandHits) hits += h;
    }
    // A call this Embree build does not support (a packet width it was built without) only sets
    // the device's error and traces nothing: such a row must not pass for a fast one.
    if (const RTCError error = rtcGetDeviceError(device); error != RTC_ERROR_NONE)
        state.SkipWithError(("Embree error " + std::to_string(int(error))).c_str());
    reportCommon(state, f, hits);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
}

// Frame by frame, each method on 1 and 2 threads: patchRasterizer/<scene>/<blur>/<lens>/<threads>.
int registerAll() {
    for (int scene = 0; scene < 3; ++scene)
        for (int blur = 0; blur < 3; ++blur)
            for (bool lens : {false, true})
                for (int threads : {1, 2}) {
                    const std::string suffix = std::string("/") + kSceneNames[scene] + "/" +
                                               kBlurNames[blur] + (lens ? "/lens" : "/pinhole") +
                                               "/threads:" + std::to_string(threads);
                    benchmark::RegisterBenchmark(("patchRasterizer" + suffix).c_str(),
                                                 patchRasterizer, scene, blur, lens, threads,
                                                 DesignPoint{})
                        ->Unit(benchmark::kMillisecond)
                        ->UseRealTime();
                    for (EmbreeApi api :
                         {EmbreeApi::OneRay, EmbreeApi::Packet16, EmbreeApi::Stream})
                        benchmark::RegisterBenchmark((kApiNames[int(api)] + suffix).c_str(), embree,
                                                     scene, blur, lens, threads, api)
                            ->Unit(benchmark::kMillisecond)
                            ->UseRealTime();
                }
    // The tile size is the modelled hardware's choice, not the simulator's; these rows show
    // what other sizes would cost the simulator on the two smaller scenes, one thread each
    // (tiles/<scene>:<tile side>/<blur>/<lens>, against the embree rows' one-thread times;
    // named so that the matrix's filter '/(default|factor32)/' leaves them out).
    for (int scene = 0; scene < 2; ++scene)
        for (int blur = 0; blur < 3; ++blur)
            for (bool lens : {false, true})
                for (int tile : {4, 8, 16}) {
                    const std::string name = std::string("tiles/") + kSceneNames[scene] + ":" +
                                             std::to_string(tile) + "/" + kBlurNames[blur] +
                                             (lens ? "/lens" : "/pinhole");
                    benchmark::RegisterBenchmark(name.c_str(), patchRasterizer, scene, blur, lens,
                                                 1, DesignPoint{tile, 0, 0})
                        ->Unit(benchmark::kMillisecond)
                        ->UseRealTime();
                }
    // Fewer, larger units per tile on the micropolygon scene: hierarchies of 64 leaves of 4 (the
    // default), 8, 16 and 32 triangles, so groups of 256 to 2,048 triangles (at 32, one group per
    // patch of this scene), one thread each (groups/factor32:<leaf size>/<blur>/<lens>).
    for (int blur = 0; blur < 3; ++blur)
        for (bool lens : {false, true})
            for (int leaf : {4, 8, 16, 32}) {
                const std::string name = std::string("groups/factor32:") + std::to_string(leaf) +
                                         "/" + kBlurNames[blur] + (lens ? "/lens" : "/pinhole");
                benchmark::RegisterBenchmark(name.c_str(), patchRasterizer, 1, blur, lens, 1,
                                             DesignPoint{0, leaf, kMaxLeavesPerHierarchy * leaf})
                    ->Unit(benchmark::kMillisecond)
                    ->UseRealTime();
            }
    return 0;
}
const int registered = registerAll();

}  // namespace
