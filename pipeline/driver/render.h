#pragma once
// `patchsim render`: a whole frame through the pipeline. The front end runs over all patches in
// parallel; each patch is split into groups and its hierarchies built (counted once); then the
// screen's tile rows are dealt to workers round-robin and every worker walks all patches in order
// over its own rows. A tile's z-buffer is only touched by its own worker in patch order, so the
// image and every counter are the same for any thread count.

#include <memory>
#include <string>
#include <vector>

#include "backend/image.h"
#include "pipeline/core/effects.h"
#include "pipeline/core/rasterizer_options.h"
#include "pipeline/core/scene.h"
#include "rasterizer/moving_mesh.h"
#include "rasterizer/visibility_buffer.h"

namespace patchsim {

enum class VisibilityMethod : std::uint8_t { Patch, Reference };
const char* visibilityMethodName(VisibilityMethod m);

struct RenderOptions {
    VisibilityMethod method = VisibilityMethod::Patch;
    EffectOverrides overrides;
    int threads = 0;
};

struct RenderResult {
    Image image;
    Effects effects;
    std::size_t patches = 0;
    std::size_t triangles = 0;
    double frontEndSeconds = 0, visibilitySeconds = 0, shadingSeconds = 0;
    std::unique_ptr<VisibilityBuffer> visibility;
};

RenderResult renderScene(const SceneDesc& scene, const RenderOptions& options);

// The visibility step of the patch method on prepared meshes, for benchmarks: groups and
// hierarchies, then every tile of every group, tile rows dealt to `threads` workers.
class PatchRasterizer;
void runPatchVisibility(const std::vector<MovingMesh>& meshes, const PatchRasterizer& rasterizer,
                        int threads, VisibilityBuffer& buffer);

}  // namespace patchsim
