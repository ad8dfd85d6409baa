// The bounding baselines (rasterizer/baselines/bounding_rasterizer.h) as visibility methods:
// triangle-bbox, interval and interleaved, in bands of rows.

#include "core/error.h"
#include "core/scene_reader.h"
#include "pipeline/methods/visibility_method.h"
#include "rasterizer/baselines/bounding_rasterizer.h"

namespace patchsim {

namespace {

const Counter kInterleavedPasses{"IL/Passes", "passes",
                                 "Frames rendered and accumulated: one per sample index, each "
                                 "running the front end at its own time",
                                 CounterKind::Max};
const Counter kAccumulatedPixels{"IL/Accumulated pixels", "pixels",
                                 "Pixels added into the accumulation buffer (every pixel of every "
                                 "pass), charged as full-screen pass reads",
                                 CounterKind::Sum};

class BoundingFrame : public MethodFrame {
  public:
    BoundingFrame(const FrameInputs& in, Bounding bounding)
        : MethodFrame(in), bounding_(bounding) {}
    void visibility() override {
        const RayCaster caster{in_.camera(), in_.lens(), *in_.samples, in_.effects.motion, true};
        BoundingOptions options;
        options.method = bounding_;
        options.timeStrata = intervalTimeStrata(in_.options->timeStrata,
                                                in_.samples->samplesPerPixel(), in_.effects.motion);
        if (bounding_ == Bounding::Interval)
            intervalTimeStrataCounter().raiseTo(options.timeStrata);
        options.bound = in_.options->triangleBound;
        options.threads = in_.workers;
        options.partition = in_.partition;
        options.memoryTrace = in_.memoryTrace;
        const std::vector<BoundingWork> work =
            rasterizeByBounds(*in_.meshes, caster, in_.targets, options);
        for (std::size_t i = 0; i < work.size(); ++i) {
            work[i].flush(bounding_);
            work[i].charge(ops_[i]);
        }
    }

    // An accumulation buffer renders the frame once per sample index, so every pass runs the
    // front end again, at the pass's one time: the kinds counted at both shutter ends (control
    // points transformed, stencils applied) cost half per pass, the rest in full.
    void chargeFrontEnd(const FrontEndWork& work, PatchOps& ops) const override {
        if (bounding_ != Bounding::Interleaved) return work.charge(ops);
        PatchOps pass;
        work.charge(pass);
        pass[Op::ControlPoints] *= 0.5;
        pass[Op::StencilApplications] *= 0.5;
        const double passes = double(in_.samples->samplesPerPixel());
        for (std::size_t k = 0; k < pass.ops.size(); ++k) ops.ops[k] += passes * pass.ops[k];
    }
    // Each pass's image is added into the accumulation buffer: a full-screen pass per sample
    // index, charged with the frame's last patch as the image-space methods' passes are.
    void finish(ResolvedFrame&) override {
        if (bounding_ != Bounding::Interleaved || ops_.empty()) return;
        const int passes = in_.samples->samplesPerPixel();
        const std::int64_t pixels =
            std::int64_t(passes) * in_.scene->film.width * in_.scene->film.height;
        kInterleavedPasses.raiseTo(passes);
        kAccumulatedPixels += pixels;
        ops_.back()[Op::PostSamples] += double(pixels);
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
    // Every bounding method rasterizes triangle by triangle, a band of rows at a time. The
    // accumulation buffer's hardware renders a frame per sample index instead: its trace is
    // replayed once per index (MemoryTrace::accumulation).
    std::unique_ptr<MemoryTrace> makeMemoryTrace(const SceneDesc& scene) const override {
        auto trace = std::make_unique<MemoryTrace>(
            MemoryTrace::bands(scene.film.width, scene.film.height, FramePartition::kClasses,
                               scene.film.samplesPerPixel));
        trace->setAccumulation(bounding_ == Bounding::Interleaved);
        return trace;
    }
    // The bands' prepared samples are held with the film to the memory budget.
    void check(const SceneDesc& scene, const RenderOptions& options, int workers) const override {
        VisibilityMethod::check(scene, options, workers);
        const FilmDesc& film = scene.film;
        const std::uint64_t scratch = boundingBandScratchBytes(
            film.width, film.height, film.samplesPerPixel, bounding_, workers);
        const std::uint64_t total = filmBytes(film) + scratch;
        if (total <= options.memoryBudgetBytes) return;
        const auto mib = [](std::uint64_t bytes) {
            return std::to_string((bytes + (1u << 20) - 1) >> 20);
        };
        throw InputError(scene.path, "film.spp",
                         std::string("the ") + name_ + " method prepares " + mib(scratch) +
                             " MiB of samples for the bands it rasterizes at once (--threads); "
                             "with the film's " +
                             mib(filmBytes(film)) + " MiB that is " + mib(total) +
                             " MiB, over the memory budget of " +
                             std::to_string(options.memoryBudgetBytes >> 20) +
                             " MiB (--memory-budget-mib): use fewer samples or threads");
    }
    const RatioCounter& sampleTestEfficiency() const override {
        return boundingSampleTestEfficiency(bounding_);
    }
    // Every test is a sample-triangle pair; outside static frames each with its own ray.
    VisibilityTotals totals(const CounterValues& v) const override {
        const BoundingCounters& c = boundingCounters(bounding_);
        return {v[c.samplesTested], v[c.rayTriangleTests], v[c.visibilitySamples],
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
