#pragma once
// The reference visibility method: every sample against every triangle of every patch, at the
// sample's time. It shares the sample set, the camera ray and the watertight triangle test with
// the patch rasterizer, and nothing else: no traversal, bounds, tile or hit-gathering code, so a
// bug there cannot hide in both. It is the oracle the patch rasterizer is checked against sample
// for sample. Cost is samples x triangles: for small frames and tests.

#include <vector>

#include "core/camera.h"
#include "core/number_format.h"
#include "core/ray.h"
#include "core/samples.h"
#include "core/work_counts.h"
#include "rasterizer/common/moving_mesh.h"
#include "rasterizer/common/sample_rays.h"
#include "rasterizer/common/visibility_targets.h"

namespace patchsim {

// X(field, "Stage/Name", "unit", kind, "definition", charges...) (core/work_counts.h). Charged per
// patch: every sample is tested against the patch, once per triangle, and its hits are written.
#define PATCHSIM_REFERENCE_WORK(X)                                                                \
    X(samples, "REF/Samples", "samples", Sum, "Samples traced by the reference method",           \
      Op::SamplesTested)                                                                          \
    X(triangleTests, "REF/Ray-triangle tests", "tests", Sum,                                      \
      "Reference ray-triangle tests (every sample against every triangle)", Op::RayTriangleTests) \
    X(hits, "REF/Visibility samples", "samples", Sum, "Reference samples that hit a surface",     \
      Op::DepthTests)

struct ReferenceWork {
    PATCHSIM_REFERENCE_WORK(PATCHSIM_WORK_FIELD)
    PATCHSIM_WORK_METHODS(ReferenceWork)
};
struct ReferenceCounters {
    PATCHSIM_REFERENCE_WORK(PATCHSIM_WORK_HANDLE)
};
const ReferenceCounters& referenceCounters();

// Reference visibility samples per ray-triangle test (every sample against every triangle).
const RatioCounter& referenceSampleTestEfficiency();

// Rows [y0, y1) of the frame; every sample's record becomes the nearest opaque hit over all
// meshes, and every transparent hit in front of it goes to the transparent layers. `motion`: the
// geometry moves (without it and without a lens, samples are tested with edge functions).
// `triangleFormat`: the ray-triangle tests' arithmetic (rasterizer.triangle_format).
void renderReferenceRows(const std::vector<MovingMesh>& meshes, const Camera& camera,
                         const LensModel& lens, const SampleGenerator& samples, bool motion, int y0,
                         int y1, const VisibilityTargets& targets, ReferenceWork& work,
                         const NumberFormat& triangleFormat = NumberFormat::fp32());

}  // namespace patchsim
