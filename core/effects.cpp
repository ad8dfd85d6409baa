#include "core/effects.h"

namespace patchsim {

Effects detectEffects(const SceneDesc& scene, bool geometryMoves, bool cameraMoves) {
    Effects e;
    const bool shutterOpens = scene.shutter.close > scene.shutter.open;
    e.motion = (geometryMoves || cameraMoves) && shutterOpens;
    e.defocus = scene.lens.apertureRadius > 0.0f;
    for (const ObjectDesc& o : scene.objects) {
        const MaterialDesc& m = o.material;
        e.transparency = e.transparency || m.opacity < 1.0f || m.closeOpacity < 1.0f;
        e.shadingVaries =
            e.shadingVaries ||
            (shutterOpens && (m.color != m.closeColor || m.opacity != m.closeOpacity));
    }
    return e;
}

Effects applyOverrides(Effects e, const EffectOverrides& o) {
    if (o.disableMotion) e.motion = e.shadingVaries = false;
    if (o.disableDefocus) e.defocus = false;
    if (o.disableTransparency) e.transparency = false;
    return e;
}

std::string describeMode(const Effects& e) {
    std::string mode = e.motion ? "motion (moving boxes, time intervals, t per sample)"
                       : e.shadingVaries
                           ? "static geometry (static boxes, no time intervals), "
                             "shading over time (t per sample)"
                           : "static (static boxes, no time intervals, no t in samples)";
    mode += e.lensPlaneSamples()
                ? "; defocus (lens u,v per sample, two planes per tile side, lens edge functions)"
            : e.defocus ? "; defocus (lens u,v per sample, two planes per tile side)"
            : e.motion  ? "; pinhole (no lens samples, four side planes)"
                        : "; pinhole (no lens samples, four side planes, edge functions)";
    mode += e.transparency ? "; transparency (every hit kept, sorted and blended)"
                           : "; opaque (nearest hit only, no sort)";
    return mode;
}

}  // namespace patchsim
