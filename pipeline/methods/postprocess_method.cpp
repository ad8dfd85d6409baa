// The post-process reconstruction filter (McGuire et al. 2012) on the mid-shutter sharp frame.

#include "backend/image_space/motion_blur_postprocess.h"
#include "pipeline/methods/sharp_frame_method.h"

namespace patchsim {

namespace {

class PostprocessFrame : public SharpMethodFrame {
  public:
    using SharpMethodFrame::SharpMethodFrame;
    void finish(ResolvedFrame& frame) override {
        PostprocessWork work;
        if (in_.effects.motion) {
            PostprocessOptions o = in_.options->postprocess;
            o.seed = in_.scene->film.seed;
            const int w = frame.color.width, h = frame.color.height;
            const PostprocessPlanes planes =
                in_.memoryTrace ? recordResolveAovs(in_.memoryTrace->startImagePasses(), w, h)
                                : PostprocessPlanes{};
            frame.color =
                reconstructMotionBlur(frame, in_.camera().farPlane(), o, work, nullptr, planes);
        }
        work.flush();
        // The filter's passes run once the frame is shaded: charged with its last patch.
        if (!ops_.empty()) work.charge(ops_.back());
    }
};

class PostprocessMethod : public SharpFrameMethod {
  public:
    const char* name() const override { return "postprocess"; }
    const char* after() const override {
        return "McGuire et al. 2012 reconstruction filter on a mid-shutter pinhole frame "
               "(weights as in Tan et al. 2022)";
    }
    std::unique_ptr<MethodFrame> start(const FrameInputs& in) const override {
        return std::make_unique<PostprocessFrame>(in);
    }
};

}  // namespace

const VisibilityMethod& postprocessMethod() {
    static const PostprocessMethod method;
    return method;
}

}  // namespace patchsim
