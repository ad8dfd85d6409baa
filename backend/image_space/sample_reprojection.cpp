#include "backend/image_space/sample_reprojection.h"

#include <algorithm>
#include <cmath>

#include "core/counters.h"
#include "core/ray.h"
#include "tessellator/front_end.h"

namespace patchsim {

namespace {

// A record's world position (w = 1) or, without a hit, the sample's world direction (w = 0).
Vec4 worldPoint(const ShadingContext& c, const SharpFrame& f, const Mat4& toWorld,
                const VisibilityRecord& r, int x, int y, int s) {
    if (!r.hit()) {
        const Sample smp = f.samples->sample(x, y, s);
        const Vec2 screen = rasterToScreen(*c.camera, Vec2(float(x), float(y)) + smp.pixelOffset);
        return toWorld * Vec4(screen, -1.0f, 0.0f);
    }
    const MovingMesh& mesh = (*c.meshes)[std::size_t(r.patch)];
    const std::uint32_t* v = &mesh.indices[3 * std::size_t(r.triangle)];
    const float w[3] = {1.0f - r.b1 - r.b2, r.b1, r.b2};
    Vec3 p(0);
    for (int k = 0; k < 3; ++k) p += w[k] * mesh.vertexAt(v[k], f.time);
    return toWorld * Vec4(p, 1.0f);
}

// Where the reprojection's passes are recorded (null: nowhere), and their planes.
struct ReprojectionPlanes {
    ImagePassTrace* trace = nullptr;
    std::uint16_t parts[2]{}, sum = 0, output = 0;
};

ReprojectionPlanes declarePlanes(ImagePassTrace* trace, const VisibilityBuffer& v) {
    if (!trace) return {};
    const auto pixels = std::uint64_t(v.width()) * std::uint64_t(v.height());
    const std::uint64_t samples = pixels * std::uint64_t(v.samplesPerPixel());
    ReprojectionPlanes p{trace,
                         {trace->addPlane("open sample parts", samples, kSamplePartBytes),
                          trace->addPlane("close sample parts", samples, kSamplePartBytes)},
                         trace->addPlane("accumulation", pixels, kReprojectionSumBytes),
                         trace->addPlane("output", pixels, kResolvedImagePixelBytes)};
    trace->beginPass("resolve sample parts");
    for (const std::uint16_t parts : p.parts)
        for (std::uint64_t i = 0; i < samples; ++i) trace->write(parts, i);
    trace->beginPass("reproject");
    return p;
}

// The accumulation buffer: per pixel, the weighted colours of the parts that landed there and
// their total weight (a whole number when every sample is one opaque part).
class Accumulation {
  public:
    Accumulation(const Camera& camera, int width, int height, int steps,
                 const ReprojectionPlanes& planes)
        : camera_(camera),
          planes_(planes),
          width_(width),
          height_(height),
          sum_(std::size_t(width) * std::size_t(height), Vec3(0)),
          weight_(sum_.size(), 0.0f) {
        for (int k = 0; k < steps; ++k)
            views_.push_back(camera.worldToCameraAt(float(k) / float(steps - 1)));
    }

    // Reprojects one part into every camera.
    void add(const Vec4& world, const Vec3& color, float weight, ReprojectionWork& work) {
        for (const Mat4& view : views_) {
            Vec3 p = Vec3(view * world);
            if (world.w == 0.0f) p *= 1e6f;  // a direction: far along it
            Vec2 raster;
            const bool front = camera_.cameraToRaster(p, raster);
            if (!front || !(raster.x >= 0.0f && raster.x < float(width_)) ||
                !(raster.y >= 0.0f && raster.y < float(height_))) {
                ++work.offScreen;
                continue;
            }
            ++work.reprojections;
            const std::size_t pixel =
                std::size_t(int(raster.y)) * std::size_t(width_) + std::size_t(int(raster.x));
            sum_[pixel] += weight * color;
            weight_[pixel] += weight;
            if (planes_.trace) planes_.trace->update(planes_.sum, pixel);
        }
    }

    // Each pixel's weighted mean; holes (nothing of any weight landed) blend the two frames.
    Image resolve(const Image& openPixels, const Image& closePixels, ReprojectionWork& work) const {
        Image out(width_, height_);
        ImagePassTrace* trace = planes_.trace;
        if (trace) trace->beginPass("resolve accumulation");
        for (int y = 0; y < height_; ++y) {
            for (int x = 0; x < width_; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(width_) + std::size_t(x);
                if (trace) trace->read(planes_.sum, i);
                if (weight_[i] > 0.0f) {
                    out.set(x, y, sum_[i] / weight_[i]);
                } else {
                    ++work.holes;
                    out.set(x, y, 0.5f * (openPixels.get(x, y) + closePixels.get(x, y)));
                    if (trace)
                        trace->read(std::uint16_t(ImagePassTrace::resolvedImage(0) |
                                                  ImagePassTrace::resolvedImage(1)),
                                    i);
                }
                if (trace) trace->write(planes_.output, i);
            }
        }
        return out;
    }

  private:
    const Camera& camera_;
    ReprojectionPlanes planes_;
    int width_, height_;
    std::vector<Mat4> views_;
    std::vector<Vec3> sum_;
    std::vector<float> weight_;
};

// Reprojects the transparent layers of sample (x, y, s) in front of its opaque hit, nearest
// first, each weighted by its opacity times what the layers in front let through; returns what
// they all let through, the opaque part's weight. Out of line: its sort buffer is a 9 KiB stack
// frame, which the opaque path should not set up for every sample.
[[gnu::noinline]] float addLayers(const ShadingContext& c, const SharpFrame& f, const Mat4& toWorld,
                                  int x, int y, int s, Accumulation& into, ReprojectionWork& work) {
    const VisibilityRecord& front = f.visibility->at(x, y, s);
    const std::size_t index = f.visibility->index(x, y, s);
    LayerFragment sorted[256];
    int kept = 0;
    for (int k = 0; k < f.layers->count(index); ++k) {
        const LayerFragment& layer = f.layers->layers(index)[k];
        if (!front.hit() || layer.record.nearerThan(front)) sorted[kept++] = layer;
    }
    std::sort(sorted, sorted + kept, [](const LayerFragment& a, const LayerFragment& b) {
        return a.record.nearerThan(b.record);
    });
    float through = 1.0f;
    for (int k = 0; k < kept; ++k) {
        const VisibilityRecord& r = sorted[k].record;
        const SurfaceAttributes a = interpolateAttributes(c, r);
        into.add(worldPoint(c, f, toWorld, r, x, y, s), shadeFragment(c, a, r.time),
                 through * a.opacity, work);
        through *= 1.0f - a.opacity;
    }
    work.layers += kept;
    return through;
}

void addFrame(const ShadingContext& c, const SharpFrame& f, Accumulation& into,
              ReprojectionWork& work, ImagePassTrace* trace, std::uint16_t parts) {
    const VisibilityBuffer& v = *f.visibility;
    const Mat4 toWorld = glm::inverse(c.camera->worldToCameraAt(f.time));
    for (int y = 0; y < v.height(); ++y) {
        for (int x = 0; x < v.width(); ++x) {
            for (int s = 0; s < v.samplesPerPixel(); ++s) {
                ++work.samples;
                const std::size_t i = v.index(x, y, s);
                if (trace) trace->read(parts, i);
                const bool layered = f.layers && f.layers->count(i) > 0;
                const float through =
                    layered ? addLayers(c, f, toWorld, x, y, s, into, work) : 1.0f;
                const Vec3 color((*f.colors)[3 * i], (*f.colors)[3 * i + 1],
                                 (*f.colors)[3 * i + 2]);
                into.add(worldPoint(c, f, toWorld, v.at(x, y, s), x, y, s), color, through, work);
            }
        }
    }
}

}  // namespace

PATCHSIM_WORK_DEFINE(ReprojectionWork, ReprojectionCounters, reprojectionCounters,
                     PATCHSIM_REPROJECTION_WORK)

Image reprojectSamples(const ShadingContext& c, const SharpFrame& open, const SharpFrame& close,
                       const Image& openPixels, const Image& closePixels,
                       const ReprojectionOptions& o, ReprojectionWork& work,
                       ImagePassTrace* trace) {
    const ReprojectionPlanes planes = declarePlanes(trace, *open.visibility);
    Accumulation sum(*c.camera, open.visibility->width(), open.visibility->height(),
                     std::max(2, o.cameraSteps), planes);
    addFrame(c, open, sum, work, trace, planes.parts[0]);
    addFrame(c, close, sum, work, trace, planes.parts[1]);
    return sum.resolve(openPixels, closePixels, work);
}

}  // namespace patchsim
