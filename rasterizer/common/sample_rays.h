#pragma once
// The camera ray of one sample, for the methods that trace samples one at a time (the reference,
// the bounding-box baselines, the Embree comparison). The patch rasterizer makes the same rays a
// tile at a time (tile_rays.h).

#include "core/camera.h"
#include "core/ray.h"
#include "core/samples.h"

namespace patchsim {

// What every sample's ray shares.
struct RayCaster {
    const Camera& camera;
    LensModel lens;
    const SampleGenerator& samples;
    bool motion = false;   // samples outside a tile's time range are rejected
    bool zCulling = true;  // rays end at their sample's depth
    // Nothing moves and there is no lens: samples are tested with edge functions
    // (screen_triangle.h), on the meshes' t=0 positions.
    bool screenPlane() const { return !motion && !(lens.radius > 0); }
    // A lens and nothing moving: samples are tested with lens edge functions (lens_triangle.h).
    bool lensPlane() const { return !motion && lens.radius > 0; }
};

// The ray of sample `s` of pixel (x, y), with the camera's near-to-far range.
Ray sampleRay(const RayCaster& caster, int x, int y, int s);

}  // namespace patchsim
