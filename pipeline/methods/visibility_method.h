#pragma once
// Every way patchsim decides what each sample sees (DESIGN.md section 5), behind one interface.
//
// Representation
// --------------
// A VisibilityMethod is one stateless object per method, made once and listed in the registry
// (method_registry.cpp, one line per method) with its name, help and provenance. The render
// driver (pipeline/driver/render.h) runs the pipeline's order of events and asks a method only
// what is its own: the sample set it consumes (`makeSamples`), what it refuses or needs beyond
// the film (`check`), one frame's work (`start`, which makes a MethodFrame), and what its own
// counters say (`totals`, `sampleTestEfficiency`). Nothing in the driver names a method.
//
// A MethodFrame lives for one frame:
// - `visibility()` fills the frame's targets (the per-sample visibility buffer, the transparent
//   layers, the per-pixel counts) for the rows this process owns (FramePartition), flushes the
//   counts of the work it did, and adds that work to `ops()`: per patch, as the operations the
//   timing model charges. When a frame is split over MPI ranks, rank 0 adds the other ranks'
//   `ops()` to its own, and their counters to its counters.
// - `chargeFrontEnd` adds a patch's front-end work (IA to DS) to the patch's operations: as the
//   front end did it, or as many times as the method's passes run it.
// - `finish(frame)` runs on rank 0 after the back end has shaded and resolved the frame: the
//   method's own image step (a post-process, a reprojection, colours of its own), whose work it
//   flushes and adds to `ops()` too.

#include <memory>
#include <string>
#include <vector>

#include "backend/shading/resolve.h"
#include "backend/shading/t_fragment.h"
#include "core/counters.h"
#include "core/memory_trace.h"
#include "core/ray.h"
#include "core/samples.h"
#include "core/scene.h"
#include "core/stage_ops.h"
#include "pipeline/methods/render_options.h"
#include "rasterizer/common/frame_partition.h"
#include "rasterizer/common/moving_mesh.h"
#include "rasterizer/common/visibility_targets.h"
#include "tessellator/front_end.h"

namespace patchsim {

// What the pipeline gives a method for one frame.
struct FrameInputs {
    const SceneDesc* scene = nullptr;
    const RenderOptions* options = nullptr;
    const FrontEnd* frontEnd = nullptr;
    const std::vector<TessellatedPatch>* patches = nullptr;  // by global patch index
    const std::vector<MovingMesh>* meshes = nullptr;         // camera space, by patch index
    Effects effects;                                         // as simulated (overrides applied)
    const SampleGenerator* samples = nullptr;                // the set makeSamples made
    VisibilityTargets targets;
    FramePartition partition;
    int workers = 1;
    // Where the method records its surface traffic for the memory model, when the hardware
    // models memory and the method records it (VisibilityMethod::makeMemoryTrace); else null.
    MemoryTrace* memoryTrace = nullptr;

    const Camera& camera() const { return frontEnd->camera(); }
    ShadingContext shading() const { return {frontEnd, patches, meshes, &camera()}; }
    // The scene's thin lens, or a pinhole when defocus is not simulated.
    LensModel lens() const;
};

class MethodFrame {
  public:
    explicit MethodFrame(const FrameInputs& inputs) : in_(inputs), ops_(inputs.meshes->size()) {}
    virtual ~MethodFrame() = default;
    MethodFrame(const MethodFrame&) = delete;
    MethodFrame& operator=(const MethodFrame&) = delete;

    virtual void visibility() = 0;
    virtual void finish(ResolvedFrame& frame) { (void)frame; }
    // Charges one patch's front-end work: once, unless the method runs the front end once per
    // pass (an accumulation buffer).
    virtual void chargeFrontEnd(const FrontEndWork& work, PatchOps& ops) const { work.charge(ops); }
    std::vector<PatchOps>& ops() { return ops_; }

    // The rows of the frame this process filled, when it is split: bands of pixel rows, unless
    // the method works in tiles.
    virtual bool ownsPixelRow(int y) const {
        return in_.partition.ownsBandPixelRow(y, in_.scene->film.height);
    }
    // The tile rows whose per-tile counts this process made (methods that count per pixel).
    virtual bool ownsTileRow(int ty) const { return in_.partition.ownsTileRow(ty); }

  protected:
    const FrameInputs& in_;
    std::vector<PatchOps> ops_;
};

// A method's visibility work in a frame, from its own counters: samples tested (for the bounding
// methods, sample-triangle pairs), rays (or ray-triangle tests where every test is its own ray),
// visibility samples, and their ratio.
struct VisibilityTotals {
    std::int64_t samplesTested = 0, rays = 0, visibilitySamples = 0;
    double sampleTestEfficiency = 0;
};

class VisibilityMethod {
  public:
    virtual ~VisibilityMethod() = default;

    virtual const char* name() const = 0;   // as on the command line: "triangle-bbox"
    virtual const char* after() const = 0;  // where it comes from, one line
    virtual bool exact() const = 0;         // the reference's nearest hits for the same samples
    // Counts its work per pixel (heat maps).
    virtual bool countsPerPixel() const { return false; }
    // Renders through the patch rasterizer, so the scene's rasterizer options change its work.
    virtual bool rasterizesPatches() const { return false; }
    // Runs its ray-triangle tests in rasterizer.triangle_format: the methods that rasterize
    // through the patch rasterizer, whose culling grows by the test's reach, and the reference,
    // its oracle. The bounding baselines test in fp32: their culling is not grown, so a narrower
    // test there would lose samples.
    virtual bool roundsTriangleTests() const { return false; }
    // Can split a frame between processes (FramePartition).
    virtual bool splitsFrames() const { return true; }
    // The trace its per-sample surface traffic is recorded in for the memory model
    // (core/memory_trace.h), cut into the regions it works in; null if it records none.
    virtual std::unique_ptr<MemoryTrace> makeMemoryTrace(const SceneDesc& scene) const {
        (void)scene;
        return nullptr;
    }

    // The sample set the method consumes, given the effects the frame simulates.
    virtual SampleGenerator makeSamples(const FilmDesc& film, const Effects& effects) const;
    // Throws InputError for what the method refuses (options, a split frame) or cannot fit in
    // the memory budget beside the film; called before anything is allocated. `workers` is the
    // process's thread count.
    virtual void check(const SceneDesc& scene, const RenderOptions& options, int workers) const;
    virtual std::unique_ptr<MethodFrame> start(const FrameInputs& inputs) const = 0;

    virtual const RatioCounter& sampleTestEfficiency() const = 0;
    virtual VisibilityTotals totals(const CounterValues& values) const = 0;
};

// Every method, in the order the help and the docs list them.
const std::vector<const VisibilityMethod*>& visibilityMethods();
// The method of that name, or null.
const VisibilityMethod* findVisibilityMethod(const std::string& name);
// The method of that name; throws std::invalid_argument when there is none (names from tests and
// tables that must exist).
const VisibilityMethod& methodNamed(const std::string& name);
std::string visibilityMethodNames();  // "patch, reference, ..." for messages

}  // namespace patchsim
