#pragma once
// Which effects a scene calls for (DESIGN.md section 7), and the simulation mode chosen from them.
// Motion: any control point or the camera moves during the shutter. Shading over time: a
// material's colour or opacity changes during the shutter (samples then need a time even when
// nothing moves). Defocus: aperture > 0. Transparency: any opacity < 1. A study can switch an
// effect off; it is then not simulated even where the scene calls for it (`--no-motion` switches
// off everything that varies over the shutter).

#include <string>

#include "core/scene.h"

namespace patchsim {

struct Effects {
    bool motion = false;         // geometry or camera: moving boxes and time intervals
    bool shadingVaries = false;  // a material changes over the shutter
    bool defocus = false;
    bool transparency = false;

    // Samples carry a time when anything varies over the shutter.
    bool timeSamples() const { return motion || shadingVaries; }
    // Nothing moves and there is no lens: a sample is a point in the screen plane, tested with
    // edge functions instead of a ray (rasterizer/common/screen_triangle.h).
    bool screenPlaneSamples() const { return !motion && !defocus; }
    // A lens and nothing moving: a sample is a point (x, y, u, v), tested with edge functions of
    // the triangle seen from its lens point (rasterizer/common/lens_triangle.h).
    bool lensPlaneSamples() const { return !motion && defocus; }
};

struct EffectOverrides {
    bool disableMotion = false;
    bool disableDefocus = false;
    bool disableTransparency = false;
};

// `geometryMoves` comes from the vertex stage: true when any control point differs between t=0
// and t=1 (transform keyframes or per-vertex close positions).
Effects detectEffects(const SceneDesc& scene, bool geometryMoves, bool cameraMoves);
Effects applyOverrides(Effects called, const EffectOverrides& overrides);

// e.g. "motion (moving boxes, time intervals, t per sample); pinhole (4 side planes); opaque
// (nearest hit, no sort)".
std::string describeMode(const Effects& effects);

}  // namespace patchsim
