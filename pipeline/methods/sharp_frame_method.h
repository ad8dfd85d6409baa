#pragma once
// The methods that blur sharp frames (backend/image_space): the patch rasterizer renders each
// frame with every sample at one time through a pinhole; the method's own step then blurs it.

#include "pipeline/methods/patch_method.h"

namespace patchsim {

class SharpFrameMethod : public VisibilityMethod {
  public:
    bool exact() const override { return false; }
    bool countsPerPixel() const override { return true; }
    bool rasterizesPatches() const override { return true; }
    // The patch rasterizer's ray tests (hybrid's reveal rays stay fp32).
    bool roundsTriangleTests() const override { return true; }
    // The sharp frame's tiles, as the patch method's; the method's image-space passes follow
    // the resolve (core/image_pass_trace.h).
    std::unique_ptr<MemoryTrace> makeMemoryTrace(const SceneDesc& scene) const override;
    // Every sample at `sharpTime()`, through a pinhole.
    SampleGenerator makeSamples(const FilmDesc& film, const Effects& effects) const override;
    void check(const SceneDesc& scene, const RenderOptions& options, int workers) const override;
    const RatioCounter& sampleTestEfficiency() const override;
    VisibilityTotals totals(const CounterValues& values) const override;

  protected:
    virtual float sharpTime() const { return 0.5f; }
};

// The samples of a sharp frame at `time` (no time, lens or shading-over-time dimension).
SampleGenerator sharpFrameSamples(const FilmDesc& film, const Effects& effects, float time);
// What the patch rasterizer simulates for a sharp frame: the scene's motion, no defocus.
Effects sharpFrameRasterized(const Effects& effects);

// The frame rasterized by the patch rasterizer, as the patch method does, but sharp.
class SharpMethodFrame : public TiledFrame {
  public:
    using TiledFrame::TiledFrame;
    void visibility() override;
};

}  // namespace patchsim
