#pragma once
// A whole frame through the patch rasterizer: every patch's groups and hierarchies, then every
// tile those groups cover, on a fixed number of threads.
//
// Threads and determinism: the screen's tile rows are dealt to `kRowClasses` classes (tile row ty
// is class ty % kRowClasses), a number that does not depend on the thread count. One worker runs
// a class at a time and walks every patch in order over the class's tiles, so a tile's z-buffer,
// transparent layers and heat-map cells are touched by one worker only, in patch order: the image
// and every count are the same on any number of threads. Each class owns one pool of transparent
// layers. A frame can be split between processes (MPI ranks) by class: each rasterizes the classes
// it owns, and the owners' rows and work are put together afterwards.

#include <cstddef>
#include <functional>
#include <vector>

#include "rasterizer/moving_mesh.h"
#include "rasterizer/patch_rasterizer.h"
#include "rasterizer/transparent_layers.h"

namespace patchsim {

class Progress;

inline constexpr int kRowClasses = TransparentLayers::kPools;

struct FrameRasterOptions {
    int threads = 0;
    std::vector<std::size_t> order;  // patch order (index order when empty)
    Progress* progress = nullptr;    // advanced once per patch and owned row class
    // The row classes this process rasterizes; all when empty.
    std::function<bool(int rowClass)> ownsRowClass;
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

// Does tile row `ty` belong to row class `rowClass`?
inline bool inRowClass(int ty, int rowClass) {
    return ty % kRowClasses == rowClass;
}

}  // namespace patchsim
