#include "pipeline/core/effects.h"

namespace patchsim {

Effects detectEffects(const SceneDesc& scene, bool geometryMoves, bool cameraMoves) {
    Effects e;
    e.motion = (geometryMoves || cameraMoves) && scene.shutter.close > scene.shutter.open;
    e.defocus = scene.lens.apertureRadius > 0.0f;
    for (const ObjectDesc& o : scene.objects)
        e.transparency =
            e.transparency || o.material.opacity < 1.0f || o.material.closeOpacity < 1.0f;
    return e;
}

Effects applyOverrides(Effects e, const EffectOverrides& o) {
    if (o.disableMotion) e.motion = false;
    if (o.disableDefocus) e.defocus = false;
    if (o.disableTransparency) e.transparency = false;
    return e;
}

std::string describeMode(const Effects& e) {
    std::string mode = e.motion ? "motion (moving boxes, time intervals, t per sample)"
                                : "static (static boxes, no time intervals, no t in samples)";
    mode += e.defocus ? "; defocus (lens u,v per sample, two planes per tile side)"
                      : "; pinhole (no lens samples, four side planes)";
    mode += e.transparency ? "; transparency (every hit kept, sorted and blended)"
                           : "; opaque (nearest hit only, no sort)";
    return mode;
}

}  // namespace patchsim
