#include "backend/shading/resolve.h"

#include <algorithm>
#include <cmath>

#include "core/counters.h"
#include "core/parallel.h"
#include "core/progress.h"

namespace patchsim {

const Counter omLayersBlended{"OM/Layers blended", "fragments",
                              "Transparent t-fragments blended over the opaque one"};
const Counter omSamplesResolved{"OM/Samples resolved", "samples",
                                "Samples whose final colour was resolved"};

const char* resolveFilterName(ResolveFilter f) {
    return f == ResolveFilter::Box ? "box" : "gaussian";
}

namespace {

// Per-pixel shading state: the per-pixel-primitive rate's cache, one entry per (patch, triangle),
// and, when the frame's shading work is counted, where each fragment shaded is charged to its
// patch (the timing model's pixel-shader invocations).
struct PixelShading {
    struct Entry {
        std::int32_t patch;
        std::uint32_t triangle;
        Vec3 color;
        float opacity;
    };
    std::vector<Entry> entries;  // reused for every pixel (cleared, capacity kept)
    double* shadedPerPatch = nullptr;
};

// Fragments shaded per patch: an array per worker, summed after (whole numbers, so the sum is
// exact in any order and does not depend on the threads).
class ShadingWork {
  public:
    ShadingWork(std::size_t patches, int threads)
        : perWorker_(std::size_t(resolveThreadCount(threads)), std::vector<double>(patches, 0.0)) {}
    double* of(int worker) { return perWorker_[std::size_t(worker)].data(); }
    std::vector<double> total() const {
        std::vector<double> sum(perWorker_.front().size(), 0.0);
        for (const std::vector<double>& w : perWorker_)
            for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += w[i];
        return sum;
    }

  private:
    std::vector<std::vector<double>> perWorker_;
};

struct Shaded {
    Vec3 color;
    float opacity;
};

// A sample's opaque hit's attributes, when shading interpolated them (not when it reused a
// cached colour), for the AOVs. One per worker, reused sample after sample: shading interpolates
// into `value` in place, so the attributes are neither copied nor cleared per sample.
struct FrontAttributes {
    bool known = false;
    SurfaceAttributes value;
};

// `interpolated`, when given, gets the record's attributes if they were interpolated.
Shaded shadeRecord(const ShadingContext& c, const VisibilityRecord& r, ShadingRate rate,
                   PixelShading& cache, FrontAttributes* interpolated = nullptr) {
    if (rate == ShadingRate::PerPixelPrimitive) {
        for (const auto& e : cache.entries) {
            if (e.patch == r.patch && e.triangle == r.triangle) {
                ++shadingCounters().reused;
                return {e.color, e.opacity};
            }
        }
    }
    SurfaceAttributes local;
    SurfaceAttributes& a = interpolated ? interpolated->value : local;
    interpolateAttributes(c, r, a);
    if (interpolated) interpolated->known = true;
    if (cache.shadedPerPatch) cache.shadedPerPatch[r.patch] += 1;
    const Shaded s{shadeFragment(c, a, r.time), a.opacity};
    if (rate == ShadingRate::PerPixelPrimitive)
        cache.entries.push_back({r.patch, r.triangle, s.color, s.opacity});
    return s;
}

// The transparent layers of sample `index` blended over `color`, back to front; layers behind the
// opaque hit `front` are hidden. Kept out of line: its sort buffer is a 9 KiB stack frame, which
// the opaque path should not set up for every sample.
[[gnu::noinline]] Vec3 blendLayers(const ShadingContext& c, const VisibilityRecord& front,
                                   const TransparentLayers& layers, std::size_t index, int n,
                                   Vec3 color, ShadingRate rate, PixelShading& cache) {
    LayerFragment sorted[256];
    int kept = 0;
    for (int i = 0; i < n; ++i) {
        const LayerFragment& f = layers.layers(index)[i];
        if (front.hit() && !f.record.nearerThan(front)) continue;
        sorted[kept++] = f;
    }
    std::sort(sorted, sorted + kept, [](const LayerFragment& a, const LayerFragment& b) {
        return b.record.nearerThan(a.record);
    });
    for (int i = 0; i < kept; ++i) {
        const Shaded f = shadeRecord(c, sorted[i].record, rate, cache);
        color = f.opacity * f.color + (1.0f - f.opacity) * color;
    }
    omLayersBlended += kept;
    return color;
}

// `frontAttributes`, when given, gets the opaque hit's attributes if shading interpolated them.
Vec3 shadeSample(const ShadingContext& c, const VisibilityBuffer& opaque,
                 const TransparentLayers* layers, int x, int y, int s, ShadingRate rate,
                 PixelShading& cache, FrontAttributes* frontAttributes = nullptr) {
    const VisibilityRecord& front = opaque.at(x, y, s);
    const Vec3 color =
        front.hit() ? shadeRecord(c, front, rate, cache, frontAttributes).color : kBackground;
    if (!layers) return color;
    const std::size_t index = opaque.index(x, y, s);
    const int n = layers->count(index);
    if (n == 0) return color;
    return blendLayers(c, front, *layers, index, n, color, rate, cache);
}

// The surface whose colour weighs most in a sample with transparent layers: each layer in front
// of the opaque hit `front` weighs its opacity times what the layers in front of it let through,
// the opaque hit (or the background) what they all let through; ties go to the nearer. Null when
// the background weighs most. Out of line for its sort buffer, as blendLayers.
[[gnu::noinline]] const VisibilityRecord* dominantSurface(const ShadingContext& c,
                                                          const VisibilityRecord& front,
                                                          const TransparentLayers& layers,
                                                          std::size_t index, int n) {
    const VisibilityRecord* sorted[256];
    int kept = 0;
    for (int i = 0; i < n; ++i) {
        const VisibilityRecord& f = layers.layers(index)[i].record;
        if (front.hit() && !f.nearerThan(front)) continue;
        sorted[kept++] = &f;
    }
    std::sort(sorted, sorted + kept, [](const VisibilityRecord* a, const VisibilityRecord* b) {
        return a->nearerThan(*b);
    });
    const VisibilityRecord* best = nullptr;
    float bestWeight = 0, transmittance = 1;
    for (int i = 0; i < kept; ++i) {
        const float opacity = surfaceOpacity(c, *sorted[i]);
        if (transmittance * opacity > bestWeight) {
            best = sorted[i];
            bestWeight = transmittance * opacity;
        }
        transmittance *= 1.0f - opacity;
    }
    if (transmittance > bestWeight) return front.hit() ? &front : nullptr;
    return best;
}

// One pixel's AOVs, accumulated sample by sample in sample order. Depth is the opaque hits'; the
// motion is each sample's dominant surface's (dominantSurface: a transparent layer, when it
// weighs most, gives its motion, as a filter with one velocity per pixel needs to blur it).
struct PixelAovs {
    float depth = 0, motionX = 0, motionY = 0;
    int hits = 0, covered = 0, surfaces = 0;  // surfaces: samples a surface dominates

    // Sample s; `front` is its opaque hit's attributes when they are at hand, else null.
    void add(const ShadingContext& c, const VisibilityBuffer& opaque,
             const TransparentLayers* transparent, int x, int y, int s,
             const SurfaceAttributes* front) {
        const VisibilityRecord& r = opaque.at(x, y, s);
        const std::size_t index = opaque.index(x, y, s);
        const int layers = transparent ? transparent->count(index) : 0;
        covered += r.hit() || layers > 0;
        if (r.hit()) {
            ++hits;
            depth += r.depth;
        }
        const VisibilityRecord* dominant =
            layers > 0 ? dominantSurface(c, r, *transparent, index, layers) : &r;
        if (!dominant || !dominant->hit()) return;
        ++surfaces;
        const SurfaceAttributes a =
            front && dominant == &r ? *front : interpolateAttributes(c, *dominant);
        Vec2 r0, r1;
        if (c.camera->cameraToRaster(a.cameraPosition0, r0) &&
            c.camera->cameraToRaster(a.cameraPosition1, r1)) {
            motionX += r1.x - r0.x;
            motionY += r1.y - r0.y;
        }
    }

    // Writes all four planes: they start unwritten (allocateAovs).
    void store(ResolvedFrame& frame, std::size_t pixel, int spp) const {
        frame.coverage[pixel] = float(covered) / float(spp);
        frame.depth[pixel] = hits == 0 ? 0.0f : depth / float(hits);
        frame.motionX[pixel] = surfaces == 0 ? 0.0f : motionX / float(surfaces);
        frame.motionY[pixel] = surfaces == 0 ? 0.0f : motionY / float(surfaces);
    }
};

// The AOV planes, unwritten: each pixel's PixelAovs::store fills them on the worker that owns
// its row, so their pages are first touched there.
void allocateAovs(ResolvedFrame& frame, const VisibilityBuffer& opaque) {
    const std::size_t pixels = std::size_t(opaque.width()) * std::size_t(opaque.height());
    for (FloatPlane* plane : {&frame.depth, &frame.coverage, &frame.motionX, &frame.motionY})
        *plane = FloatPlane(pixels);
}

// Every sample's colour; `work`, when given, counts the fragments shaded.
std::vector<float> shadeEverySample(const ShadingContext& c, const VisibilityBuffer& opaque,
                                    const TransparentLayers* transparent, ShadingRate rate,
                                    int threads, Progress* progress, ShadingWork* work) {
    const int spp = opaque.samplesPerPixel();
    std::vector<float> colors(opaque.records().size() * 3);
    parallelFor(std::size_t(opaque.height()), threads, [&](int w, std::size_t row) {
        PixelShading cache;
        if (work) cache.shadedPerPatch = work->of(w);
        const int y = int(row);
        for (int x = 0; x < opaque.width(); ++x) {
            cache.entries.clear();
            for (int s = 0; s < spp; ++s) {
                const Vec3 col = shadeSample(c, opaque, transparent, x, y, s, rate, cache);
                const std::size_t i = opaque.index(x, y, s) * 3;
                colors[i] = col.x;
                colors[i + 1] = col.y;
                colors[i + 2] = col.z;
            }
        }
        omSamplesResolved += std::int64_t(opaque.width()) * spp;
        if (progress) progress->advance();
    });
    return colors;
}

}  // namespace

std::vector<float> shadeSamples(const ShadingContext& c, const VisibilityBuffer& opaque,
                                const TransparentLayers* transparent, ShadingRate rate, int threads,
                                Progress* progress) {
    return shadeEverySample(c, opaque, transparent, rate, threads, progress, nullptr);
}

Image filterSamples(const std::vector<float>& colors, const VisibilityBuffer& layout,
                    const SampleGenerator& samples, const ResolveOptions& options, int threads) {
    const int w = layout.width(), h = layout.height(), spp = layout.samplesPerPixel();
    Image image = Image::unfilled(w, h);  // every pixel set below
    const int reach =
        options.filter == ResolveFilter::Box ? 0 : int(std::ceil(options.gaussianRadius - 0.5f));
    parallelFor(std::size_t(h), threads, [&](int, std::size_t row) {
        const int y = int(row);
        for (int x = 0; x < w; ++x) {
            Vec3 sum(0);
            float weights = 0;
            for (int ny = std::max(0, y - reach); ny <= std::min(h - 1, y + reach); ++ny) {
                for (int nx = std::max(0, x - reach); nx <= std::min(w - 1, x + reach); ++nx) {
                    for (int s = 0; s < spp; ++s) {
                        float weight = 1.0f;
                        if (options.filter == ResolveFilter::Gaussian) {
                            const Vec2 p =
                                Vec2(float(nx), float(ny)) + samples.sample(nx, ny, s).pixelOffset;
                            const Vec2 d = p - Vec2(float(x) + 0.5f, float(y) + 0.5f);
                            const float r2 = glm::dot(d, d);
                            if (r2 > options.gaussianRadius * options.gaussianRadius) continue;
                            weight = std::exp(
                                -r2 / (2.0f * options.gaussianSigma * options.gaussianSigma));
                        }
                        const std::size_t i = layout.index(nx, ny, s) * 3;
                        sum += weight * Vec3(colors[i], colors[i + 1], colors[i + 2]);
                        weights += weight;
                    }
                }
            }
            image.set(x, y, weights > 0 ? sum / weights : Vec3(0));
        }
    });
    return image;
}

namespace {

// The box filter fused with shading and the AOVs: each pixel's samples shaded and averaged in
// one pass, with filterSamples's arithmetic and no per-sample colour buffer; the AOVs reuse the
// attributes shading interpolated for each opaque hit.
void shadeAverageAndAovs(const ShadingContext& c, const VisibilityBuffer& opaque,
                         const TransparentLayers* transparent, ShadingRate rate, int threads,
                         Progress* progress, ShadingWork& work, ResolvedFrame& frame) {
    const int spp = opaque.samplesPerPixel();
    frame.color = Image::unfilled(opaque.width(), opaque.height());
    allocateAovs(frame, opaque);
    parallelFor(std::size_t(opaque.height()), threads, [&](int w, std::size_t row) {
        PixelShading cache;
        cache.shadedPerPatch = work.of(w);
        FrontAttributes front;
        const int y = int(row);
        for (int x = 0; x < opaque.width(); ++x) {
            cache.entries.clear();
            Vec3 sum(0);
            float weights = 0;
            PixelAovs aovs;
            for (int s = 0; s < spp; ++s) {
                const float weight = 1.0f;
                front.known = false;
                sum += weight * shadeSample(c, opaque, transparent, x, y, s, rate, cache, &front);
                weights += weight;
                aovs.add(c, opaque, transparent, x, y, s, front.known ? &front.value : nullptr);
            }
            frame.color.set(x, y, weights > 0 ? sum / weights : Vec3(0));
            aovs.store(frame, std::size_t(y) * std::size_t(opaque.width()) + std::size_t(x), spp);
        }
        omSamplesResolved += std::int64_t(opaque.width()) * spp;
        if (progress) progress->advance();
    });
}

}  // namespace

ResolvedFrame resolveFrame(const ShadingContext& c, const VisibilityBuffer& opaque,
                           const TransparentLayers* transparent, const SampleGenerator& samples,
                           const ResolveOptions& options, int threads, Progress* progress) {
    ResolvedFrame frame;
    ShadingWork work(c.patches->size(), threads);
    if (options.filter == ResolveFilter::Box) {
        shadeAverageAndAovs(c, opaque, transparent, options.shadingRate, threads, progress, work,
                            frame);
    } else {
        frame.color = filterSamples(
            shadeEverySample(c, opaque, transparent, options.shadingRate, threads, progress, &work),
            opaque, samples, options, threads);
        allocateAovs(frame, opaque);
        parallelFor(std::size_t(opaque.height()), threads, [&](int, std::size_t row) {
            const int y = int(row);
            for (int x = 0; x < opaque.width(); ++x) {
                PixelAovs aovs;
                for (int s = 0; s < opaque.samplesPerPixel(); ++s)
                    aovs.add(c, opaque, transparent, x, y, s, nullptr);
                aovs.store(frame, std::size_t(y) * std::size_t(opaque.width()) + std::size_t(x),
                           opaque.samplesPerPixel());
            }
        });
    }
    frame.shadedPerPatch = work.total();
    return frame;
}

void writeExrWithAovs(const ResolvedFrame& frame, const std::string& path) {
    const std::size_t pixels = std::size_t(frame.color.width) * std::size_t(frame.color.height);
    std::vector<float> data(pixels * 7);
    for (std::size_t p = 0; p < pixels; ++p) {
        for (std::size_t k = 0; k < 3; ++k) data[p * 7 + k] = frame.color.rgb[p * 3 + k];
        data[p * 7 + 3] = frame.depth[p];
        data[p * 7 + 4] = frame.coverage[p];
        data[p * 7 + 5] = frame.motionX[p];
        data[p * 7 + 6] = frame.motionY[p];
    }
    writeFloatChannels(path, frame.color.width, frame.color.height,
                       {"R", "G", "B", "Z", "coverage", "motion.x", "motion.y"}, data);
}

}  // namespace patchsim
