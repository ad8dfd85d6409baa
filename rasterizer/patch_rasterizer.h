#pragma once
// The patch rasterizer of US 8,791,945: per patch (or group of a patch's triangles), a hierarchy of
// moving boxes; conservative screen bounds of the moving, defocused patch; a tiled walk of those
// bounds; per tile a frustum traversal that rejects, narrows the time interval at the leaves and
// finds the branch node; per sample in the tile's time interval a ray from the branch node,
// tested against boxes at the sample's time and then watertight against the triangles blended
// to that time.
//
// Everything the per-tile and per-sample loops need is set up before them: tile frusta are plain
// planes, rays carry their slab constants, and work is counted into a local WorkCounts that is
// flushed to the thread-local counters once per group. The loops allocate nothing.

#include <cstdint>
#include <vector>

#include "pipeline/core/camera.h"
#include "pipeline/core/effects.h"
#include "pipeline/core/rasterizer_options.h"
#include "pipeline/core/ray.h"
#include "pipeline/core/samples.h"
#include "rasterizer/patch_hierarchy.h"
#include "rasterizer/pixel_work.h"
#include "rasterizer/tile_frustum.h"
#include "rasterizer/transparent_layers.h"
#include "rasterizer/visibility_buffer.h"

namespace patchsim {

// The work of one group, counted locally and flushed once.
struct WorkCounts {
    std::int64_t tilesInBounds = 0, tilesRejectedSpace = 0, tilesRejectedTime = 0;
    std::int64_t tilesOverlapping = 0;
    std::int64_t planeTests = 0, timeIntervals = 0, frustumNodeVisits = 0;
    std::int64_t branchDepthSum = 0;
    std::int64_t samplesTested = 0, samplesRejectedTime = 0, raysCast = 0;
    std::int64_t rayBoxTests = 0, rayTriangleTests = 0, visibilitySamples = 0;
    std::int64_t fullScreenBounds = 0, patches = 0;
    std::int64_t transparentFragments = 0, transparentOverflow = 0;
    void add(const WorkCounts& o);
    void flush() const;  // into the RS/ thread-local counters
};

// Result of a tile's frustum traversal (exposed for tests and the branch-node comparison).
struct TileTraversal {
    bool overlaps = false;
    float tmin = 0, tmax = 1;
    std::uint64_t leafMask = 0;
    int firstSplitNode = -1;  // first node whose two children both overlap (or the single leaf)
    int bitmaskNode = -1;     // bottom-most node above exactly all overlapping leaves
};

// Where visibility samples go: the nearest opaque hit per sample, every transparent hit (when the
// scene has transparency), and optionally per-pixel work for heat maps. `pool` names the
// transparent-layer pool the calling worker owns.
struct VisibilityTargets {
    VisibilityBuffer* opaque = nullptr;
    TransparentLayers* transparent = nullptr;
    PixelWork* pixelWork = nullptr;
    int pool = 0;
};

class PatchRasterizer {
  public:
    PatchRasterizer(const Camera& camera, const LensModel& lens, const SampleGenerator& samples,
                    const Effects& effects, const RasterizerOptions& options);

    // Rasterizes every group of a mesh, single-threaded.
    void rasterize(const MovingMesh& mesh, const VisibilityTargets& targets, WorkCounts& work);

    // Steps, public so a driver can spread tiles over threads and tests can look inside.
    struct Group {
        PatchHierarchy hierarchy;
        int tileX0 = 0, tileY0 = 0, tileX1 = 0, tileY1 = 0;  // tile range [x0,x1) x [y0,y1)
    };
    void prepareGroup(const MovingMesh& mesh, const std::uint32_t* triangles, std::size_t count,
                      Group& group, WorkCounts& work) const;
    TileTraversal traverseTile(const Group& group, const TileFrustum& frustum,
                               WorkCounts& work) const;
    TileFrustum tileFrustum(const TileRect& tile, const VisibilityBuffer& buffer) const;
    void rasterizeTile(const MovingMesh& mesh, const Group& group, int tileX, int tileY,
                       const VisibilityTargets& targets, WorkCounts& work) const;

    const RasterizerOptions& options() const { return options_; }

  private:
    void screenBounds(const PatchHierarchy& h, float bounds[4], WorkCounts& work) const;
    void traceSamples(const MovingMesh& mesh, const Group& group, const TileRect& tile,
                      const TileTraversal& traversal, int branchNode,
                      const VisibilityTargets& targets, WorkCounts& work) const;

    const Camera& camera_;
    LensModel lens_;
    const SampleGenerator& samples_;
    Effects effects_;
    RasterizerOptions options_;
    std::vector<std::uint32_t> order_;  // reused between meshes
    std::vector<std::uint32_t> groupBegin_;
    Group group_;
};

// The ray of sample `s` of pixel (x, y).
Ray sampleRay(const Camera& camera, const LensModel& lens, const SampleGenerator& samples, int x,
              int y, int s);

// Nearest hit of a ray against the given triangles of a mesh at the ray's time; updates `best`
// (tie-break by depth, patch, triangle). Returns the number of triangle tests.
int intersectTriangles(const MovingMesh& mesh, const std::uint32_t* triangles, std::size_t count,
                       const Ray& ray, float lambdaMin, float lambdaMax, VisibilityRecord& best);

// The per-sample box test (12 multiply-adds): does the ray, at its time, meet the moving box
// within [lambdaMin, lambdaMax]? Conservative by a relative 1e-5.
bool rayMeetsMovingBox(const Ray& ray, const LBBox& box, float lambdaMin, float lambdaMax);

// Every hit of a ray against the given triangles, offered to a sample's transparent layers.
// Returns the number of triangle tests; counts fragments and overflow into `work`.
int offerAllHits(const MovingMesh& mesh, const std::uint32_t* triangles, std::size_t count,
                 const Ray& ray, float lambdaMin, float lambdaMax, TransparentLayers& layers,
                 std::size_t sample, int pool, WorkCounts& work);

}  // namespace patchsim
