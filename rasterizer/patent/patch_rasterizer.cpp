#include "rasterizer/patent/patch_rasterizer.h"

#include "rasterizer/common/lens_triangle.h"
#include "rasterizer/patent/branch_node.h"
#include "rasterizer/patent/ray_stream.h"
#include "rasterizer/patent/screen_bounds.h"
#include "rasterizer/patent/screen_pass.h"
#include "rasterizer/patent/tile_frustum.h"
#include "rasterizer/patent/tile_traversal.h"

namespace patchsim {

PatchRasterizer::PatchRasterizer(const Camera& camera, const LensModel& lens,
                                 const SampleGenerator& samples, const Effects& effects,
                                 const RasterizerOptions& options)
    : camera_(camera),
      lens_(lens),
      samples_(samples),
      effects_(effects),
      options_(options),
      grid_{camera.width(), camera.height(), options.tileSize},
      rayBoxArithmetic_(options.rayBoxFormat) {
    if (!effects_.defocus) lens_.radius = 0;
}

void PatchRasterizer::prepareGroup(const MovingMesh& mesh, const std::uint32_t* triangles,
                                   std::size_t count, Group& group, RasterWork& work,
                                   const LeafVertexTable* leafTable) const {
    group.hierarchy.buildOrdered(mesh, triangles, count, options_.leafSize, leafTable);
    if (options_.triangleFormat != NumberFormat::fp32())
        group.hierarchy.growForTriangleTest(options_.triangleFormat, lens_.radius,
                                            leavesTestedWithRays(mesh, group.hierarchy));
    group.hierarchy.storeNodesIn(options_.nodeFormat);
    ++work.groups;
    work.nodesBuilt += group.hierarchy.nodeCount();
    const auto bytes = std::int64_t(group.hierarchy.bytes());
    work.hierarchyBytes += bytes;
    work.peakHierarchyBytes = std::max(work.peakHierarchyBytes, bytes);
    group.nodes.build(group.hierarchy, options_.boundsSpace, camera_, lens_, work,
                      options_.screenBoundsFormat);
    // In 2D the nodes are already projected: the bounds are their rectangles' union.
    const ScreenBounds bounds =
        options_.boundsSpace == BoundsSpace::Screen2D
            ? screenBounds(group.hierarchy, options_.boundsLevel, camera_, group.nodes.screen)
            : screenBounds(group.hierarchy, options_.boundsLevel, camera_, lens_);
    work.fullScreenBounds += bounds.fullScreen;
    group.tiles = tilesCovering(bounds, grid_);
    if (effects_.screenPlaneSamples() || effects_.lensPlaneSamples())
        projectLeafVertices(mesh, group, work);
}

// The leaves whose triangles take the ray test (bit j: leaf j): every leaf, except in a static
// or defocus-only frame, where only a triangle with no fixed-point screen form
// (screen_triangle.h) or no lens form (lens_triangle.h) does.
std::uint64_t PatchRasterizer::leavesTestedWithRays(const MovingMesh& mesh,
                                                    const PatchHierarchy& h) const {
    const bool screen = effects_.screenPlaneSamples(), lens = effects_.lensPlaneSamples();
    if (!screen && !lens) return ~std::uint64_t(0);
    const auto needsRay = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        return screen ? setupScreenTriangle(camera_, a, b, c).kind == ScreenTriangle::Kind::NeedsRay
                      : setupLensTriangle(camera_, lens_, a, b, c).kind ==
                            LensTriangle::Kind::NeedsRay;
    };
    std::uint64_t leaves = 0;
    for (int leaf = 0; leaf < h.leafCount(); ++leaf) {
        std::size_t count = 0;
        const std::uint32_t* triangles = h.leafTriangles(leaf, count);
        for (std::size_t k = 0; k < count; ++k) {
            const std::uint32_t* v = &mesh.indices[3 * std::size_t(triangles[k])];
            if (needsRay(mesh.position0[v[0]], mesh.position0[v[1]], mesh.position0[v[2]])) {
                leaves |= std::uint64_t(1) << leaf;
                break;
            }
        }
    }
    return leaves;
}

// The viewport transform of a static or defocus-only frame, once per vertex of each leaf: every
// tile the leaf overlaps sets its triangles up from these (screen_pass.h, lens_pass.h).
void PatchRasterizer::projectLeafVertices(const MovingMesh& mesh, Group& group,
                                          RasterWork& work) const {
    const PatchHierarchy& h = group.hierarchy;
    const bool lens = effects_.lensPlaneSamples();
    if (lens) {
        group.screenVertices.clear();
        group.lensVertices.resize(h.leafVertexTotal());
    } else {
        group.lensVertices.clear();
        group.screenVertices.resize(h.leafVertexTotal());
    }
    for (int leaf = 0; leaf < h.leafCount(); ++leaf) {
        std::size_t count = 0;
        const std::uint32_t* vertices = h.leafVertices(leaf, count);
        const std::size_t first = h.leafVertexOffset(leaf);
        for (std::size_t k = 0; k < count; ++k) {
            const Vec3& p = mesh.position0[vertices[k]];
            if (lens)
                group.lensVertices[first + k] = projectThroughLens(lens_, p);
            else
                group.screenVertices[first + k] = projectToScreen(camera_, p);
        }
    }
    work.screenVertices += std::int64_t(h.leafVertexTotal());
}

void PatchRasterizer::rasterizeTile(const MovingMesh& mesh, const Group& group, int tileX,
                                    int tileY, TileRays& rays, const VisibilityTargets& targets,
                                    RasterWork& work) const {
    const TileRect tile = grid_.rect(tileX, tileY);
    ++work.tilesInBounds;
    if (targets.pixels) targets.pixels->countTileTest(tileX, tileY);
    const float farDepth = options_.zCulling ? rays.farthestDepthBound() : camera_.farPlane();
    const TileTraversal traversal = traverseTile(
        group.hierarchy, group.nodes, {&camera_, lens_, tile, farDepth, options_.planeFormat},
        effects_.motion, timeRefinementOf(options_), work);
    if (!traversal.overlaps) return;
    ++work.tilesOverlapping;
    const int branch = branchNode(options_.branchMethod, traversal, group.hierarchy.depth());
    StreamPass pass{&mesh, &group.hierarchy, &traversal, branch, options_.zCulling};
    pass.screenVertices = group.screenVertices.data();
    pass.lensVertices = group.lensVertices.data();
    if (options_.rayBoxFormat != NumberFormat::fp32()) pass.rayBoxArithmetic = &rayBoxArithmetic_;
    if (options_.triangleFormat != NumberFormat::fp32())
        pass.triangleFormat = &options_.triangleFormat;
    if (!mesh.opaque && targets.transparent) {
        pass.transparent = targets.transparent;
        pass.pool = targets.pool;
    }
    if (rays.subpixelX != nullptr)
        rasterizeScreenPass(rays, pass, camera_, work);
    else if (rays.screenX != nullptr)
        rasterizeLensPass(rays, pass, camera_, lens_, work);
    else
        traceRayStream(rays, pass, work);
}

}  // namespace patchsim
