#include "rasterizer/frame_rasterizer.h"

#include <numeric>

#include "pipeline/core/parallel.h"
#include "pipeline/core/progress.h"
#include "rasterizer/tile_samples.h"
#include "rasterizer/z_culling.h"

namespace patchsim {

namespace {

// Every group of every patch, prepared (hierarchy and covered tiles).
std::vector<std::vector<PatchRasterizer::Group>> prepareGroups(
    const std::vector<MovingMesh>& meshes, const PatchRasterizer& rasterizer, int threads,
    std::vector<RasterWork>& work) {
    std::vector<std::vector<PatchRasterizer::Group>> groups(meshes.size());
    parallelFor(meshes.size(), threads, [&](int, std::size_t i) {
        ++work[i].patches;
        std::vector<std::uint32_t> triangles, groupBegin;
        splitIntoGroups(meshes[i], rasterizer.options().trianglesPerGroup(), triangles, groupBegin);
        for (std::size_t g = 0; g + 1 < groupBegin.size(); ++g) {
            if (groupBegin[g] == groupBegin[g + 1]) continue;
            groups[i].emplace_back();
            rasterizer.prepareGroup(meshes[i], triangles.data() + groupBegin[g],
                                    groupBegin[g + 1] - groupBegin[g], groups[i].back(), work[i]);
        }
    });
    return groups;
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
    const auto groups = prepareGroups(meshes, rasterizer, options.threads, work.hierarchies);
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
        for (std::size_t i : order) {
            RasterWork& tileWork = classWork[rowClassIndex][i];
            for (const PatchRasterizer::Group& group : groups[i]) {
                for (int ty = group.tiles.y0; ty < std::min(group.tiles.y1, tileRows); ++ty) {
                    if (!inRowClass(ty, rowClass)) continue;
                    for (int tx = group.tiles.x0; tx < group.tiles.x1; ++tx)
                        rasterizer.rasterizeTile(meshes[i], group, tx, ty, mine, tileWork);
                }
            }
            if (options.progress) options.progress->advance();
        }
    });
    for (const auto& rows : classWork)
        for (std::size_t i = 0; i < meshes.size(); ++i) work.tiles[i].add(rows[i]);
    return work;
}

}  // namespace patchsim
