#pragma once
// t-fragments and the pixel shader (after Widmer et al. 2016).
//
// Representation
// --------------
// A t-fragment is a visibility sample (patch, triangle, barycentrics, depth, and the sample's
// time and lens position). Its
// surface identity is the patch and the domain (u,v) the barycentrics give on the triangle; from
// it every attribute is known at t=0 and t=1 (the domain shader's position and normal, the
// material's colour and opacity at shutter open and close) and blended to the fragment's time,
// so shading happens late, once per t-fragment, whatever visibility method produced it.

#include <vector>

#include "core/camera.h"
#include "core/counters.h"
#include "rasterizer/common/moving_mesh.h"
#include "rasterizer/common/visibility_buffer.h"
#include "tessellator/front_end.h"

namespace patchsim {

enum class ShadingRate : std::uint8_t {
    PerFragment,        // every t-fragment is shaded at its own time
    PerPixelPrimitive,  // once per pixel and triangle (MSAA style), at the first sample's time
};
const char* shadingRateName(ShadingRate r);

// What shading reads: the surfaces (tessellated patches with their materials), their
// camera-space positions (for motion vectors) and the camera.
struct ShadingContext {
    const FrontEnd* frontEnd = nullptr;
    const std::vector<TessellatedPatch>* patches = nullptr;  // by global patch index
    const std::vector<MovingMesh>* meshes = nullptr;         // camera space, by global patch index
    const Camera* camera = nullptr;
};

struct SurfaceAttributes {
    Vec3 normal;     // world space, blended to the fragment's time
    Vec2 surfaceUV;  // face-level (u,v) of the limit surface
    Vec2 domainUV;   // the tessellator's domain (u,v) on the patch
    Vec3 color;      // material colour at the fragment's time
    float opacity = 1;
    Vec3 cameraPosition0;  // the surface point in camera space at t=0 and t=1
    Vec3 cameraPosition1;
    bool unlit = false;
};

// At the record's own time.
SurfaceAttributes interpolateAttributes(const ShadingContext& context,
                                        const VisibilityRecord& record);
// The same, written into `attributes` (every field), for callers that keep them: no copy.
void interpolateAttributes(const ShadingContext& context, const VisibilityRecord& record,
                           SurfaceAttributes& attributes);

// The record's material opacity at its own time (what interpolateAttributes gives, without the
// geometry): the transparency blend's alpha.
float surfaceOpacity(const ShadingContext& context, const VisibilityRecord& record);

// Lambert with an ambient term and a checker on the surface (u,v); unlit materials give their
// colour. Counts one PS invocation.
Vec3 shadeFragment(const ShadingContext& context, const SurfaceAttributes& surface, float time);

inline const Vec3 kBackground{0.05f, 0.05f, 0.07f};

// The pixel shader's counters: invocations, and samples that reused a colour shaded for the same
// pixel and triangle (per-pixel-primitive rate).
struct ShadingCounters {
    const Counter& invocations;
    const Counter& reused;
};
const ShadingCounters& shadingCounters();
// Reused / (invoked + reused).
double shadingReuseRate(const CounterValues& values);

}  // namespace patchsim
