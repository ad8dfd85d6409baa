#include "pipeline/methods/patch_method.h"

#include <algorithm>
#include <numeric>
#include <random>

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "rasterizer/patent/frame_rasterizer.h"
#include "rasterizer/patent/tile_rays.h"

namespace patchsim {

void rasterizePatches(const FrameInputs& in, const PatchPass& pass, std::vector<PatchOps>& ops) {
    const RenderOptions& options = *in.options;
    FrameRasterOptions frame;
    frame.threads = in.workers;
    frame.opaqueStartsEmpty = true;  // the buffers the render driver makes
    frame.partition = pass.partition;
    frame.memoryTrace = pass.memoryTrace;
    if (options.patchOrderSeed) {
        frame.order.resize(in.meshes->size());
        std::iota(frame.order.begin(), frame.order.end(), std::size_t(0));
        std::shuffle(frame.order.begin(), frame.order.end(),
                     std::mt19937_64(options.patchOrderSeed));
    }
    const LensModel lens{pass.rasterized.defocus ? in.scene->lens.apertureRadius : 0.0f,
                         in.scene->lens.focusDistance};
    const PatchRasterizer rasterizer(in.camera(), lens, *pass.samples, pass.rasterized,
                                     in.scene->rasterizer);
    const std::unique_ptr<ProgressShare> progressShare =
        pass.partition.split() && options.share.progressShare ? options.share.progressShare()
                                                              : nullptr;
    Progress progress("visibility", std::int64_t(rasterizer.tileGrid().tileCount()), 1,
                      pass.progress, "tiles", progressShare.get());
    frame.progress = &progress;
    const FrameRasterWork work = rasterizeFrame(*in.meshes, rasterizer, pass.targets, frame);
    progress.finish();
    const bool first = pass.partition.rank == 0;
    for (std::size_t i = 0; i < work.tiles.size(); ++i) {
        work.tiles[i].flush();
        work.tiles[i].charge(ops[i]);
        if (!first) continue;
        work.hierarchies[i].flush();
        work.hierarchies[i].charge(ops[i]);
    }
}

void checkTileScratch(const SceneDesc& scene, const RenderOptions& options, int workers) {
    const FilmDesc& film = scene.film;
    const int tileSize = scene.rasterizer.tileSize;
    const auto tiles = std::int64_t(TileGrid{film.width, film.height, tileSize}.tileCount());
    const auto rasterWorkers = std::uint64_t(std::min(std::int64_t(workers), tiles));
    const std::uint64_t scratch =
        TileRays::bytesFor(tileSize, film.samplesPerPixel, options.heatMaps, true, true);
    const std::uint64_t total = filmBytes(film) + rasterWorkers * scratch;
    if (total <= options.memoryBudgetBytes) return;
    const auto mib = [](std::uint64_t bytes) {
        return std::to_string((bytes + (1u << 20) - 1) >> 20);
    };
    throw InputError(
        scene.path, "rasterizer.tile_size",
        "tiles of " + std::to_string(tileSize) + "x" + std::to_string(tileSize) + " pixels at " +
            std::to_string(film.samplesPerPixel) + " spp need " + mib(scratch) +
            " MiB of ray scratch in each of " + std::to_string(rasterWorkers) +
            " rasterizer workers (--threads); with the film's " + mib(filmBytes(film)) +
            " MiB that is " + mib(total) + " MiB, over the memory budget of " +
            std::to_string(options.memoryBudgetBytes >> 20) +
            " MiB (--memory-budget-mib): use smaller tiles or fewer threads");
}

namespace {

class PatchFrame : public TiledFrame {
  public:
    using TiledFrame::TiledFrame;
    void visibility() override {
        rasterizePatches(in_,
                         {in_.samples, in_.effects, in_.targets, in_.partition,
                          in_.options->progress, in_.memoryTrace},
                         ops_);
    }
};

class PatchMethod : public VisibilityMethod {
  public:
    const char* name() const override { return "patch"; }
    const char* after() const override { return "US 8,791,945: moving-box hierarchy per patch"; }
    bool exact() const override { return true; }
    bool roundsTriangleTests() const override { return true; }
    bool countsPerPixel() const override { return true; }
    bool rasterizesPatches() const override { return true; }
    std::unique_ptr<MemoryTrace> makeMemoryTrace(const SceneDesc& scene) const override {
        return std::make_unique<MemoryTrace>(MemoryTrace::tiles(scene.film.width, scene.film.height,
                                                                scene.rasterizer.tileSize,
                                                                scene.film.samplesPerPixel));
    }
    void check(const SceneDesc& scene, const RenderOptions& options, int workers) const override {
        VisibilityMethod::check(scene, options, workers);
        checkTileScratch(scene, options, workers);
    }
    std::unique_ptr<MethodFrame> start(const FrameInputs& in) const override {
        return std::make_unique<PatchFrame>(in);
    }
    const RatioCounter& sampleTestEfficiency() const override {
        return patchsim::sampleTestEfficiency();
    }
    VisibilityTotals totals(const CounterValues& v) const override {
        const RasterCounters& c = rasterCounters();
        return {v[c.samplesTested], v[c.raysCast], v[c.visibilitySamples],
                v.ratio(sampleTestEfficiency())};
    }
};

}  // namespace

const VisibilityMethod& patchMethod() {
    static const PatchMethod method;
    return method;
}

}  // namespace patchsim
