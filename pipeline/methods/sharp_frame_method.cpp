#include "pipeline/methods/sharp_frame_method.h"

#include "rasterizer/patent/raster_work.h"

namespace patchsim {

SampleGenerator sharpFrameSamples(const FilmDesc& film, const Effects& effects, float time) {
    Effects sampled = effects;
    sampled.motion = sampled.shadingVaries = sampled.defocus = false;
    return SampleGenerator(film.seed, film.samplesPerPixel, sampled, film.sampler, time);
}

Effects sharpFrameRasterized(const Effects& effects) {
    Effects rasterized = effects;
    rasterized.defocus = false;
    return rasterized;
}

SampleGenerator SharpFrameMethod::makeSamples(const FilmDesc& film, const Effects& effects) const {
    return sharpFrameSamples(film, effects, sharpTime());
}

void SharpFrameMethod::check(const SceneDesc& scene, const RenderOptions& options,
                             int workers) const {
    VisibilityMethod::check(scene, options, workers);
    checkTileScratch(scene, options, workers);
}

std::unique_ptr<MemoryTrace> SharpFrameMethod::makeMemoryTrace(const SceneDesc& scene) const {
    return std::make_unique<MemoryTrace>(MemoryTrace::tiles(scene.film.width, scene.film.height,
                                                            scene.rasterizer.tileSize,
                                                            scene.film.samplesPerPixel));
}

const RatioCounter& SharpFrameMethod::sampleTestEfficiency() const {
    return patchsim::sampleTestEfficiency();
}

VisibilityTotals SharpFrameMethod::totals(const CounterValues& v) const {
    const RasterCounters& c = rasterCounters();
    return {v[c.samplesTested], v[c.raysCast], v[c.visibilitySamples],
            v.ratio(sampleTestEfficiency())};
}

void SharpMethodFrame::visibility() {
    rasterizePatches(in_,
                     {in_.samples, sharpFrameRasterized(in_.effects), in_.targets, in_.partition,
                      in_.options->progress, in_.memoryTrace},
                     ops_);
}

}  // namespace patchsim
