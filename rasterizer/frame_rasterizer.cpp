#include "rasterizer/frame_rasterizer.h"

#include <numeric>

#include "pipeline/core/parallel.h"
#include "pipeline/core/progress.h"
#include "rasterizer/patch_merge.h"
#include "rasterizer/tile_samples.h"
#include "rasterizer/z_culling.h"

namespace patchsim {

namespace {

// Every group of every unit, prepared (hierarchy and covered tiles); a unit's work goes to its
// first patch.
std::vector<std::vector<PatchRasterizer::Group>> prepareGroups(const RasterUnits& units,
                                                               const PatchRasterizer& rasterizer,
                                                               int threads,
                                                               std::vector<RasterWork>& work) {
    std::vector<std::vector<PatchRasterizer::Group>> groups(units.meshes.size());
    parallelFor(units.meshes.size(), threads, [&](int, std::size_t u) {
        const MovingMesh& mesh = *units.meshes[u];
        RasterWork& w = work[units.firstPatch[u]];
        w.patches += std::int64_t(units.patchCount[u]);
        if (units.patchCount[u] > 1) w.patchesMerged += std::int64_t(units.patchCount[u]);
        std::vector<std::uint32_t> triangles, groupBegin;
        splitIntoGroups(mesh, rasterizer.options().trianglesPerGroup(), triangles, groupBegin);
        for (std::size_t g = 0; g + 1 < groupBegin.size(); ++g) {
            if (groupBegin[g] == groupBegin[g + 1]) continue;
            groups[u].emplace_back();
            rasterizer.prepareGroup(mesh, triangles.data() + groupBegin[g],
                                    groupBegin[g + 1] - groupBegin[g], groups[u].back(), w);
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
    const std::vector<std::size_t> unitsInOrder = unitOrder(units, order);
    const auto groups = prepareGroups(units, rasterizer, options.threads, work.hierarchies);
    const TileSamples tileSamples(rasterizer.tileGrid(), rasterizer.caster().camera,
                                  rasterizer.caster().samples, options.threads);
    TileDepthBounds depthBounds(rasterizer.tileGrid(), *targets.opaque);
    // Tile work per row class and patch (fixed slots), added up in a fixed order afterwards.
    std::vector<std::vector<RasterWork>> classWork(kRowClasses,
                                                   std::vector<RasterWork>(meshes.size()));
    const int tileRows = rasterizer.tileGrid().tilesY();
    parallelFor(kRowClasses, options.threads, [&](int, std::size_t rowClassIndex) {
        const int rowClass = int(rowClassIndex);
        if (options.ownsRowClass && !options.ownsRowClass(rowClass)) return;
        VisibilityTargets mine = targets;
        mine.pool = rowClass;
        mine.tileSamples = &tileSamples;
        mine.depthBounds = &depthBounds;
        for (std::size_t u : unitsInOrder) {
            RasterWork& tileWork = classWork[rowClassIndex][units.firstPatch[u]];
            for (const PatchRasterizer::Group& group : groups[u]) {
                for (int ty = group.tiles.y0; ty < std::min(group.tiles.y1, tileRows); ++ty) {
                    if (!inRowClass(ty, rowClass)) continue;
                    for (int tx = group.tiles.x0; tx < group.tiles.x1; ++tx)
                        rasterizer.rasterizeTile(*units.meshes[u], group, tx, ty, mine, tileWork);
                }
            }
            if (options.progress) options.progress->advance(std::int64_t(units.patchCount[u]));
        }
    });
    for (const auto& rows : classWork)
        for (std::size_t i = 0; i < meshes.size(); ++i) work.tiles[i].add(rows[i]);
    return work;
}

}  // namespace patchsim
