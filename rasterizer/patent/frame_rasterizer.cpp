#include "rasterizer/patent/frame_rasterizer.h"

#include <memory>
#include <numeric>

#include "core/parallel.h"
#include "core/progress.h"
#include "rasterizer/patent/hierarchy_orders.h"
#include "rasterizer/patent/patch_merge.h"
#include "rasterizer/patent/tile_bins.h"

namespace patchsim {

namespace {

// Every group of every unit, prepared (hierarchy and covered tiles); a unit's work goes to its
// first patch. The groups' hierarchies share the leaf vertex tables of `orders`.
std::vector<std::vector<PatchRasterizer::Group>> prepareGroups(const RasterUnits& units,
                                                               const PatchRasterizer& rasterizer,
                                                               const HierarchyOrders& orders,
                                                               int threads,
                                                               std::vector<RasterWork>& work) {
    std::vector<std::vector<PatchRasterizer::Group>> groups(units.meshes.size());
    parallelFor(units.meshes.size(), threads, [&](int, std::size_t u) {
        const MovingMesh& mesh = *units.meshes[u];
        RasterWork& w = work[units.firstPatch[u]];
        w.patches += std::int64_t(units.patchCount[u]);
        if (units.patchCount[u] > 1) w.patchesMerged += std::int64_t(units.patchCount[u]);
        const HierarchyOrder& order = orders.of(u);
        const std::vector<std::uint32_t>& begin = order.groupBegin;
        for (std::size_t g = 0; g + 1 < begin.size(); ++g) {
            if (begin[g] == begin[g + 1]) continue;
            groups[u].emplace_back();
            rasterizer.prepareGroup(mesh, order.triangles.data() + begin[g],
                                    begin[g + 1] - begin[g], groups[u].back(), w,
                                    &order.leafTables[g]);
        }
    });
    return groups;
}

// Units in the order their first patch comes in `order`.
std::vector<std::size_t> unitOrder(const RasterUnits& units,
                                   const std::vector<std::size_t>& order) {
    std::vector<std::size_t> result;
    std::vector<bool> seen(units.meshes.size(), false);
    for (std::size_t i : order) {
        const std::size_t u = units.unitOf[i];
        if (seen[u]) continue;
        seen[u] = true;
        result.push_back(u);
    }
    return result;
}

// The frame's groups in raster order: units in patch order, each unit's groups in turn.
struct RasterOrder {
    std::vector<std::size_t> unit;   // per group
    std::vector<std::size_t> group;  // per group: its index in its unit
    std::vector<TileRange> covered;  // per group
};

RasterOrder rasterOrder(const std::vector<std::size_t>& units,
                        const std::vector<std::vector<PatchRasterizer::Group>>& groups) {
    RasterOrder order;
    for (std::size_t u : units)
        for (std::size_t g = 0; g < groups[u].size(); ++g) {
            order.unit.push_back(u);
            order.group.push_back(g);
            order.covered.push_back(groups[u][g].tiles);
        }
    return order;
}

// What one worker keeps across the tiles it takes.
struct Worker {
    std::unique_ptr<TileRays> rays;  // made on the worker's first tile
    std::vector<RasterWork> work;    // per patch
    std::unique_ptr<RegionTraceWriter> trace;
};

}  // namespace

FrameRasterWork rasterizeFrame(const std::vector<MovingMesh>& meshes,
                               const PatchRasterizer& rasterizer, const VisibilityTargets& targets,
                               const FrameRasterOptions& options) {
    std::vector<std::size_t> order = options.order;
    if (order.empty()) {
        order.resize(meshes.size());
        std::iota(order.begin(), order.end(), std::size_t(0));
    }
    FrameRasterWork work;
    work.hierarchies.resize(meshes.size());
    work.tiles.resize(meshes.size());
    const RasterizerOptions& ro = rasterizer.options();
    const RasterUnits units =
        makeRasterUnits(meshes, ro.mergeTrianglesBelow, ro.trianglesPerGroup());
    const HierarchyOrders orders(units.meshes, ro.trianglesPerGroup(), ro.leafSize,
                                 options.threads);
    const auto groups = prepareGroups(units, rasterizer, orders, options.threads, work.hierarchies);
    const RasterOrder raster = rasterOrder(unitOrder(units, order), groups);
    const TileGrid& grid = rasterizer.tileGrid();
    const TileBins bins(grid, raster.covered);
    const TileRayFrame frame{&rasterizer.camera(),
                             rasterizer.lens(),
                             {&rasterizer.samples(), options.sampleTable},
                             rasterizer.samples().samplesPerPixel(),
                             rasterizer.samples().effects().timeSamples(),
                             grid.tileSize,
                             targets.pixels != nullptr,
                             options.opaqueStartsEmpty,
                             // The geometry's effects, not the samples': a sharp frame of a moving
                             // scene (sharp_frame_method.h) samples one time of moving triangles.
                             rasterizer.effects().screenPlaneSamples(),
                             rasterizer.effects().lensPlaneSamples()};
    // One transparent-layer pool per worker.
    int threads = resolveThreadCount(options.threads);
    if (targets.transparent) threads = std::min(threads, targets.transparent->pools());
    std::vector<Worker> workers;
    workers.resize(std::size_t(threads));
    parallelFor(grid.tileCount(), threads, [&](int w, std::size_t t) {
        const int tx = int(t % std::size_t(grid.tilesX())),
                  ty = int(t / std::size_t(grid.tilesX()));
        if (!options.partition.ownsTileRow(ty)) return;
        const std::span<const std::uint32_t> bin = bins.groupsOf(t);
        if (!bin.empty()) {
            Worker& worker = workers[std::size_t(w)];
            if (!worker.rays) {
                worker.rays = std::make_unique<TileRays>(frame);
                worker.work.resize(meshes.size());
                if (options.memoryTrace) {
                    worker.trace = std::make_unique<RegionTraceWriter>(*options.memoryTrace);
                    worker.trace->keepEmptyPasses();  // a tile test reads the hierarchy
                    worker.rays->trace = worker.trace.get();
                }
            }
            TileRays& rays = *worker.rays;
            rays.load(grid.rect(tx, ty), *targets.opaque);
            if (worker.trace) worker.trace->beginRegion(t);
            VisibilityTargets mine = targets;
            mine.pool = w;
            for (std::uint32_t g : bin) {
                const std::size_t u = raster.unit[g];
                if (worker.trace) worker.trace->beginPass(std::uint32_t(units.firstPatch[u]));
                rasterizer.rasterizeTile(*units.meshes[u], groups[u][raster.group[g]], tx, ty, rays,
                                         mine, worker.work[units.firstPatch[u]]);
                if (worker.trace) worker.trace->endPass();
            }
            rays.store(*targets.opaque, targets.pixels);
        }
        if (options.progress) options.progress->advance();
    });
    for (const Worker& worker : workers)
        for (std::size_t i = 0; i < worker.work.size(); ++i) work.tiles[i].add(worker.work[i]);
    return work;
}

}  // namespace patchsim
