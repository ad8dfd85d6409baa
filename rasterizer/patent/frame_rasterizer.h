#pragma once
// A whole frame through the patch rasterizer: every patch's groups and hierarchies, then every
// tile, each with every group that covers it, on a fixed number of threads.
//
// Threads and determinism: groups are binned to the tiles their screen bounds cover
// (tile_bins.h), and a worker takes the next unfinished tile (dynamic scheduling): it makes the
// tile's rays once (tile_rays.h), runs every group of the tile's bin in patch order, and writes
// the tile's samples back. A tile is touched by one worker only, in patch order, and each
// patch's work is a sum of integers, so the image and every count are the same on any number of
// threads and in any schedule. A worker owns one pool of transparent layers. A frame can be split
// between processes (MPI ranks) by the class of a tile's row (frame_partition.h): each rasterizes
// the tiles of the classes it owns, and the owners' rows and work are put together afterwards.

#include <cstddef>
#include <functional>
#include <vector>

#include "core/memory_trace.h"
#include "rasterizer/common/frame_partition.h"
#include "rasterizer/common/moving_mesh.h"
#include "rasterizer/common/transparent_layers.h"
#include "rasterizer/patent/patch_rasterizer.h"

namespace patchsim {

class Progress;

struct FrameRasterOptions {
    int threads = 0;
    std::vector<std::size_t> order;  // patch order (index order when empty)
    Progress* progress = nullptr;    // advanced once per owned tile
    // The tile rows this process rasterizes.
    FramePartition partition;
    // The frame's samples, made before (the rasterizer's generator makes them tile by tile when
    // there is no table).
    const SampleTable* sampleTable = nullptr;
    // targets.opaque holds no hits yet (as renderScene makes it), so it need not be read.
    bool opaqueStartsEmpty = false;
    // When the hardware models memory: each pass's z reads and visibility writes, per tile (a
    // trace of MemoryTrace::tiles with the grid's tile size).
    MemoryTrace* memoryTrace = nullptr;
};

// Each patch's work: building its hierarchies (every patch, whichever rows are owned) and its
// tiles (the owned row classes only).
struct FrameRasterWork {
    std::vector<RasterWork> hierarchies, tiles;
    RasterWork patch(std::size_t i) const {
        RasterWork w = hierarchies[i];
        w.add(tiles[i]);
        return w;
    }
};

// Visibility of every patch into `targets`. Counters are not flushed: the caller adds the work.
FrameRasterWork rasterizeFrame(const std::vector<MovingMesh>& meshes,
                               const PatchRasterizer& rasterizer, const VisibilityTargets& targets,
                               const FrameRasterOptions& options);

}  // namespace patchsim
