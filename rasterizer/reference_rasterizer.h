#pragma once
// The reference visibility method: every sample against every triangle of every patch, at the
// sample's time. It shares the sample set, the camera ray and the watertight triangle test with
// the patch rasterizer, and nothing else: no traversal, bounds, tile or hit-gathering code, so a
// bug there cannot hide in both. It is the oracle the patch rasterizer is checked against sample
// for sample. Cost is samples x triangles: for small frames and tests.

#include <vector>

#include "pipeline/core/camera.h"
#include "pipeline/core/counters.h"
#include "pipeline/core/ray.h"
#include "pipeline/core/samples.h"
#include "rasterizer/moving_mesh.h"
#include "rasterizer/sample_rays.h"
#include "rasterizer/visibility_targets.h"

namespace patchsim {

struct ReferenceWork {
    std::int64_t samples = 0, triangleTests = 0, hits = 0;
};

struct ReferenceCounters {
    const Counter& samples;
    const Counter& triangleTests;
    const Counter& hits;
};
const ReferenceCounters& referenceCounters();

// Reference visibility samples per ray-triangle test (every sample against every triangle).
const RatioCounter& referenceSampleTestEfficiency();

// Rows [y0, y1) of the frame; every sample's record becomes the nearest opaque hit over all
// meshes, and every transparent hit in front of it goes to the transparent layers.
void renderReferenceRows(const std::vector<MovingMesh>& meshes, const Camera& camera,
                         const LensModel& lens, const SampleGenerator& samples, int y0, int y1,
                         const VisibilityTargets& targets, ReferenceWork& work);

}  // namespace patchsim
