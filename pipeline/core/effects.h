#pragma once
// Which effects a scene calls for (SPEC section 7), and the simulation mode chosen from them.
// Motion: any control point or the camera moves during the shutter. Defocus: aperture > 0.
// Transparency: any opacity < 1. A study can switch an effect off; it is then not simulated even
// where the scene calls for it.

#include <string>

#include "pipeline/core/scene.h"

namespace patchsim {

struct Effects {
    bool motion = false;
    bool defocus = false;
    bool transparency = false;
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
