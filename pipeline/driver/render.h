#pragma once
// `patchsim render`: a whole frame through the pipeline, in the pipeline's order of events. The
// front end runs over all patches in parallel; the visibility method (pipeline/methods, chosen by
// RenderOptions::method) fills the per-sample visibility buffer; the back end then shades every
// t-fragment at its time, blends transparent layers and resolves; the method's own image step
// follows (a post-process, a reprojection, its own colours); and every stage's counted work goes
// to the timing model per patch. Images and every counter are the same for any thread count.
//
// A frame can be split between processes (MPI ranks, DESIGN.md section 13) by screen tiles: each
// rank runs the front end, rasterizes the tile-row classes it owns, and sends their rows and work
// to rank 0, which puts the frame together, shades it and writes the one output. The result equals
// a local render byte for byte.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"
#include "core/scene_reader.h"
#include "core/stage_ops.h"
#include "pipeline/methods/render_options.h"
#include "pipeline/methods/visibility_method.h"
#include "pipeline/timing/timing_model.h"
#include "rasterizer/common/pixel_counters.h"
#include "rasterizer/common/transparent_layers.h"
#include "rasterizer/common/visibility_buffer.h"

namespace patchsim {

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
    // The frame's surface traffic (RenderOptions::memoryTrace, methods that record it).
    std::unique_ptr<MemoryTrace> memoryTrace;
    // The method records its traffic, but not on this frame (an accumulation buffer's
    // transparent layers).
    bool memoryTraceDropped = false;
    std::optional<SampleGenerator> sampleSet;  // the frame's samples, when the trace is kept
    ControlPointFetch controlPointFetch;       // what IA reads per patch, when the trace is kept
    SiteFormats formats;  // issue 35's sites: positions, and the patch method's boxes and tests
};

RenderResult renderScene(const SceneDesc& scene, const RenderOptions& options);

// A rendered frame's modelled time on `hardware`: its surface traffic through the memory system
// when the hardware models one, then the timing model.
struct FrameTiming {
    std::optional<MemoryReport> memory;
    TimingReport timing;
    EnergyReport energy;
    // The hardware models memory but the frame's method records no surface traffic: its timing
    // is the compute-only model's.
    bool memoryNotModelled = false;
};
FrameTiming timeFrame(const RenderResult& result, const HardwareConfig& hardware);

// Throws InputError for what the render refuses before it allocates anything: the rasterizer's
// options, the transparent layers, and what the method refuses or cannot fit in the memory
// budget beside the film (VisibilityMethod::check). renderScene calls it first.
void checkRender(const SceneDesc& scene, const RenderOptions& options);

}  // namespace patchsim
