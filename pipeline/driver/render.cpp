#include "pipeline/driver/render.h"

#include <chrono>
#include <numeric>
#include <random>

#include "pipeline/core/error.h"
#include "pipeline/core/parallel.h"
#include "pipeline/core/progress.h"
#include "pipeline/driver/scene_info.h"
#include "rasterizer/reference_rasterizer.h"
#include "tessellator/front_end.h"

namespace patchsim {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Tile rows are dealt to this many classes (independent of the thread count); each class owns
// one pool of transparent layers.
constexpr int kRowClasses = TransparentLayers::kPools;

}  // namespace

std::vector<PatchRasterWork> runPatchVisibility(const std::vector<MovingMesh>& meshes,
                                                const PatchRasterizer& rasterizer, int threads,
                                                const VisibilityTargets& targets,
                                                const std::vector<std::size_t>& orderIn,
                                                Progress* progress) {
    std::vector<std::size_t> order = orderIn;
    if (order.empty()) {
        order.resize(meshes.size());
        std::iota(order.begin(), order.end(), std::size_t(0));
    }
    // Hierarchies and screen bounds per group, once per patch.
    std::vector<std::vector<PatchRasterizer::Group>> groups(meshes.size());
    std::vector<WorkCounts> prepareWork(std::size_t(resolveThreadCount(threads)));
    parallelFor(meshes.size(), threads, [&](int w, std::size_t i) {
        WorkCounts& work = prepareWork[std::size_t(w)];
        ++work.patches;
        std::vector<std::uint32_t> triangles, groupBegin;
        splitIntoGroups(meshes[i], rasterizer.options().trianglesPerGroup(), triangles,
                        groupBegin);
        for (std::size_t g = 0; g + 1 < groupBegin.size(); ++g) {
            if (groupBegin[g] == groupBegin[g + 1]) continue;
            groups[i].emplace_back();
            rasterizer.prepareGroup(meshes[i], triangles.data() + groupBegin[g],
                                    groupBegin[g + 1] - groupBegin[g], groups[i].back(), work);
        }
    });
    for (const WorkCounts& w : prepareWork) w.flush();
    std::vector<PatchRasterWork> perPatch(meshes.size());
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        for (const PatchRasterizer::Group& g : groups[i]) {
            perPatch[i].nodesBuilt += g.hierarchy.nodeCount();
            perPatch[i].largestHierarchyBytes =
                std::max<std::uint64_t>(perPatch[i].largestHierarchyBytes, g.hierarchy.bytes());
        }
    }
    // Tile work per patch, per row class (fixed slots), summed afterwards in a fixed order.
    std::vector<std::vector<WorkCounts>> classWork(kRowClasses,
                                                   std::vector<WorkCounts>(meshes.size()));
    const int tileSize = rasterizer.options().tileSize;
    const int tileRows = (targets.opaque->height() + tileSize - 1) / tileSize;
    parallelFor(kRowClasses, threads, [&](int, std::size_t rowClass) {
        VisibilityTargets mine = targets;
        mine.pool = int(rowClass);
        for (std::size_t i : order) {
            WorkCounts& work = classWork[rowClass][i];
            for (const PatchRasterizer::Group& group : groups[i]) {
                for (int ty = group.tileY0; ty < std::min(group.tileY1, tileRows); ++ty) {
                    if (ty % kRowClasses != int(rowClass)) continue;
                    for (int tx = group.tileX0; tx < group.tileX1; ++tx)
                        rasterizer.rasterizeTile(meshes[i], group, tx, ty, mine, work);
                }
            }
            if (progress) progress->advance();
        }
        for (const WorkCounts& work : classWork[rowClass]) work.flush();
    });
    for (const auto& rows : classWork)
        for (std::size_t i = 0; i < meshes.size(); ++i) perPatch[i].work.add(rows[i]);
    return perPatch;
}

namespace {

std::vector<PatchOps> collectPatchOps(const std::vector<TessellatedPatch>& patches,
                                      const std::vector<PatchRasterWork>& raster,
                                      const std::vector<double>& shading) {
    std::vector<PatchOps> ops(patches.size());
    for (std::size_t i = 0; i < patches.size(); ++i) {
        const TessellatedPatch& p = patches[i];
        const WorkCounts& w = raster[i].work;
        PatchOps& o = ops[i];
        const double points = double(p.tessellation.points.size());
        o[Op::Patches] = 1;
        o[Op::ControlPoints] = p.controlPoints;
        o[Op::EdgeFactors] = p.domain == PatchDomain::Quad ? 4 : 3;
        o[Op::DomainPoints] = points;
        o[Op::Triangles] = double(p.triangleCount());
        o[Op::Evaluations] = p.culled() ? 0 : points;
        o[Op::StencilApplications] = p.culled() ? 0 : 6 * points;
        o[Op::NodesBuilt] = double(raster[i].nodesBuilt);
        o[Op::PlaneTests] = double(w.planeTests);
        o[Op::TimeIntervals] = double(w.timeIntervals);
        o[Op::SamplesTested] = double(w.samplesTested);
        o[Op::RayBoxTests] = double(w.rayBoxTests);
        o[Op::RayTriangleTests] = double(w.rayTriangleTests);
        o[Op::Invocations] = shading[i];
        o[Op::DepthTests] = double(w.visibilitySamples);
        o[Op::TransparentFragments] = double(w.transparentFragments);
        o.hierarchyBytes = raster[i].largestHierarchyBytes;
    }
    return ops;
}

// The reference method's work per patch, charged to the rasterizer stage like the patch method's:
// every sample is tested against every triangle of every patch; its hits are written.
std::vector<PatchRasterWork> referencePatchWork(const std::vector<MovingMesh>& meshes,
                                                const VisibilityBuffer& buffer,
                                                const TransparentLayers* layers) {
    std::vector<PatchRasterWork> work(meshes.size());
    const auto samples = std::int64_t(buffer.records().size());
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        work[i].work.samplesTested = samples;
        work[i].work.raysCast = samples;
        work[i].work.rayTriangleTests = samples * std::int64_t(meshes[i].triangleCount());
    }
    for (std::size_t r = 0; r < buffer.records().size(); ++r) {
        const VisibilityRecord& record = buffer.records()[r];
        if (record.hit()) ++work[std::size_t(record.patch)].work.visibilitySamples;
        if (!layers) continue;
        for (int k = 0; k < layers->count(r); ++k)
            ++work[std::size_t(layers->layers(r)[k].record.patch)].work.transparentFragments;
    }
    return work;
}

}  // namespace

const char* visibilityMethodName(VisibilityMethod m) {
    return m == VisibilityMethod::Patch ? "patch" : "reference";
}

RenderResult renderScene(const SceneDesc& scene, const RenderOptions& options) {
    scene.rasterizer.validate(scene.path);
    if (options.maxLayers < 1 || options.maxLayers > 255)
        throw InputError("command line", "--max-layers", "must be in [1, 255]");
    RenderResult result;
    const int workers = resolveThreadCount(options.threads);
    auto start = std::chrono::steady_clock::now();
    const FrontEnd frontEnd(scene);
    result.effects =
        applyOverrides(detectEffects(scene, frontEnd.geometryMoves(), frontEnd.camera().moves()),
                       options.overrides);
    for (const SceneObject& object : frontEnd.objects())
        for (const std::string& note : objectNotes(object)) result.notes.push_back(note);
    const Camera& camera = frontEnd.camera();
    const std::size_t count = frontEnd.patchCount();
    std::vector<TessellatedPatch> patches(count);
    std::vector<MovingMesh> meshes(count);
    std::vector<FrontEndWorkspace> workspaces;
    for (int w = 0; w < workers; ++w) workspaces.push_back(frontEnd.makeWorkspace());
    {
        Progress progress("front end ", std::int64_t(count), 1, options.progress);
        parallelFor(count, workers, [&](int w, std::size_t i) {
            frontEnd.tessellate(i, patches[i], workspaces[std::size_t(w)]);
            const MaterialDesc& m =
                frontEnd.objects()[std::size_t(patches[i].object)].desc.material;
            const bool opaque =
                !result.effects.transparency || (m.opacity >= 1.0f && m.closeOpacity >= 1.0f);
            toMovingMesh(patches[i], camera, result.effects.motion, int(i), opaque, meshes[i]);
            progress.advance();
        });
    }
    result.patches = count;
    for (const TessellatedPatch& p : patches) result.triangles += p.triangleCount();
    result.frontEndSeconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    std::vector<PatchRasterWork> rasterWork(count);
    const SampleGenerator samples(
        scene.film.seed, scene.film.samplesPerPixel, result.effects,
        scene.film.gridSamples ? SamplePattern::Grid : SamplePattern::Stratified);
    const LensModel lens{result.effects.defocus ? scene.lens.apertureRadius : 0.0f,
                         scene.lens.focusDistance};
    result.visibility = std::make_unique<VisibilityBuffer>(
        scene.film.width, scene.film.height, scene.film.samplesPerPixel, camera.farPlane());
    if (result.effects.transparency)
        result.transparent = std::make_unique<TransparentLayers>(
            result.visibility->records().size(), options.maxLayers);
    if (options.heatMaps)
        result.pixelWork = std::make_unique<PixelWork>(scene.film.width, scene.film.height,
                                                       scene.rasterizer.tileSize);
    VisibilityTargets targets{result.visibility.get(), result.transparent.get(),
                              result.pixelWork.get(), 0};
    if (options.method == VisibilityMethod::Patch) {
        std::vector<std::size_t> order;
        if (options.patchOrderSeed) {
            order.resize(count);
            std::iota(order.begin(), order.end(), std::size_t(0));
            std::shuffle(order.begin(), order.end(), std::mt19937_64(options.patchOrderSeed));
        }
        const PatchRasterizer rasterizer(camera, lens, samples, result.effects, scene.rasterizer);
        Progress progress("visibility", std::int64_t(count) * kRowClasses, kRowClasses,
                          options.progress);
        rasterWork = runPatchVisibility(meshes, rasterizer, workers, targets, order, &progress);
    } else {
        Progress progress("reference ", kRowClasses, 1, options.progress);
        parallelFor(kRowClasses, workers, [&](int, std::size_t band) {
            ReferenceWork work;
            VisibilityTargets mine = targets;
            mine.pool = int(band);
            const int y0 = int(band) * scene.film.height / kRowClasses;
            const int y1 = int(band + 1) * scene.film.height / kRowClasses;
            renderReferenceRows(meshes, camera, lens, samples, y0, y1, mine, work);
            progress.advance();
        });
        rasterWork = referencePatchWork(meshes, *result.visibility, result.transparent.get());
    }
    result.visibilitySeconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    const ShadingContext context{&frontEnd, &patches, &meshes, &camera, &samples};
    {
        Progress progress("shading   ", scene.film.height, 1, options.progress, "rows");
        result.frame = resolveFrame(context, *result.visibility, result.transparent.get(),
                                    options.resolve, workers, &progress);
    }
    result.shadingSeconds = secondsSince(start);
    result.patchOps =
        collectPatchOps(patches, rasterWork,
                        shadingWorkPerPatch(*result.visibility, result.transparent.get(),
                                            options.resolve.shadingRate, count));
    return result;
}

}  // namespace patchsim
