#include "pipeline/driver/render.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <random>

#include "pipeline/core/error.h"
#include "pipeline/core/parallel.h"
#include "pipeline/core/progress.h"
#include "pipeline/driver/frame_share.h"
#include "pipeline/driver/scene_info.h"
#include "rasterizer/bounding_rasterizer.h"
#include "rasterizer/frame_rasterizer.h"
#include "rasterizer/reference_rasterizer.h"
#include "rasterizer/tile_grid.h"
#include "rasterizer/tile_rays.h"
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

FrontEndOutput runFrontEnd(const FrontEnd& frontEnd, const Effects& effects, int workers,
                           bool progressBar) {
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
        progress.advance();
    });
    return out;
}

// The reference method's work per patch, charged to the rasterizer stage like the patch method's:
// every sample is tested against every triangle of every patch; its hits are written.
std::vector<RasterWork> referencePatchWork(const std::vector<MovingMesh>& meshes,
                                           const VisibilityBuffer& buffer,
                                           const TransparentLayers* layers) {
    std::vector<RasterWork> work(meshes.size());
    const auto samples = std::int64_t(buffer.records().size());
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        work[i].samplesTested = samples;
        work[i].raysCast = samples;
        work[i].rayTriangleTests = samples * std::int64_t(meshes[i].triangleCount());
    }
    for (std::size_t r = 0; r < buffer.records().size(); ++r) {
        const VisibilityRecord& record = buffer.records()[r];
        if (record.hit()) ++work[std::size_t(record.patch)].visibilitySamples;
        if (!layers) continue;
        for (int k = 0; k < layers->count(r); ++k)
            ++work[std::size_t(layers->layers(r)[k].record.patch)].transparentFragments;
    }
    return work;
}

// The front end's, the shader's and the output merger's share of each patch's work; the
// visibility method adds its own (charge*).
std::vector<PatchOps> collectPatchOps(const std::vector<TessellatedPatch>& patches,
                                      const std::vector<double>& shading) {
    std::vector<PatchOps> ops(patches.size());
    for (std::size_t i = 0; i < patches.size(); ++i) {
        const TessellatedPatch& p = patches[i];
        PatchOps& o = ops[i];
        const double points = double(p.tessellation.points.size());
        o[Op::Patches] = 1;
        o[Op::ControlPoints] = p.controlPoints;
        o[Op::EdgeFactors] = p.domain == PatchDomain::Quad ? 4 : 3;
        o[Op::DomainPoints] = points;
        o[Op::Triangles] = double(p.triangleCount());
        o[Op::Evaluations] = p.culled() ? 0 : points;
        o[Op::StencilApplications] = p.culled() ? 0 : 6 * points;
        o[Op::Invocations] = shading[i];
    }
    return ops;
}

void chargeRasterWork(const RasterWork& w, PatchOps& o) {
    // A node converted to the 2DH or 2D bounds space costs what building one does: one pass over
    // its two boxes.
    o[Op::NodesBuilt] = double(w.nodesBuilt + w.nodesConverted);
    o[Op::PlaneTests] = double(w.planeTests);
    o[Op::TimeIntervals] = double(w.timeIntervals);
    o[Op::SamplesTested] = double(w.samplesTested);
    o[Op::RayBoxTests] = double(w.rayBoxTests);
    o[Op::RayTriangleTests] = double(w.rayTriangleTests);
    o[Op::DepthTests] = double(w.visibilitySamples);
    o[Op::TransparentFragments] = double(w.transparentFragments);
    o.hierarchyBytes = std::uint64_t(w.peakHierarchyBytes);
}

void chargeBoundingWork(const BoundingWork& w, PatchOps& o) {
    o[Op::TriangleSetups] = double(w.triangleSetups);
    o[Op::SamplesTested] = double(w.samplesTested);
    o[Op::RayTriangleTests] = double(w.samplesTested);
    o[Op::DepthTests] = double(w.visibilitySamples);
    o[Op::TransparentFragments] = double(w.transparentFragments);
}

Bounding boundingOf(VisibilityMethod m) {
    return m == VisibilityMethod::Interval      ? Bounding::Interval
           : m == VisibilityMethod::Interleaved ? Bounding::Interleaved
                                                : Bounding::TriangleBBox;
}

bool isBoundingMethod(VisibilityMethod m) {
    return m == VisibilityMethod::TriangleBBox || m == VisibilityMethod::Interval ||
           m == VisibilityMethod::Interleaved;
}

// The image-space methods start from one sharp frame at mid-shutter through a pinhole.
// (reprojection: two, at shutter open and close).
bool startsFromSharpFrame(VisibilityMethod m) {
    return m == VisibilityMethod::Postprocess || m == VisibilityMethod::Hybrid ||
           m == VisibilityMethod::Reprojection;
}

// ... which the patch rasterizer renders.
bool usesPatchRasterizer(VisibilityMethod m) {
    return m == VisibilityMethod::Patch || startsFromSharpFrame(m);
}

// Reference rows are dealt in this many horizontal bands, like the patch method's row classes.
constexpr int kReferenceBands = kRowClasses;

struct Visibility {
    std::vector<RasterWork> hierarchies, tiles;  // per patch (patch method)
    std::vector<BoundingWork> bounding;          // per patch (bounding-box methods)
    std::function<bool(int y)> ownsPixelRow;     // rows this process filled
    std::function<bool(int ty)> ownsTileRow;
};

Visibility runVisibility(const SceneDesc& scene, const RenderOptions& options,
                         const FrontEndOutput& fe, const Camera& camera,
                         const SampleGenerator& samples, const Effects& effects,
                         const VisibilityTargets& targets, int workers) {
    const LensModel lens{effects.defocus ? scene.lens.apertureRadius : 0.0f,
                         scene.lens.focusDistance};
    const FrameShare& share = options.share;
    const auto ownsClass = [share](int c) { return c % share.ranks == share.rank; };
    const std::size_t count = fe.meshes.size();
    Visibility v;
    if (usesPatchRasterizer(options.method)) {
        FrameRasterOptions frame;
        frame.threads = workers;
        frame.opaqueStartsEmpty = true;  // the buffers renderScene makes
        if (options.patchOrderSeed) {
            frame.order.resize(count);
            std::iota(frame.order.begin(), frame.order.end(), std::size_t(0));
            std::shuffle(frame.order.begin(), frame.order.end(),
                         std::mt19937_64(options.patchOrderSeed));
        }
        if (share.split()) frame.ownsRowClass = ownsClass;
        const PatchRasterizer rasterizer(camera, lens, samples, effects, scene.rasterizer);
        const std::unique_ptr<ProgressShare> progressShare =
            share.progressShare ? share.progressShare() : nullptr;
        Progress progress("visibility", std::int64_t(rasterizer.tileGrid().tileCount()), 1,
                          options.progress, "tiles", progressShare.get());
        frame.progress = &progress;
        FrameRasterWork work = rasterizeFrame(fe.meshes, rasterizer, targets, frame);
        progress.finish();
        v.hierarchies = std::move(work.hierarchies);
        v.tiles = std::move(work.tiles);
        const int tileSize = rasterizer.tileGrid().tileSize;
        v.ownsTileRow = [ownsClass](int ty) { return ownsClass(ty % kRowClasses); };
        v.ownsPixelRow = [ownsClass, tileSize](int y) {
            return ownsClass((y / tileSize) % kRowClasses);
        };
        return v;
    }
    // The reference and the bounding-box methods work in horizontal bands of rows.
    const int height = scene.film.height;
    v.hierarchies.resize(count);
    v.tiles.resize(count);
    v.ownsTileRow = [](int) { return false; };
    v.ownsPixelRow = [ownsClass, height](int y) {
        for (int band = 0; band < kReferenceBands; ++band)
            if (y < (band + 1) * height / kReferenceBands) return ownsClass(band);
        return false;
    };
    if (isBoundingMethod(options.method)) {
        const RayCaster caster{camera, lens, samples, effects.motion, true};
        BoundingOptions bounding;
        bounding.method = boundingOf(options.method);
        bounding.timeStrata = options.timeStrata;
        bounding.threads = workers;
        if (share.split()) bounding.ownsBand = ownsClass;
        v.bounding = rasterizeByBounds(fe.meshes, caster, targets, bounding);
        return v;
    }
    const std::unique_ptr<ProgressShare> progressShare =
        share.progressShare ? share.progressShare() : nullptr;
    Progress progress("reference ", kReferenceBands, 1, options.progress, "bands",
                      progressShare.get());
    parallelFor(kReferenceBands, workers, [&](int, std::size_t band) {
        if (share.split() && !ownsClass(int(band))) return;
        ReferenceWork work;
        VisibilityTargets mine = targets;
        mine.pool = int(band);
        const int y0 = int(band) * height / kReferenceBands;
        const int y1 = int(band + 1) * height / kReferenceBands;
        renderReferenceRows(fe.meshes, camera, lens, samples, y0, y1, mine, work);
        progress.advance();
    });
    progress.finish();
    return v;
}

}  // namespace

const RatioCounter& sampleTestEfficiencyOf(VisibilityMethod method) {
    if (usesPatchRasterizer(method)) return sampleTestEfficiency();
    if (method == VisibilityMethod::Reference) return referenceSampleTestEfficiency();
    if (method == VisibilityMethod::TFragment) return tfragmentSampleTestEfficiency();
    return boundingSampleTestEfficiency(boundingOf(method));
}

VisibilityTotals visibilityTotals(const CounterValues& v, VisibilityMethod method) {
    VisibilityTotals t;
    t.sampleTestEfficiency = v.ratio(sampleTestEfficiencyOf(method));
    if (method == VisibilityMethod::TFragment) {
        // Its samples tested are its motion samples' t-fragment tests, its rays the lens rays.
        const RatioCounter& ste = tfragmentSampleTestEfficiency();
        t = {v[ste.denominator], v.byName("TF/Lens rays"), v[ste.numerator],
             t.sampleTestEfficiency};
        return t;
    }
    if (usesPatchRasterizer(method)) {
        const RasterCounters& c = rasterCounters();
        t = {v[c.samplesTested], v[c.raysCast], v[c.visibilitySamples], t.sampleTestEfficiency};
    } else if (method == VisibilityMethod::Reference) {
        const ReferenceCounters& c = referenceCounters();
        t = {v[c.samples], v[c.samples], v[c.hits], t.sampleTestEfficiency};
    } else {
        const BoundingCounters& c = boundingCounters(boundingOf(method));
        t = {v[c.samplesTested], v[c.samplesTested], v[c.visibilitySamples],
             t.sampleTestEfficiency};
    }
    return t;
}

namespace {

// The approximate methods' own work, beyond the sharp frames the patch rasterizer renders.
struct ApproximateWork {
    PostprocessWork post;
    HybridWork hybrid;
    ReprojectionWork reprojection;
    TFragmentWork tfragment;
    void flush() const {
        post.flush();
        hybrid.flush();
        reprojection.flush();
        tfragment.flush();
    }
};

// Charged with the frame's last patch: the passes and rays run once it is shaded.
void chargeApproximateWork(const ApproximateWork& w, PatchOps& last) {
    auto& ops = last.ops;
    ops[std::size_t(Op::PostSamples)] += double(w.post.pixels + w.post.gatherSamples +
                                                w.hybrid.maskReads + w.reprojection.reprojections);
    ops[std::size_t(Op::RayBoxTests)] += double(w.hybrid.rayBoxTests + w.tfragment.rayNodeTests);
    ops[std::size_t(Op::RayTriangleTests)] +=
        double(w.hybrid.rayTriangleTests + w.tfragment.capsuleTests + w.tfragment.sphereTests +
               w.tfragment.cubeTests);
    // The t-fragment method: its rasterization, hierarchy, and the shading of every motion sample
    // beyond the one per sample the resolve charges.
    ops[std::size_t(Op::SamplesTested)] += double(w.tfragment.rasterizedFragments);
    ops[std::size_t(Op::NodesBuilt)] += double(w.tfragment.bvhNodes);
    ops[std::size_t(Op::Invocations)] += double(w.tfragment.motionSamples - w.tfragment.lensRays);
}

}  // namespace

void checkFrameMemory(const SceneDesc& scene, const RenderOptions& options,
                      const std::string& source) {
    if (!usesPatchRasterizer(options.method)) return;
    const int workers = resolveThreadCount(options.threads);
    const FilmDesc& film = scene.film;
    const int tileSize = scene.rasterizer.tileSize;
    const auto tiles = std::int64_t(TileGrid{film.width, film.height, tileSize}.tileCount());
    const auto rasterWorkers = std::uint64_t(
        std::min({std::int64_t(workers), std::int64_t(TransparentLayers::kPools), tiles}));
    const std::uint64_t scratch =
        TileRays::bytesFor(tileSize, film.samplesPerPixel, options.heatMaps, true);
    const std::uint64_t total = filmBytes(film) + rasterWorkers * scratch;
    if (total <= options.memoryBudgetBytes) return;
    const auto mib = [](std::uint64_t bytes) {
        return std::to_string((bytes + (1u << 20) - 1) >> 20);
    };
    throw InputError(
        source, "rasterizer.tile_size",
        "tiles of " + std::to_string(tileSize) + "x" + std::to_string(tileSize) + " pixels at " +
            std::to_string(film.samplesPerPixel) + " spp need " + mib(scratch) +
            " MiB of ray scratch in each of " + std::to_string(rasterWorkers) +
            " rasterizer workers (--threads); with the film's " + mib(filmBytes(film)) +
            " MiB that is " + mib(total) + " MiB, over the memory budget of " +
            std::to_string(options.memoryBudgetBytes >> 20) +
            " MiB (--memory-budget-mib): use smaller tiles or fewer threads");
}

RenderResult renderScene(const SceneDesc& scene, const RenderOptions& options) {
    scene.rasterizer.validate(scene.path);
    scene.rasterizer.validateTileSamples(scene.film.samplesPerPixel, scene.path);
    if (options.maxLayers < 1 || options.maxLayers > 255)
        throw InputError("command line", "--max-layers", "must be in [1, 255]");
    if (options.heatMaps && !usesPatchRasterizer(options.method))
        throw InputError("command line", "--heatmaps",
                         std::string("the ") + visibilityMethodName(options.method) +
                             " method does not count its work per pixel; heat maps come from "
                             "the patch rasterizer (patch, postprocess, hybrid, reprojection)");
    RenderResult result;
    const int workers = resolveThreadCount(options.threads);
    checkFrameMemory(scene, options, scene.path);
    auto start = std::chrono::steady_clock::now();
    const FrontEnd frontEnd(scene, workers);
    result.effects =
        applyOverrides(detectEffects(scene, frontEnd.geometryMoves(), frontEnd.camera().moves()),
                       options.overrides);
    for (const SceneObject& object : frontEnd.objects())
        for (const std::string& note : objectNotes(object)) result.notes.push_back(note);
    const Camera& camera = frontEnd.camera();
    const FrontEndOutput fe = runFrontEnd(frontEnd, result.effects, workers, options.progress);
    result.patches = fe.patches.size();
    for (const TessellatedPatch& p : fe.patches) result.triangles += p.triangleCount();
    result.frontEndSeconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    // The interleaved method is an accumulation buffer: its samples repeat in every pixel. The
    // image-space methods start from sharp frames: every sample at one time, through a pinhole
    // (mid-shutter; the reprojection's at shutter open, and a second one at close).
    const bool sharpFrame = startsFromSharpFrame(options.method);
    const bool reprojection = options.method == VisibilityMethod::Reprojection;
    Effects sampled = result.effects, rasterized = result.effects;
    if (sharpFrame) {
        sampled.motion = sampled.shadingVaries = sampled.defocus = false;
        rasterized.defocus = false;
    }
    const SampleGenerator samples(scene.film.seed, scene.film.samplesPerPixel, sampled,
                                  options.method == VisibilityMethod::Interleaved
                                      ? SamplePattern::Interleaved
                                      : scene.film.sampler,
                                  sharpFrame && !reprojection ? 0.5f : 0.0f);
    result.visibility =
        std::make_unique<VisibilityBuffer>(scene.film.width, scene.film.height,
                                           scene.film.samplesPerPixel, camera.farPlane(), workers);
    if (result.effects.transparency)
        result.transparent = std::make_unique<TransparentLayers>(
            result.visibility->records().size(), options.maxLayers);
    if (options.heatMaps)
        result.pixels = std::make_unique<PixelCounters>(
            TileGrid{scene.film.width, scene.film.height, scene.rasterizer.tileSize});
    const VisibilityTargets targets{result.visibility.get(), result.transparent.get(),
                                    result.pixels.get(), 0};
    const CounterValues beforeVisibility = CounterRegistry::instance().snapshot();
    const ShadingContext context{&frontEnd, &fe.patches, &fe.meshes, &camera};
    const bool tfragment = options.method == VisibilityMethod::TFragment;
    ApproximateWork approximate;
    std::vector<float> tfragmentColors;
    Visibility visibility;
    if (tfragment && options.share.split())
        throw InputError("command line", "--method", "tfragment does not split across MPI ranks");
    if (tfragment) {
        const LensModel lens{result.effects.defocus ? scene.lens.apertureRadius : 0.0f,
                             scene.lens.focusDistance};
        tfragmentColors = renderTFragments(context, samples, lens, options.tfragment,
                                           options.tfragmentTimeSampled, workers,
                                           *result.visibility, approximate.tfragment);
    } else {
        visibility =
            runVisibility(scene, options, fe, camera, samples, rasterized, targets, workers);
    }
    for (const RasterWork& w : visibility.tiles) w.flush();
    const FrameShare& share = options.share;
    if (share.split()) {
        // Every rank built every hierarchy; only rank 0 counts them. The others send their rows,
        // their tile work and what their visibility step counted.
        CounterValues counts = CounterRegistry::instance().snapshot().since(beforeVisibility);
        const FrameRows rows{result.visibility.get(), result.transparent.get(), result.pixels.get(),
                             &visibility.tiles,       &visibility.bounding,     &counts};
        const std::vector<std::string> parts = share.gather(
            share.root() ? std::string()
                         : packFrameRows(rows, visibility.ownsPixelRow, visibility.ownsTileRow));
        if (!share.root()) {
            result.complete = false;
            return result;
        }
        for (std::size_t r = 1; r < parts.size(); ++r) {
            unpackFrameRows(parts[r], rows);
            CounterRegistry::instance().merge(counts);
        }
    }
    // The reprojection's second sharp frame, at shutter close (on every rank, in full).
    const SampleGenerator closeSamples(scene.film.seed, scene.film.samplesPerPixel, sampled,
                                       scene.film.sampler, 1.0f);
    std::unique_ptr<VisibilityBuffer> closeFrame;
    std::unique_ptr<TransparentLayers> closeLayers;
    if (reprojection) {
        closeFrame = std::make_unique<VisibilityBuffer>(scene.film.width, scene.film.height,
                                                        scene.film.samplesPerPixel,
                                                        camera.farPlane(), workers);
        if (result.transparent)
            closeLayers = std::make_unique<TransparentLayers>(closeFrame->records().size(),
                                                              options.maxLayers);
        RenderOptions whole = options;
        whole.share = {};
        Visibility second =
            runVisibility(scene, whole, fe, camera, closeSamples, rasterized,
                          {closeFrame.get(), closeLayers.get(), nullptr, 0}, workers);
        for (const RasterWork& w : second.tiles) w.flush();
        for (std::size_t i = 0; i < result.patches; ++i) {
            visibility.hierarchies[i].add(second.hierarchies[i]);
            visibility.tiles[i].add(second.tiles[i]);
        }
    }
    std::vector<PatchOps> visibilityOps(result.patches);
    for (std::size_t i = 0; i < result.patches; ++i) {
        if (usesPatchRasterizer(options.method)) {
            visibility.hierarchies[i].flush();
            RasterWork work = visibility.hierarchies[i];
            work.add(visibility.tiles[i]);
            chargeRasterWork(work, visibilityOps[i]);
        } else if (isBoundingMethod(options.method)) {
            visibility.bounding[i].flush(boundingOf(options.method));
            chargeBoundingWork(visibility.bounding[i], visibilityOps[i]);
        }
    }
    if (options.method == VisibilityMethod::Reference) {
        const std::vector<RasterWork> work =
            referencePatchWork(fe.meshes, *result.visibility, result.transparent.get());
        for (std::size_t i = 0; i < result.patches; ++i)
            chargeRasterWork(work[i], visibilityOps[i]);
    }
    result.visibilitySeconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    {
        Progress progress("shading   ", scene.film.height, 1, options.progress, "rows");
        result.frame = resolveFrame(context, *result.visibility, result.transparent.get(), samples,
                                    options.resolve, workers, &progress);
    }
    if (tfragment) {
        result.frame.color =
            filterSamples(tfragmentColors, *result.visibility, samples, options.resolve, workers);
    } else if (reprojection && result.effects.motion) {
        // The opaque hits' colours: the transparent layers are reprojected as parts of their own.
        const std::vector<float> openColors = shadeSamples(context, *result.visibility, nullptr,
                                                           options.resolve.shadingRate, workers);
        const std::vector<float> closeColors =
            shadeSamples(context, *closeFrame, nullptr, options.resolve.shadingRate, workers);
        // Holes take the blend of the two frames as the resolve shows them, layers and all.
        const Image closePixels =
            filterSamples(closeLayers ? shadeSamples(context, *closeFrame, closeLayers.get(),
                                                     options.resolve.shadingRate, workers)
                                      : closeColors,
                          *closeFrame, closeSamples, options.resolve, workers);
        result.frame.color = reprojectSamples(
            context,
            {result.visibility.get(), result.transparent.get(), &openColors, &samples, 0.0f},
            {closeFrame.get(), closeLayers.get(), &closeColors, &closeSamples, 1.0f},
            result.frame.color, closePixels, options.reprojection, approximate.reprojection);
    } else if (sharpFrame && result.effects.motion) {
        PostprocessOptions o = options.postprocess;
        o.seed = scene.film.seed;
        if (options.method == VisibilityMethod::Hybrid)
            result.frame.color =
                hybridMotionBlur(context, result.frame, *result.visibility,
                                 {o, options.edgeThreshold}, approximate.post, approximate.hybrid);
        else
            result.frame.color =
                reconstructMotionBlur(result.frame, camera.farPlane(), o, approximate.post);
    }
    approximate.flush();
    result.shadingSeconds = secondsSince(start);
    result.patchOps = collectPatchOps(fe.patches, result.frame.shadedPerPatch);
    for (std::size_t i = 0; i < result.patches; ++i)
        for (int op = 0; op < kOpCount; ++op)
            if (stageOf(Op(op)) == Stage::RS || op == int(Op::DepthTests) ||
                op == int(Op::TransparentFragments))
                result.patchOps[i].ops[std::size_t(op)] += visibilityOps[i].ops[std::size_t(op)];
    for (std::size_t i = 0; i < result.patches; ++i)
        result.patchOps[i].hierarchyBytes = visibilityOps[i].hierarchyBytes;
    if (!result.patchOps.empty()) chargeApproximateWork(approximate, result.patchOps.back());
    return result;
}

}  // namespace patchsim
