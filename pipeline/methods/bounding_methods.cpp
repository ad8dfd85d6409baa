// The bounding baselines (rasterizer/baselines/bounding_rasterizer.h) as visibility methods:
// triangle-bbox, interval and interleaved, in bands of rows.

#include "pipeline/methods/visibility_method.h"
#include "rasterizer/baselines/bounding_rasterizer.h"

namespace patchsim {

namespace {

class BoundingFrame : public MethodFrame {
  public:
    BoundingFrame(const FrameInputs& in, Bounding bounding)
        : MethodFrame(in), bounding_(bounding) {}
    void visibility() override {
        const RayCaster caster{in_.camera(), in_.lens(), *in_.samples, in_.effects.motion, true};
        BoundingOptions options;
        options.method = bounding_;
        options.timeStrata = in_.options->timeStrata;
        options.threads = in_.workers;
        options.partition = in_.partition;
        const std::vector<BoundingWork> work =
            rasterizeByBounds(*in_.meshes, caster, in_.targets, options);
        for (std::size_t i = 0; i < work.size(); ++i) {
            work[i].flush(bounding_);
            work[i].charge(ops_[i]);
        }
    }

  private:
    Bounding bounding_;
};

class BoundingMethod : public VisibilityMethod {
  public:
    BoundingMethod(Bounding bounding, const char* name, bool exact, const char* after)
        : bounding_(bounding), name_(name), exact_(exact), after_(after) {}
    const char* name() const override { return name_; }
    const char* after() const override { return after_; }
    bool exact() const override { return exact_; }
    // The interleaved method is an accumulation buffer: its samples repeat in every pixel.
    SampleGenerator makeSamples(const FilmDesc& film, const Effects& effects) const override {
        return SampleGenerator(
            film.seed, film.samplesPerPixel, effects,
            bounding_ == Bounding::Interleaved ? SamplePattern::Interleaved : film.sampler);
    }
    std::unique_ptr<MethodFrame> start(const FrameInputs& in) const override {
        return std::make_unique<BoundingFrame>(in, bounding_);
    }
    const RatioCounter& sampleTestEfficiency() const override {
        return boundingSampleTestEfficiency(bounding_);
    }
    // Every test is a sample-triangle pair with its own ray.
    VisibilityTotals totals(const CounterValues& v) const override {
        const BoundingCounters& c = boundingCounters(bounding_);
        return {v[c.samplesTested], v[c.samplesTested], v[c.visibilitySamples],
                v.ratio(sampleTestEfficiency())};
    }

  private:
    Bounding bounding_;
    const char* name_;
    bool exact_;
    const char* after_;
};

}  // namespace

const VisibilityMethod& triangleBBoxMethod() {
    static const BoundingMethod method(
        Bounding::TriangleBBox, "triangle-bbox", true,
        "Akenine-Moller et al. 2007, McGuire et al. 2010: each triangle's bounds over the shutter");
    return method;
}

const VisibilityMethod& intervalMethod() {
    static const BoundingMethod method(Bounding::Interval, "interval", true,
                                       "Fatahalian et al. 2009: time strata, per-stratum bounds");
    return method;
}

const VisibilityMethod& interleavedMethod() {
    static const BoundingMethod method(
        Bounding::Interleaved, "interleaved", false,
        "accumulation buffer: one time and lens point per sample index in every pixel");
    return method;
}

}  // namespace patchsim
