#include "rasterizer/patch_rasterizer.h"

#include "rasterizer/branch_node.h"
#include "rasterizer/screen_bounds.h"
#include "rasterizer/tile_frustum.h"
#include "rasterizer/tile_traversal.h"
#include "rasterizer/z_culling.h"

namespace patchsim {

PatchRasterizer::PatchRasterizer(const Camera& camera, const LensModel& lens,
                                 const SampleGenerator& samples, const Effects& effects,
                                 const RasterizerOptions& options)
    : caster_{camera, lens, samples, effects.motion, options.zCulling},
      effects_(effects),
      options_(options),
      grid_{camera.width(), camera.height(), options.tileSize} {
    if (!effects_.defocus) caster_.lens.radius = 0;
}

void PatchRasterizer::prepareGroup(const MovingMesh& mesh, const std::uint32_t* triangles,
                                   std::size_t count, Group& group, RasterWork& work) const {
    group.hierarchy.build(mesh, triangles, count, options_.leafSize);
    ++work.groups;
    work.nodesBuilt += group.hierarchy.nodeCount();
    const auto bytes = std::int64_t(group.hierarchy.bytes());
    work.hierarchyBytes += bytes;
    work.peakHierarchyBytes = std::max(work.peakHierarchyBytes, bytes);
    group.nodes.build(group.hierarchy, options_.boundsSpace, caster_.camera, caster_.lens, work);
    // In 2D the nodes are already projected: the bounds are their rectangles' union.
    const ScreenBounds bounds =
        options_.boundsSpace == BoundsSpace::Screen2D
            ? screenBounds(group.hierarchy, options_.boundsLevel, caster_.camera,
                           group.nodes.screen)
            : screenBounds(group.hierarchy, options_.boundsLevel, caster_.camera, caster_.lens);
    work.fullScreenBounds += bounds.fullScreen;
    group.tiles = tilesCovering(bounds, grid_);
}

void PatchRasterizer::rasterizeTile(const MovingMesh& mesh, const Group& group, int tileX,
                                    int tileY, const VisibilityTargets& targets,
                                    RasterWork& work) const {
    const TileRect tile = grid_.rect(tileX, tileY);
    ++work.tilesInBounds;
    if (targets.pixels) targets.pixels->countTileTest(tileX, tileY);
    const float farDepth =
        options_.zCulling ? targets.depthBounds->bound(tileX, tileY) : caster_.camera.farPlane();
    const TileTraversal traversal =
        traverseTile(group.hierarchy, group.nodes, {&caster_.camera, caster_.lens, tile, farDepth},
                     effects_.motion, options_.timeRefinement, work);
    if (!traversal.overlaps) return;
    ++work.tilesOverlapping;
    const int branch = branchNode(options_.branchMethod, traversal, group.hierarchy.depth());
    work.branchDepthSum += group.hierarchy.levelOf(branch);
    traceTileSamples(caster_, mesh, group.hierarchy, tileX, tileY, traversal, branch, targets,
                     work);
}

}  // namespace patchsim
