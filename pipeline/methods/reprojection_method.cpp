// Sample reprojection (Taylor): sharp frames at shutter open and close, every sample reprojected
// into cameras across the shutter.

#include "backend/image_space/sample_reprojection.h"
#include "pipeline/methods/sharp_frame_method.h"

namespace patchsim {

namespace {

class ReprojectionFrame : public SharpMethodFrame {
  public:
    using SharpMethodFrame::SharpMethodFrame;
    void finish(ResolvedFrame& frame) override;

  private:
    // The second sharp frame, at shutter close, whole (rank 0 renders it after the split frame).
    void renderCloseFrame();

    std::unique_ptr<SampleGenerator> closeSamples_;
    MemoryTrace* closeTrace_ = nullptr;  // its surface traffic, when recorded
    std::unique_ptr<VisibilityBuffer> close_;
    std::unique_ptr<TransparentLayers> closeLayers_;
};

void ReprojectionFrame::renderCloseFrame() {
    const FilmDesc& film = in_.scene->film;
    closeSamples_ = std::make_unique<SampleGenerator>(sharpFrameSamples(film, in_.effects, 1.0f));
    if (in_.memoryTrace) closeTrace_ = &in_.memoryTrace->addLaterFrame();
    close_ = std::make_unique<VisibilityBuffer>(film.width, film.height, film.samplesPerPixel,
                                                in_.camera().farPlane(), in_.workers);
    if (in_.targets.transparent)
        closeLayers_ = std::make_unique<TransparentLayers>(
            close_->records().size(), in_.options->maxLayers, in_.targets.transparent->pools());
    rasterizePatches(in_,
                     {closeSamples_.get(),
                      sharpFrameRasterized(in_.effects),
                      {close_.get(), closeLayers_.get(), nullptr, 0},
                      FramePartition{},
                      in_.options->progress,
                      closeTrace_},
                     ops_);
}

void ReprojectionFrame::finish(ResolvedFrame& frame) {
    renderCloseFrame();
    // A still frame is the open frame itself: the close frame is rendered, not resolved.
    if (closeTrace_) closeTrace_->setResolved(in_.effects.motion);
    ReprojectionWork work;
    if (in_.effects.motion) {
        const ShadingContext context = in_.shading();
        const RenderOptions& o = *in_.options;
        // The opaque hits' colours: the transparent layers are reprojected as parts of their own.
        const std::vector<float> openColors =
            shadeSamples(context, *in_.targets.opaque, nullptr, o.resolve.shadingRate, in_.workers);
        const std::vector<float> closeColors =
            shadeSamples(context, *close_, nullptr, o.resolve.shadingRate, in_.workers);
        // Holes take the blend of the two frames as the resolve shows them, layers and all.
        const Image closePixels =
            filterSamples(closeLayers_ ? shadeSamples(context, *close_, closeLayers_.get(),
                                                      o.resolve.shadingRate, in_.workers)
                                       : closeColors,
                          *close_, *closeSamples_, o.resolve, in_.workers);
        frame.color = reprojectSamples(
            context, {in_.targets.opaque, in_.targets.transparent, &openColors, in_.samples, 0.0f},
            {close_.get(), closeLayers_.get(), &closeColors, closeSamples_.get(), 1.0f},
            frame.color, closePixels, o.reprojection, work,
            in_.memoryTrace ? &in_.memoryTrace->startImagePasses() : nullptr);
    }
    work.flush();
    // The reprojection passes run once the frames are shaded: charged with the last patch.
    if (!ops_.empty()) work.charge(ops_.back());
}

class ReprojectionMethod : public SharpFrameMethod {
  public:
    const char* name() const override { return "reprojection"; }
    const char* after() const override {
        return "Taylor: the samples of sharp frames at shutter open and close reprojected into "
               "cameras across the shutter (camera motion)";
    }
    std::unique_ptr<MethodFrame> start(const FrameInputs& in) const override {
        return std::make_unique<ReprojectionFrame>(in);
    }

    // Both sharp frames and the passes; a transparent frame's layers, reprojected as parts of
    // their samples, are not recorded, so such a frame records nothing.
    std::unique_ptr<MemoryTrace> makeMemoryTrace(const SceneDesc& scene) const override {
        std::unique_ptr<MemoryTrace> trace = SharpFrameMethod::makeMemoryTrace(scene);
        trace->setOpaqueOnly();
        return trace;
    }

  protected:
    float sharpTime() const override { return 0.0f; }
};

}  // namespace

const VisibilityMethod& reprojectionMethod() {
    static const ReprojectionMethod method;
    return method;
}

}  // namespace patchsim
