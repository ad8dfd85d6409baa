#pragma once
// The pixel shader and resolve of the minimal back end: a visibility record is shaded late, at the
// sample's own time, from the patch's domain-shader attributes (normal and surface u,v blended
// between shutter open and close, then interpolated with the hit's barycentrics): Lambert with an
// ambient term and a procedural checker on the surface (u,v). Samples are box-filtered per pixel.

#include <vector>

#include "backend/image.h"
#include "pipeline/core/camera.h"
#include "pipeline/core/samples.h"
#include "rasterizer/visibility_buffer.h"
#include "tessellator/front_end.h"

namespace patchsim {

struct ShadingContext {
    const FrontEnd* frontEnd = nullptr;
    const std::vector<TessellatedPatch>* patches = nullptr;  // by global patch index
    const Camera* camera = nullptr;
    const SampleGenerator* samples = nullptr;
};

Vec3 shadeRecord(const ShadingContext& context, const VisibilityRecord& record, float time);
inline const Vec3 kBackground{0.05f, 0.05f, 0.07f};

// Box filter: each pixel is the mean of its samples' shaded colours.
Image resolveBox(const ShadingContext& context, const VisibilityBuffer& buffer);

}  // namespace patchsim
