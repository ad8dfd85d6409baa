#pragma once
// `patchsim render`: a whole frame through the pipeline. The front end runs over all patches in
// parallel; each patch is split into groups and its hierarchies built (counted once); then the
// screen's tile rows are dealt to a fixed number of row classes, each run by one worker that walks
// all patches in order over its own rows. A tile's z-buffer, transparent layers and heat-map
// cells are only touched by its own row class in patch order, so the image and every counter are
// the same for any thread count. The back end then shades every t-fragment at its time, blends
// transparent layers, resolves, and writes the AOVs.

#include <memory>
#include <string>
#include <vector>

#include "backend/resolve.h"
#include "pipeline/core/effects.h"
#include "pipeline/core/rasterizer_options.h"
#include "pipeline/core/scene.h"
#include "pipeline/driver/timing_model.h"
#include "rasterizer/patch_rasterizer.h"

namespace patchsim {

enum class VisibilityMethod : std::uint8_t { Patch, Reference };
const char* visibilityMethodName(VisibilityMethod m);

struct RenderOptions {
    VisibilityMethod method = VisibilityMethod::Patch;
    EffectOverrides overrides;
    int threads = 0;
    int maxLayers = 16;  // transparent t-fragments kept per sample
    ResolveOptions resolve;
    bool heatMaps = false;             // collect per-pixel work
    bool progress = false;             // progress bar (when standard error is a terminal)
    std::uint64_t patchOrderSeed = 0;  // > 0: rasterize patches in a shuffled order (tests)
};

struct RenderResult {
    ResolvedFrame frame;
    std::vector<std::string> notes;  // per object (scene_info.h objectNotes)
    Effects effects;
    std::size_t patches = 0;
    std::size_t triangles = 0;
    double frontEndSeconds = 0, visibilitySeconds = 0, shadingSeconds = 0;
    std::unique_ptr<VisibilityBuffer> visibility;
    std::unique_ptr<TransparentLayers> transparent;  // null without transparency
    std::unique_ptr<PixelWork> pixelWork;            // null without heat maps
    std::vector<PatchOps> patchOps;  // every stage's counted work per patch, for the timing model
};

// The rasterizer's work on one patch, summed over its groups and tiles.
struct PatchRasterWork {
    WorkCounts work;
    std::int64_t nodesBuilt = 0;
    std::uint64_t largestHierarchyBytes = 0;
};

RenderResult renderScene(const SceneDesc& scene, const RenderOptions& options);

// The visibility step of the patch method on prepared meshes (also used by benchmarks): groups
// and hierarchies, then every tile of every group in the order given (all patches when empty).
std::vector<PatchRasterWork> runPatchVisibility(const std::vector<MovingMesh>& meshes,
                                                const PatchRasterizer& rasterizer, int threads,
                                                const VisibilityTargets& targets,
                                                const std::vector<std::size_t>& order = {},
                                                class Progress* progress = nullptr);

}  // namespace patchsim
