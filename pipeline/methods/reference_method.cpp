// The reference method (rasterizer/baselines/reference_rasterizer.h): every sample against every
// triangle, in bands of rows.

#include "core/parallel.h"
#include "core/progress.h"
#include "pipeline/methods/visibility_method.h"
#include "rasterizer/baselines/reference_rasterizer.h"
#include "rasterizer/patent/raster_work.h"

namespace patchsim {

namespace {

class ReferenceFrame : public MethodFrame {
  public:
    using MethodFrame::MethodFrame;
    void visibility() override;
    void finish(ResolvedFrame& frame) override;
};

void ReferenceFrame::visibility() {
    const FramePartition& partition = in_.partition;
    const RenderOptions& options = *in_.options;
    const std::unique_ptr<ProgressShare> progressShare =
        partition.split() && options.share.progressShare ? options.share.progressShare() : nullptr;
    constexpr int kBands = FramePartition::kClasses;
    Progress progress("reference ", kBands, 1, options.progress, "bands", progressShare.get());
    const int height = in_.scene->film.height;
    parallelFor(kBands, in_.workers, [&](int, std::size_t band) {
        if (!partition.ownsClass(int(band))) return;
        ReferenceWork work;
        VisibilityTargets mine = in_.targets;
        mine.pool = int(band);
        renderReferenceRows(*in_.meshes, in_.camera(), in_.lens(), *in_.samples, in_.effects.motion,
                            FramePartition::bandBegin(int(band), height),
                            FramePartition::bandBegin(int(band) + 1, height), mine, work,
                            in_.scene->rasterizer.triangleFormat);
        progress.advance();
    });
    progress.finish();
}

// Charged per patch once the whole frame is in: every sample is tested against every patch,
// once per triangle; a patch's hits are its visibility samples; the layers hold its transparent
// fragments.
void ReferenceFrame::finish(ResolvedFrame& frame) {
    (void)frame;
    const VisibilityBuffer& buffer = *in_.targets.opaque;
    const TransparentLayers* layers = in_.targets.transparent;
    const auto samples = std::int64_t(buffer.records().size());
    std::vector<ReferenceWork> work(in_.meshes->size());
    std::vector<RasterWork> layerWork(in_.meshes->size());
    for (std::size_t i = 0; i < work.size(); ++i) {
        work[i].samples = samples;
        work[i].triangleTests = samples * std::int64_t((*in_.meshes)[i].triangleCount());
    }
    for (std::size_t r = 0; r < buffer.records().size(); ++r) {
        const VisibilityRecord& record = buffer.records()[r];
        if (record.hit()) ++work[std::size_t(record.patch)].hits;
        if (!layers) continue;
        for (int k = 0; k < layers->count(r); ++k)
            ++layerWork[std::size_t(layers->layers(r)[k].record.patch)].transparentFragments;
    }
    for (std::size_t i = 0; i < work.size(); ++i) {
        work[i].charge(ops_[i]);
        layerWork[i].charge(ops_[i]);
    }
}

class ReferenceMethod : public VisibilityMethod {
  public:
    const char* name() const override { return "reference"; }
    const char* after() const override { return "every sample against every triangle: the oracle"; }
    bool exact() const override { return true; }
    bool roundsTriangleTests() const override { return true; }
    std::unique_ptr<MethodFrame> start(const FrameInputs& in) const override {
        return std::make_unique<ReferenceFrame>(in);
    }
    const RatioCounter& sampleTestEfficiency() const override {
        return referenceSampleTestEfficiency();
    }
    VisibilityTotals totals(const CounterValues& v) const override {
        const ReferenceCounters& c = referenceCounters();
        return {v[c.samples], v[c.samples], v[c.hits], v.ratio(sampleTestEfficiency())};
    }
};

}  // namespace

const VisibilityMethod& referenceMethod() {
    static const ReferenceMethod method;
    return method;
}

}  // namespace patchsim
