#pragma once
// What a render is asked to do beyond the scene: the visibility method and its parameters, the
// back end's options, threads, the memory budget, and the share of a frame split between
// processes.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "backend/image_space/hybrid_motion_blur.h"
#include "backend/image_space/motion_blur_postprocess.h"
#include "backend/image_space/sample_reprojection.h"
#include "backend/shading/resolve.h"
#include "backend/tfragment/tfragment_generation.h"
#include "core/effects.h"
#include "core/progress.h"
#include "core/scene_reader.h"
#include "rasterizer/baselines/bounding_rasterizer.h"
#include "rasterizer/common/frame_partition.h"

namespace patchsim {

class VisibilityMethod;

// One frame split between `ranks` processes; `gather` brings every rank's bytes to rank 0 (in
// rank order; empty on the others), as MPI_Gatherv does.
struct FrameShare {
    int rank = 0, ranks = 1;
    std::function<std::vector<std::string>(const std::string&)> gather;
    // Made by every rank at the same point (collective), so rank 0's progress shows all ranks'.
    std::function<std::unique_ptr<ProgressShare>()> progressShare;

    bool split() const { return ranks > 1; }
    bool root() const { return rank == 0; }
    FramePartition partition() const { return {rank, ranks}; }
};

struct RenderOptions {
    const VisibilityMethod* method = nullptr;  // null: the patch method
    EffectOverrides overrides;
    int threads = 0;
    int maxLayers = 16;  // transparent t-fragments kept per sample
    int timeStrata = 0;  // the interval method's K; 0: the film's samples per pixel
    TriangleBound triangleBound = TriangleBound::Hull;  // triangle-bbox's bound
    PostprocessOptions postprocess;  // the postprocess and hybrid methods' filter
    float edgeThreshold = HybridOptions{}.edgeThreshold;  // the hybrid's ray mask: threshold e
    ReprojectionOptions reprojection;                     // the reprojection method's cameras
    TFragmentOptions tfragment;  // the tfragment method's guard band, thresholds, motion samples
    bool tfragmentTimeSampled = false;  // tfragment: one traversal per motion sample instead
    ResolveOptions resolve;
    bool heatMaps = false;             // collect per-pixel work
    bool progress = false;             // progress bar (when standard error is a terminal)
    std::uint64_t patchOrderSeed = 0;  // > 0: rasterize patches in a shuffled order (tests)
    // Record the frame's surface traffic for the memory model (the hardware models memory).
    bool memoryTrace = false;
    // The film and the patch rasterizer's per-worker scratch must fit (--memory-budget-mib).
    std::uint64_t memoryBudgetBytes = SceneLimits{}.memoryBudgetBytes;
    FrameShare share;

    const VisibilityMethod& visibilityMethod() const;
};

}  // namespace patchsim
