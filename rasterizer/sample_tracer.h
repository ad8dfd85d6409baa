#pragma once
// Per-sample rays (US 8,791,945, step 7): the samples of an overlapping tile become rays, traced
// from the branch node down the tile's hierarchy.
//
// The frame's samples are kept per tile in time order (tile_samples.h): the samples of the tile's
// time range are one span, and those outside it are never looked at. The others become rays from
// their lens point through their point on the plane in focus, ending at their own z-buffer depth (z
// culling). A ray is tested against each box at its time (the 12-MADD moving box test) and, at the
// leaves, watertight against the triangles blended to its time. An opaque surface keeps the nearest
// hit; a transparent one offers every hit to the sample's layers.

#include "pipeline/core/camera.h"
#include "pipeline/core/ray.h"
#include "pipeline/core/samples.h"
#include "rasterizer/moving_mesh.h"
#include "rasterizer/patch_hierarchy.h"
#include "rasterizer/pixel_counters.h"
#include "rasterizer/raster_work.h"
#include "rasterizer/tile_traversal.h"
#include "rasterizer/transparent_layers.h"
#include "rasterizer/visibility_buffer.h"

namespace patchsim {

class TileSamples;
class TileDepthBounds;

// Where visibility samples go: the nearest opaque hit per sample, every transparent hit (when the
// scene has transparency), and optionally per-pixel work for heat maps. `pool` names the
// transparent-layer pool the calling worker owns. The patch rasterizer also reads the frame's
// samples by tile and keeps the tiles' depth bounds (frame_rasterizer makes both).
struct VisibilityTargets {
    VisibilityBuffer* opaque = nullptr;
    TransparentLayers* transparent = nullptr;
    PixelCounters* pixels = nullptr;
    int pool = 0;
    const TileSamples* tileSamples = nullptr;
    TileDepthBounds* depthBounds = nullptr;
};

// What every tile's rays share.
struct RayCaster {
    const Camera& camera;
    LensModel lens;
    const SampleGenerator& samples;
    bool motion = false;   // samples outside a tile's time range are rejected
    bool zCulling = true;  // rays end at their sample's depth
};

// The ray of sample `s` of pixel (x, y), with the camera's near-to-far range.
Ray sampleRay(const RayCaster& caster, int x, int y, int s);

// The tile's samples (those of its time range, in time order) traced from the branch node.
void traceTileSamples(const RayCaster& caster, const MovingMesh& mesh,
                      const PatchHierarchy& hierarchy, int tileX, int tileY,
                      const TileTraversal& traversal, int branchNode,
                      const VisibilityTargets& targets, RasterWork& work);

}  // namespace patchsim
