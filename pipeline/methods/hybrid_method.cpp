// Hybrid motion blur (Tan, Cui, Bhojan 2022): the post-process plus rays that reveal the
// background behind moving edges.

#include "backend/image_space/hybrid_motion_blur.h"
#include "pipeline/methods/sharp_frame_method.h"

namespace patchsim {

namespace {

class HybridFrame : public SharpMethodFrame {
  public:
    using SharpMethodFrame::SharpMethodFrame;
    void finish(ResolvedFrame& frame) override {
        PostprocessWork post;
        HybridWork hybrid;
        if (in_.effects.motion) {
            PostprocessOptions o = in_.options->postprocess;
            o.seed = in_.scene->film.seed;
            frame.color = hybridMotionBlur(
                in_.shading(), frame, *in_.targets.opaque, {o, in_.options->edgeThreshold}, post,
                hybrid, in_.memoryTrace ? &in_.memoryTrace->startImagePasses() : nullptr);
        }
        post.flush();
        hybrid.flush();
        // The mask passes and the rays run once the frame is shaded: charged with its last patch.
        if (ops_.empty()) return;
        post.charge(ops_.back());
        hybrid.charge(ops_.back());
    }
};

class HybridMethod : public SharpFrameMethod {
  public:
    const char* name() const override { return "hybrid"; }
    const char* after() const override {
        return "Tan et al. 2022: the post-process plus a ray mask and rays that reveal the "
               "background behind moving edges";
    }
    std::unique_ptr<MethodFrame> start(const FrameInputs& in) const override {
        return std::make_unique<HybridFrame>(in);
    }
};

}  // namespace

const VisibilityMethod& hybridMethod() {
    static const HybridMethod method;
    return method;
}

}  // namespace patchsim
