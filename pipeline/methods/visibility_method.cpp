#include "pipeline/methods/visibility_method.h"

#include <stdexcept>

#include "core/error.h"

namespace patchsim {

LensModel FrameInputs::lens() const {
    return {effects.defocus ? scene->lens.apertureRadius : 0.0f, scene->lens.focusDistance};
}

SampleGenerator VisibilityMethod::makeSamples(const FilmDesc& film, const Effects& effects) const {
    return SampleGenerator(film.seed, film.samplesPerPixel, effects, film.sampler);
}

void VisibilityMethod::check(const SceneDesc& scene, const RenderOptions& options,
                             int workers) const {
    (void)scene;
    (void)workers;
    if (options.heatMaps && !countsPerPixel())
        throw InputError("command line", "--heatmaps",
                         std::string("the ") + name() +
                             " method does not count its work per pixel; heat maps come from "
                             "the patch rasterizer (patch, postprocess, hybrid, reprojection)");
    if (options.share.split() && !splitsFrames())
        throw InputError("command line", "--method",
                         std::string(name()) + " does not split across MPI ranks");
}

const VisibilityMethod* findVisibilityMethod(const std::string& name) {
    for (const VisibilityMethod* m : visibilityMethods())
        if (name == m->name()) return m;
    return nullptr;
}

const VisibilityMethod& methodNamed(const std::string& name) {
    if (const VisibilityMethod* m = findVisibilityMethod(name)) return *m;
    throw std::invalid_argument("no visibility method named '" + name + "'");
}

std::string visibilityMethodNames() {
    std::string names;
    for (const VisibilityMethod* m : visibilityMethods())
        names += (names.empty() ? "" : ", ") + std::string(m->name());
    return names;
}

const VisibilityMethod& RenderOptions::visibilityMethod() const {
    return method ? *method : methodNamed("patch");
}

}  // namespace patchsim
