#pragma once
// The patch rasterizer of US 8,791,945, for one group of a patch's triangles at a time. Each step
// of the patent is a file of its own:
//
//   1. hierarchy of moving boxes        patch_hierarchy
//   2. screen bounds                    screen_bounds
//   3. tiles                            tile_grid
//   4. tile frustum tests, time ranges  tile_frustum, tile_traversal
//   5. branch node                      branch_node
//   6. z culling                        z_culling
//   7. per-sample rays, moving boxes,   tile_rays, ray_stream, moving_box_ray,
//      watertight triangles             watertight_triangle
//   8. visibility samples               visibility_buffer, transparent_layers
//
// This class ties them together: `prepareGroup` builds a group's hierarchy and finds the tiles its
// screen bounds cover (steps 1-3); `rasterizeTile` runs steps 4-8 for one of those tiles, on the
// tile's rays. The frame loop over tiles and the groups covering each, and its threads, is
// frame_rasterizer's.

#include <vector>

#include "core/camera.h"
#include "core/effects.h"
#include "core/rasterizer_options.h"
#include "core/rounded_arithmetic.h"
#include "core/samples.h"
#include "rasterizer/common/lens_triangle.h"
#include "rasterizer/common/screen_triangle.h"
#include "rasterizer/common/tile_grid.h"
#include "rasterizer/common/visibility_targets.h"
#include "rasterizer/patent/patch_hierarchy.h"
#include "rasterizer/patent/raster_work.h"
#include "rasterizer/patent/tile_rays.h"
#include "rasterizer/patent/tile_traversal.h"

namespace patchsim {

class PatchRasterizer {
  public:
    PatchRasterizer(const Camera& camera, const LensModel& lens, const SampleGenerator& samples,
                    const Effects& effects, const RasterizerOptions& options);

    struct Group {
        PatchHierarchy hierarchy;
        SpaceNodes nodes;  // the hierarchy's boxes in the tile tests' bounds space
        TileRange tiles;   // the tiles its screen bounds cover
        // A static frame's (Effects::screenPlaneSamples): each leaf's distinct vertices
        // projected and snapped (screen_triangle.h), in the order of the leaf vertex table.
        std::vector<ScreenVertex> screenVertices;
        // A defocus-only frame's (Effects::lensPlaneSamples): the same vertices projected for
        // the lens edge test (lens_triangle.h).
        std::vector<LensVertex> lensVertices;
    };
    // `triangles`: one group of the mesh's hierarchyOrder, in that order; `leafTable`, the
    // group's leaf vertex table there, which the group shares and must not outlive (made for the
    // group alone when null).
    void prepareGroup(const MovingMesh& mesh, const std::uint32_t* triangles, std::size_t count,
                      Group& group, RasterWork& work,
                      const LeafVertexTable* leafTable = nullptr) const;
    void projectLeafVertices(const MovingMesh& mesh, Group& group, RasterWork& work) const;
    std::uint64_t leavesTestedWithRays(const MovingMesh& mesh, const PatchHierarchy& h) const;
    // `rays` holds the tile's rays and nearest hits (TileRays::load); transparent hits go to
    // `targets.transparent` from pool `targets.pool`.
    void rasterizeTile(const MovingMesh& mesh, const Group& group, int tileX, int tileY,
                       TileRays& rays, const VisibilityTargets& targets, RasterWork& work) const;

    const RasterizerOptions& options() const { return options_; }
    const TileGrid& tileGrid() const { return grid_; }
    const Camera& camera() const { return camera_; }
    const LensModel& lens() const { return lens_; }
    const SampleGenerator& samples() const { return samples_; }
    const Effects& effects() const { return effects_; }

  private:
    const Camera& camera_;
    LensModel lens_;
    const SampleGenerator& samples_;
    Effects effects_;
    RasterizerOptions options_;
    TileGrid grid_;
    RoundedArithmetic rayBoxArithmetic_;  // options_.rayBoxFormat's, when narrower than fp32
};

}  // namespace patchsim
