#include "backend/resolve.h"

#include <algorithm>
#include <cmath>

#include "pipeline/core/counters.h"
#include "pipeline/core/parallel.h"
#include "pipeline/core/progress.h"

namespace patchsim {

const Counter omLayersBlended{"OM/Layers blended", "fragments",
                              "Transparent t-fragments blended over the opaque one"};
const Counter omSamplesResolved{"OM/Samples resolved", "samples",
                                "Samples whose final colour was resolved"};

const char* resolveFilterName(ResolveFilter f) {
    return f == ResolveFilter::Box ? "box" : "gaussian";
}

namespace {

// Per-pixel shading cache for the per-pixel-primitive rate: one entry per (patch, triangle).
struct PixelShadeCache {
    struct Entry {
        std::int32_t patch;
        std::uint32_t triangle;
        Vec3 color;
        float opacity;
    };
    std::vector<Entry> entries;  // reused for every pixel (cleared, capacity kept)
};

struct Shaded {
    Vec3 color;
    float opacity;
};

Shaded shadeRecord(const ShadingContext& c, const VisibilityRecord& r, ShadingRate rate,
                   PixelShadeCache& cache) {
    if (rate == ShadingRate::PerPixelPrimitive) {
        for (const auto& e : cache.entries) {
            if (e.patch == r.patch && e.triangle == r.triangle) {
                ++shadingCounters().reused;
                return {e.color, e.opacity};
            }
        }
    }
    const SurfaceAttributes a = interpolateAttributes(c, r);
    const Shaded s{shadeFragment(c, a, r.time), a.opacity};
    if (rate == ShadingRate::PerPixelPrimitive)
        cache.entries.push_back({r.patch, r.triangle, s.color, s.opacity});
    return s;
}

Vec3 shadeSample(const ShadingContext& c, const VisibilityBuffer& opaque,
                 const TransparentLayers* layers, int x, int y, int s, ShadingRate rate,
                 PixelShadeCache& cache) {
    const VisibilityRecord& front = opaque.at(x, y, s);
    Vec3 color = front.hit() ? shadeRecord(c, front, rate, cache).color : kBackground;
    if (!layers) return color;
    const std::size_t index = opaque.index(x, y, s);
    const int n = layers->count(index);
    if (n == 0) return color;
    // Back to front: the farthest first. Fragments behind the opaque surface are hidden.
    LayerFragment sorted[256];
    int kept = 0;
    for (int i = 0; i < n; ++i) {
        const LayerFragment& f = layers->layers(index)[i];
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

}  // namespace

std::vector<float> shadeSamples(const ShadingContext& c, const VisibilityBuffer& opaque,
                                const TransparentLayers* transparent, ShadingRate rate, int threads,
                                Progress* progress) {
    const int spp = opaque.samplesPerPixel();
    std::vector<float> colors(opaque.records().size() * 3);
    parallelFor(std::size_t(opaque.height()), threads, [&](int, std::size_t row) {
        PixelShadeCache cache;
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

Image filterSamples(const std::vector<float>& colors, const VisibilityBuffer& layout,
                    const SampleGenerator& samples, const ResolveOptions& options, int threads) {
    const int w = layout.width(), h = layout.height(), spp = layout.samplesPerPixel();
    Image image(w, h);
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

// The box filter fused with shading: each pixel's samples shaded and averaged in one pass, with
// filterSamples's arithmetic, and no per-sample colour buffer.
Image shadeAndAverage(const ShadingContext& c, const VisibilityBuffer& opaque,
                      const TransparentLayers* transparent, ShadingRate rate, int threads,
                      Progress* progress) {
    const int spp = opaque.samplesPerPixel();
    Image image(opaque.width(), opaque.height());
    parallelFor(std::size_t(opaque.height()), threads, [&](int, std::size_t row) {
        PixelShadeCache cache;
        const int y = int(row);
        for (int x = 0; x < opaque.width(); ++x) {
            cache.entries.clear();
            Vec3 sum(0);
            float weights = 0;
            for (int s = 0; s < spp; ++s) {
                const float weight = 1.0f;
                sum += weight * shadeSample(c, opaque, transparent, x, y, s, rate, cache);
                weights += weight;
            }
            image.set(x, y, weights > 0 ? sum / weights : Vec3(0));
        }
        omSamplesResolved += std::int64_t(opaque.width()) * spp;
        if (progress) progress->advance();
    });
    return image;
}

}  // namespace

ResolvedFrame resolveFrame(const ShadingContext& c, const VisibilityBuffer& opaque,
                           const TransparentLayers* transparent, const SampleGenerator& samples,
                           const ResolveOptions& options, int threads, Progress* progress) {
    ResolvedFrame frame;
    if (options.filter == ResolveFilter::Box)
        frame.color =
            shadeAndAverage(c, opaque, transparent, options.shadingRate, threads, progress);
    else
        frame.color = filterSamples(
            shadeSamples(c, opaque, transparent, options.shadingRate, threads, progress), opaque,
            samples, options, threads);
    const std::size_t pixels = std::size_t(opaque.width()) * std::size_t(opaque.height());
    frame.depth.assign(pixels, 0.0f);
    frame.coverage.assign(pixels, 0.0f);
    frame.motionX.assign(pixels, 0.0f);
    frame.motionY.assign(pixels, 0.0f);
    const int spp = opaque.samplesPerPixel();
    parallelFor(std::size_t(opaque.height()), threads, [&](int, std::size_t row) {
        const int y = int(row);
        for (int x = 0; x < opaque.width(); ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(opaque.width()) + std::size_t(x);
            int hits = 0, covered = 0;
            for (int s = 0; s < spp; ++s) {
                const VisibilityRecord& r = opaque.at(x, y, s);
                const bool layered = transparent && transparent->count(opaque.index(x, y, s)) > 0;
                covered += r.hit() || layered;
                if (!r.hit()) continue;
                ++hits;
                frame.depth[p] += r.depth;
                const SurfaceAttributes a = interpolateAttributes(c, r);
                Vec2 r0, r1;
                if (c.camera->cameraToRaster(a.cameraPosition0, r0) &&
                    c.camera->cameraToRaster(a.cameraPosition1, r1)) {
                    frame.motionX[p] += r1.x - r0.x;
                    frame.motionY[p] += r1.y - r0.y;
                }
            }
            frame.coverage[p] = float(covered) / float(spp);
            if (hits > 0) {
                frame.depth[p] /= float(hits);
                frame.motionX[p] /= float(hits);
                frame.motionY[p] /= float(hits);
            }
        }
    });
    return frame;
}

std::vector<double> shadingWorkPerPatch(const VisibilityBuffer& opaque,
                                        const TransparentLayers* transparent, ShadingRate rate,
                                        std::size_t patchCount, int threads) {
    // Counts per worker, summed after: whole numbers, so the sum is exact in any order.
    const int workers = std::max(1, std::min(resolveThreadCount(threads), opaque.height()));
    std::vector<std::vector<double>> counts(std::size_t(workers),
                                            std::vector<double>(patchCount, 0.0));
    parallelFor(std::size_t(opaque.height()), workers, [&](int w, std::size_t row) {
        std::vector<double>& work = counts[std::size_t(w)];
        std::vector<std::pair<std::int32_t, std::uint32_t>> seen;  // per pixel, for the reuse rate
        const int y = int(row);
        for (int x = 0; x < opaque.width(); ++x) {
            seen.clear();
            auto charge = [&](const VisibilityRecord& r) {
                if (rate == ShadingRate::PerPixelPrimitive) {
                    const std::pair<std::int32_t, std::uint32_t> key{r.patch, r.triangle};
                    if (std::find(seen.begin(), seen.end(), key) != seen.end()) return;
                    seen.push_back(key);
                }
                work[std::size_t(r.patch)] += 1;
            };
            for (int s = 0; s < opaque.samplesPerPixel(); ++s) {
                const VisibilityRecord& front = opaque.at(x, y, s);
                if (front.hit()) charge(front);
                if (!transparent) continue;
                const std::size_t i = opaque.index(x, y, s);
                for (int k = 0; k < transparent->count(i); ++k) {
                    const VisibilityRecord& r = transparent->layers(i)[k].record;
                    if (!front.hit() || r.nearerThan(front)) charge(r);
                }
            }
        }
    });
    std::vector<double> work(patchCount, 0.0);
    for (const std::vector<double>& c : counts)
        for (std::size_t i = 0; i < patchCount; ++i) work[i] += c[i];
    return work;
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
