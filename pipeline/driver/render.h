#pragma once
// `patchsim render`: a whole frame through the pipeline. The front end runs over all patches in
// parallel; the visibility method (the patch rasterizer's frame loop, rasterizer/frame_rasterizer,
// or the reference method) fills the per-sample visibility buffer; the back end then shades every
// t-fragment at its time, blends transparent layers, resolves, and writes the AOVs. Images and
// every counter are the same for any thread count.
//
// A frame can be split between processes (MPI ranks, DESIGN.md section 13) by screen tiles: each
// rank runs the front end, rasterizes the tile-row classes it owns, and sends their rows and work
// to rank 0, which puts the frame together, shades it and writes the one output. The result equals
// a local render byte for byte.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "backend/hybrid_motion_blur.h"
#include "backend/motion_blur_postprocess.h"
#include "backend/resolve.h"
#include "backend/sample_reprojection.h"
#include "backend/tfragment_method.h"
#include "pipeline/core/effects.h"
#include "pipeline/core/progress.h"
#include "pipeline/core/rasterizer_options.h"
#include "pipeline/core/scene.h"
#include "pipeline/core/scene_reader.h"
#include "pipeline/core/visibility_method.h"
#include "pipeline/driver/timing_model.h"
#include "rasterizer/pixel_counters.h"
#include "rasterizer/raster_work.h"
#include "rasterizer/transparent_layers.h"
#include "rasterizer/visibility_buffer.h"

namespace patchsim {

// One frame split between `ranks` processes; `gather` brings every rank's bytes to rank 0 (in
// rank order; empty on the others), as MPI_Gatherv does.
struct FrameShare {
    int rank = 0, ranks = 1;
    std::function<std::vector<std::string>(const std::string&)> gather;
    // Made by every rank at the same point (collective), so rank 0's progress shows all ranks'.
    std::function<std::unique_ptr<ProgressShare>()> progressShare;

    bool split() const { return ranks > 1; }
    bool root() const { return rank == 0; }
};

struct RenderOptions {
    VisibilityMethod method = VisibilityMethod::Patch;
    EffectOverrides overrides;
    int threads = 0;
    int maxLayers = 16;              // transparent t-fragments kept per sample
    int timeStrata = 4;              // the interval method's K
    PostprocessOptions postprocess;  // the postprocess and hybrid methods' filter
    float edgeThreshold = HybridOptions{}.edgeThreshold;  // the hybrid's ray mask: threshold e
    ReprojectionOptions reprojection;                     // the reprojection method's cameras
    TFragmentOptions tfragment;  // the tfragment method's guard band, thresholds, motion samples
    bool tfragmentTimeSampled = false;  // tfragment: one traversal per motion sample instead
    ResolveOptions resolve;
    bool heatMaps = false;             // collect per-pixel work
    bool progress = false;             // progress bar (when standard error is a terminal)
    std::uint64_t patchOrderSeed = 0;  // > 0: rasterize patches in a shuffled order (tests)
    // The film and the patch rasterizer's per-worker scratch must fit (--memory-budget-mib).
    std::uint64_t memoryBudgetBytes = SceneLimits{}.memoryBudgetBytes;
    FrameShare share;
};

struct RenderResult {
    bool complete = true;  // false on ranks other than 0 of a split frame: nothing to write
    ResolvedFrame frame;
    std::vector<std::string> notes;  // per object (scene_info.h objectNotes)
    Effects effects;
    std::size_t patches = 0;
    std::size_t triangles = 0;
    double frontEndSeconds = 0, visibilitySeconds = 0, shadingSeconds = 0;
    std::unique_ptr<VisibilityBuffer> visibility;
    std::unique_ptr<TransparentLayers> transparent;  // null without transparency
    std::unique_ptr<PixelCounters> pixels;           // null without heat maps
    std::vector<PatchOps> patchOps;  // every stage's counted work per patch, for the timing model
};

RenderResult renderScene(const SceneDesc& scene, const RenderOptions& options);

// Throws InputError(source, "rasterizer.tile_size") when the film and the patch rasterizer's tile
// scratch, one per worker (TileRays::bytesFor), exceed options.memoryBudgetBytes. renderScene
// checks before it allocates; the scene's reader checked the film alone.
void checkFrameMemory(const SceneDesc& scene, const RenderOptions& options,
                      const std::string& source);

// The sample test efficiency of a method's last frame, from its own counters.
const RatioCounter& sampleTestEfficiencyOf(VisibilityMethod method);

// A method's visibility work in a frame, from its own counters: samples tested (for the
// bounding methods, sample-triangle pairs), rays (or ray-triangle tests where every test is its
// own ray), visibility samples.
struct VisibilityTotals {
    std::int64_t samplesTested = 0, rays = 0, visibilitySamples = 0;
    double sampleTestEfficiency = 0;
};
VisibilityTotals visibilityTotals(const CounterValues& values, VisibilityMethod method);

}  // namespace patchsim
