#include "backend/tfragment/tfragment_trace.h"

#include <algorithm>
#include <cmath>

#include "core/counters.h"
#include "core/parallel.h"

namespace patchsim {

namespace {

struct Hit {
    float lambda;
    std::uint32_t fragment;
};

Vec3 shade(const ShadingContext& c, const TFragment& f, float lambda, const Ray& ray, float t,
           Vec2 lens, float* opacity) {
    const VisibilityRecord r{lambda * ray.depthPerLambda, f.patch, f.triangle, f.b1, f.b2, t, lens};
    const SurfaceAttributes a = interpolateAttributes(c, r);
    if (opacity) *opacity = a.opacity;
    return shadeFragment(c, a, t);
}

}  // namespace

PATCHSIM_WORK_DEFINE(TFragmentWork, TFragmentCounters, tfragmentCounters, PATCHSIM_TFRAGMENT_WORK)

const RatioCounter& tfragmentSampleTestEfficiency() {
    // Tests are the sphere tests: one per motion sample and t-fragment it is tested against.
    static const RatioCounter ratio{"TF/Sample test efficiency",
                                    "Visibility samples per sample tested (sphere test)",
                                    visibilitySamplesCounter, sphereTestsCounter};
    return ratio;
}

std::vector<float> renderTFragments(const ShadingContext& c, const SampleGenerator& samples,
                                    const LensModel& lens, const TFragmentOptions& o,
                                    bool timeSampled, int threads, VisibilityBuffer& visibility,
                                    TFragmentWork& work) {
    const TFragmentSet set = generateTFragments(c, lens.radius > 0, o, work);
    const TFragmentBvh opaque(set.opaque, work), transparent(set.transparent, work);
    const int w = visibility.width(), h = visibility.height(), spp = visibility.samplesPerPixel();
    const int M = std::max(1, o.motionSamples);
    std::vector<float> colors(visibility.records().size() * 3, 0.0f);
    std::vector<TFragmentWork> rowWork(static_cast<std::size_t>(h));
    parallelFor(std::size_t(h), threads, [&](int, std::size_t row) {
        const int y = int(row);
        TFragmentWork& rw = rowWork[row];
        std::vector<std::uint32_t> opaqueHits, transparentHits;
        std::vector<Hit> layers;
        for (int x = 0; x < w; ++x) {
            for (int s = 0; s < spp; ++s) {
                const Sample smp = samples.sample(x, y, s);
                const Vec2 disk = concentricDisk(smp.lens);
                const Ray ray = makeCameraRay(
                    *c.camera,
                    rasterToScreen(*c.camera, Vec2(float(x), float(y)) + smp.pixelOffset), disk,
                    smp.time, lens);
                ++rw.lensRays;
                if (!timeSampled) {
                    opaque.collect(ray, o.maxCollected, opaqueHits, rw);
                    transparent.collect(ray, o.maxCollected, transparentHits, rw);
                }
                Vec3 sum(0);
                for (int j = 0; j < M; ++j) {
                    const float t = std::fmod(smp.time + float(j) / float(M), 1.0f);
                    ++rw.motionSamples;
                    float nearest = ray.lambdaMax;
                    std::int64_t front = -1;
                    if (timeSampled) {
                        front = opaque.nearestAt(ray, t, nearest, rw);
                    } else {
                        for (std::uint32_t k : opaqueHits) {
                            float lambda;
                            if (hitsTFragmentAt(ray, set.opaque[k], t, lambda, rw) &&
                                (lambda < nearest || (lambda == nearest && k < front))) {
                                ++rw.visibilitySamples;
                                nearest = lambda;
                                front = k;
                            }
                        }
                    }
                    Vec3 color = kBackground;
                    if (front >= 0) {
                        const TFragment& f = set.opaque[std::size_t(front)];
                        color = shade(c, f, nearest, ray, t, smp.lens, nullptr);
                        if (j == 0)
                            visibility.at(x, y, s) = {nearest * ray.depthPerLambda,
                                                      f.patch,
                                                      f.triangle,
                                                      f.b1,
                                                      f.b2,
                                                      t,
                                                      smp.lens};
                    }
                    layers.clear();
                    for (std::uint32_t k : transparentHits) {
                        float lambda;
                        if (hitsTFragmentAt(ray, set.transparent[k], t, lambda, rw) &&
                            lambda < nearest && layers.size() < 16)
                            layers.push_back({lambda, k});
                    }
                    std::sort(layers.begin(), layers.end(), [](const Hit& a, const Hit& b) {
                        return a.lambda > b.lambda ||
                               (a.lambda == b.lambda && a.fragment < b.fragment);
                    });
                    for (const Hit& l : layers) {
                        float alpha;
                        const Vec3 layer = shade(c, set.transparent[l.fragment], l.lambda, ray, t,
                                                 smp.lens, &alpha);
                        color = alpha * layer + (1.0f - alpha) * color;
                    }
                    sum += color;
                }
                const std::size_t i = visibility.index(x, y, s);
                const Vec3 mean = sum / float(M);
                colors[3 * i] = mean.x;
                colors[3 * i + 1] = mean.y;
                colors[3 * i + 2] = mean.z;
            }
        }
    });
    for (const TFragmentWork& rw : rowWork) work.add(rw);
    return colors;
}

}  // namespace patchsim
