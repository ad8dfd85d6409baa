// The t-fragment method (Widmer et al. 2016) as a visibility method: its own colours per sample,
// filtered by the back end's resolve filter.

#include "backend/tfragment/tfragment_trace.h"
#include "pipeline/methods/visibility_method.h"

namespace patchsim {

namespace {

class TFragmentFrame : public MethodFrame {
  public:
    using MethodFrame::MethodFrame;
    void visibility() override {
        const RenderOptions& o = *in_.options;
        colors_ = renderTFragments(in_.shading(), *in_.samples, in_.lens(), o.tfragment,
                                   o.tfragmentTimeSampled, in_.workers, *in_.targets.opaque, work_);
    }
    void finish(ResolvedFrame& frame) override {
        frame.color = filterSamples(colors_, *in_.targets.opaque, *in_.samples,
                                    in_.options->resolve, in_.workers);
        work_.flush();
        // Its passes and its shading are the frame's, charged with the last patch.
        if (!ops_.empty()) work_.charge(ops_.back());
    }

  private:
    std::vector<float> colors_;
    TFragmentWork work_;
};

class TFragmentMethod : public VisibilityMethod {
  public:
    const char* name() const override { return "tfragment"; }
    const char* after() const override {
        return "Widmer et al. 2016: t-fragments rasterized at t=1, an LBVH of their t-AABBs, lens "
               "rays, motion sampling";
    }
    bool exact() const override { return false; }
    // Its LBVH spans the frame.
    bool splitsFrames() const override { return false; }
    std::unique_ptr<MethodFrame> start(const FrameInputs& in) const override {
        return std::make_unique<TFragmentFrame>(in);
    }
    const RatioCounter& sampleTestEfficiency() const override {
        return tfragmentSampleTestEfficiency();
    }
    // Its samples tested are its motion samples' t-fragment tests, its rays the lens rays.
    VisibilityTotals totals(const CounterValues& v) const override {
        const TFragmentCounters& c = tfragmentCounters();
        return {v[c.sphereTests], v[c.lensRays], v[c.visibilitySamples],
                v.ratio(sampleTestEfficiency())};
    }
};

}  // namespace

const VisibilityMethod& tfragmentMethod() {
    static const TFragmentMethod method;
    return method;
}

}  // namespace patchsim
