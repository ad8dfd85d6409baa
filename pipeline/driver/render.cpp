#include "pipeline/driver/render.h"

#include <chrono>

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "pipeline/driver/frame_share.h"
#include "pipeline/driver/scene_info.h"
#include "pipeline/methods/visibility_method.h"
#include "tessellator/front_end.h"

namespace patchsim {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The frame's tessellated patches and their camera-space meshes.
struct FrontEndOutput {
    std::vector<TessellatedPatch> patches;
    std::vector<MovingMesh> meshes;
};

FrontEndOutput runFrontEnd(const FrontEnd& frontEnd, const Effects& effects,
                           const NumberFormat& vertexFormat, int workers, bool progressBar) {
    const std::size_t count = frontEnd.patchCount();
    FrontEndOutput out{std::vector<TessellatedPatch>(count), std::vector<MovingMesh>(count)};
    std::vector<FrontEndWorkspace> workspaces;
    for (int w = 0; w < workers; ++w) workspaces.push_back(frontEnd.makeWorkspace());
    Progress progress("front end ", std::int64_t(count), 1, progressBar);
    parallelFor(count, workers, [&](int w, std::size_t i) {
        TessellatedPatch& patch = out.patches[i];
        frontEnd.tessellate(i, patch, workspaces[std::size_t(w)]);
        const MaterialDesc& m = frontEnd.objects()[std::size_t(patch.object)].desc.material;
        const bool opaque = !effects.transparency || (m.opacity >= 1.0f && m.closeOpacity >= 1.0f);
        toMovingMesh(patch, frontEnd.camera(), effects.motion, int(i), opaque, out.meshes[i]);
        storePositionsIn(out.meshes[i], vertexFormat);
        progress.advance();
    });
    return out;
}

// The front end's and the shader's share of each patch's work (the front end's as the method's
// passes run it); the visibility method adds its own.
std::vector<PatchOps> frontEndAndShadingOps(const std::vector<TessellatedPatch>& patches,
                                            const std::vector<double>& shading,
                                            const MethodFrame& frame) {
    std::vector<PatchOps> ops(patches.size());
    for (std::size_t i = 0; i < patches.size(); ++i) {
        frame.chargeFrontEnd(patches[i].work, ops[i]);
        ops[i][Op::Invocations] = shading[i];
    }
    return ops;
}

// The frame's buffers: per-sample visibility, transparent layers (one pool per worker, and at
// least one per band of rows), per-pixel counts.
VisibilityTargets makeBuffers(const SceneDesc& scene, const RenderOptions& options,
                              const Camera& camera, int workers, RenderResult& result) {
    const FilmDesc& film = scene.film;
    result.visibility = std::make_unique<VisibilityBuffer>(
        film.width, film.height, film.samplesPerPixel, camera.farPlane(), workers);
    if (result.effects.transparency)
        result.transparent = std::make_unique<TransparentLayers>(
            result.visibility->records().size(), options.maxLayers,
            std::max(workers, FramePartition::kClasses));
    if (options.heatMaps)
        result.pixels = std::make_unique<PixelCounters>(
            TileGrid{film.width, film.height, scene.rasterizer.tileSize});
    return {result.visibility.get(), result.transparent.get(), result.pixels.get(), 0};
}

// A frame split between processes: the others send rank 0 their rows, their work and what their
// visibility step counted. Returns false on the other ranks, which have nothing more to do.
bool gatherSplitFrame(const FrameShare& share, const CounterValues& beforeVisibility,
                      MethodFrame& frame, RenderResult& result) {
    CounterValues counts = CounterRegistry::instance().snapshot().since(beforeVisibility);
    const FrameRows rows{result.visibility.get(), result.transparent.get(), result.pixels.get(),
                         &frame.ops(), &counts};
    const std::vector<std::string> parts =
        share.gather(share.root() ? std::string()
                                  : packFrameRows(
                                        rows, [&](int y) { return frame.ownsPixelRow(y); },
                                        [&](int ty) { return frame.ownsTileRow(ty); }));
    if (!share.root()) return false;
    for (std::size_t r = 1; r < parts.size(); ++r) {
        unpackFrameRows(parts[r], rows);
        CounterRegistry::instance().merge(counts);
    }
    return true;
}

// Each patch's control points as the input assembler fetches them (the memory model's front-end
// traffic), patches in the front end's order.
ControlPointFetch controlPointFetch(const FrontEnd& frontEnd) {
    ControlPointFetch fetch;
    fetch.patchBegin.reserve(frontEnd.patchCount() + 1);
    fetch.patchBegin.push_back(0);
    std::vector<int> indices;
    for (const SceneObject& object : frontEnd.objects()) {
        for (const PatchInfo& patch : object.mesh->patches()) {
            object.mesh->controlPointIndices(patch.face, indices);
            for (const int v : indices)
                fetch.vertices.push_back(std::uint32_t(fetch.vertexCount + std::uint64_t(v)));
            fetch.patchBegin.push_back(fetch.vertices.size());
        }
        fetch.vertexCount += object.cage.positions.size();
    }
    return fetch;
}

// The scene through IA, VS, HS, TS and DS, on all threads.
FrontEndOutput frontEndStages(const FrontEnd& frontEnd, const RenderOptions& options, int workers,
                              RenderResult& result) {
    const auto start = std::chrono::steady_clock::now();
    result.effects = applyOverrides(
        detectEffects(frontEnd.scene(), frontEnd.geometryMoves(), frontEnd.camera().moves()),
        options.overrides);
    for (const SceneObject& object : frontEnd.objects())
        for (const std::string& note : objectNotes(object)) result.notes.push_back(note);
    FrontEndOutput fe =
        runFrontEnd(frontEnd, result.effects, result.formats.vertices, workers, options.progress);
    result.patches = fe.patches.size();
    for (const TessellatedPatch& p : fe.patches) result.triangles += p.triangleCount();
    result.frontEndSeconds = secondsSince(start);
    return fe;
}

}  // namespace

void checkRender(const SceneDesc& scene, const RenderOptions& options) {
    scene.rasterizer.validate(scene.path);
    scene.rasterizer.validateTileSamples(scene.film.samplesPerPixel, scene.path);
    if (options.maxLayers < 1 || options.maxLayers > 255)
        throw InputError("command line", "--max-layers", "must be in [1, 255]");
    options.visibilityMethod().check(scene, options, resolveThreadCount(options.threads));
}

RenderResult renderScene(const SceneDesc& scene, const RenderOptions& options) {
    checkRender(scene, options);
    const VisibilityMethod& method = options.visibilityMethod();
    const int workers = resolveThreadCount(options.threads);
    RenderResult result;
    if (method.rasterizesPatches()) {
        result.formats.nodes = scene.rasterizer.nodeFormat;
        result.formats.planes = scene.rasterizer.planeFormat;
        result.formats.screenBounds = scene.rasterizer.screenBoundsFormat;
        result.formats.rayBoxes = scene.rasterizer.rayBoxFormat;
    }
    result.formats.vertices = scene.rasterizer.vertexFormat;
    if (method.roundsTriangleTests()) result.formats.triangles = scene.rasterizer.triangleFormat;
    const FrontEnd frontEnd(scene, workers);
    const FrontEndOutput fe = frontEndStages(frontEnd, options, workers, result);

    auto start = std::chrono::steady_clock::now();
    const SampleGenerator samples = method.makeSamples(scene.film, result.effects);
    const VisibilityTargets targets =
        makeBuffers(scene, options, frontEnd.camera(), workers, result);
    if (options.memoryTrace) {
        result.memoryTrace = method.makeMemoryTrace(scene);
        result.sampleSet = samples;  // where the samples lie, for depth compression
        // What some methods do with the layers is not modelled (an accumulation buffer's pass
        // per sample index, reprojection's layer parts): such a frame records nothing, and its
        // report says memory is not modelled.
        if (result.memoryTrace && result.transparent && result.memoryTrace->opaqueOnly()) {
            result.memoryTrace.reset();
            result.memoryTraceDropped = true;
        }
        if (result.memoryTrace) {
            result.controlPointFetch = controlPointFetch(frontEnd);
            if (result.transparent) result.memoryTrace->setLayerSlots(options.maxLayers);
        }
    }
    const FrameInputs in{&scene,
                         &options,
                         &frontEnd,
                         &fe.patches,
                         &fe.meshes,
                         result.effects,
                         &samples,
                         targets,
                         options.share.partition(),
                         workers,
                         result.memoryTrace.get()};
    const CounterValues beforeVisibility = CounterRegistry::instance().snapshot();
    const std::unique_ptr<MethodFrame> frame = method.start(in);
    frame->visibility();
    if (options.share.split() &&
        !gatherSplitFrame(options.share, beforeVisibility, *frame, result)) {
        result.complete = false;
        return result;
    }
    result.visibilitySeconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    {
        Progress progress("shading   ", scene.film.height, 1, options.progress, "rows");
        result.frame = resolveFrame(in.shading(), *result.visibility, result.transparent.get(),
                                    samples, options.resolve, workers, &progress);
    }
    frame->finish(result.frame);
    result.shadingSeconds = secondsSince(start);
    result.patchOps = frontEndAndShadingOps(fe.patches, result.frame.shadedPerPatch, *frame);
    for (std::size_t i = 0; i < result.patchOps.size(); ++i)
        result.patchOps[i].add(frame->ops()[i]);
    return result;
}

FrameTiming timeFrame(const RenderResult& result, const HardwareConfig& hardware) {
    FrameTiming t;
    if (hardware.memory && result.memoryTrace && !result.patchOps.empty()) {
        const MemoryConfig& m = *hardware.memory;
        FrameMemoryInputs inputs{result.patchOps.size(), result.patchOps.size() - 1,
                                 hierarchySpills(result.patchOps, hardware.scratchBudgetBytes)};
        inputs.fetch = &result.controlPointFetch;
        std::optional<DepthCompressionReport> compression;
        // An accumulation buffer's depth lives one pass at a time: not compressed.
        if (m.depthCompression != DepthCompression::None && result.visibility && result.sampleSet &&
            !result.memoryTrace->accumulation()) {
            compression = compressDepth(*result.visibility, *result.sampleSet, m.surfaceTile,
                                        m.depthCompression);
            inputs.depthScale = compression->blockScales();
        }
        t.memory = simulateMemory(*result.memoryTrace, m, inputs);
        t.memory->depthCompression = std::move(compression);
    }
    t.memoryNotModelled = hardware.memory && !result.memoryTrace;
    t.timing = simulateTiming(result.patchOps, hardware, t.memory ? &*t.memory : nullptr);
    t.energy =
        estimateEnergy(result.patchOps, hardware, t.memory ? &*t.memory : nullptr, result.formats);
    return t;
}

}  // namespace patchsim
