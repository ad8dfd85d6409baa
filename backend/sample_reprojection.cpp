#include "backend/sample_reprojection.h"

#include <cmath>

#include "pipeline/core/counters.h"
#include "pipeline/core/ray.h"
#include "tessellator/front_end.h"

namespace patchsim {

namespace {

const Counter rpSamples{"RP/Samples", "samples", "Samples of the two sharp frames reprojected"};
const Counter rpReprojections{"RP/Reprojections", "samples",
                              "Sample-camera reprojections written into the accumulation buffer"};
const Counter rpOffScreen{"RP/Off-screen reprojections", "samples",
                          "Reprojections that fell outside the image"};
const Counter rpHoles{"RP/Holes", "pixels",
                      "Pixels no sample was reprojected into (disocclusions), filled by blending"};

// A sample's world position (w = 1) or, without a hit, its world direction (w = 0).
Vec4 worldPoint(const ShadingContext& c, const SharpFrame& f, int x, int y, int s) {
    const VisibilityRecord& r = f.visibility->at(x, y, s);
    const Mat4 toWorld = glm::inverse(c.camera->worldToCameraAt(f.time));
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

}  // namespace

void ReprojectionWork::flush() const {
    rpSamples += samples;
    rpReprojections += reprojections;
    rpOffScreen += offScreen;
    rpHoles += holes;
}

Image reprojectSamples(const ShadingContext& c, const SharpFrame& open, const SharpFrame& close,
                       const Image& openPixels, const Image& closePixels,
                       const ReprojectionOptions& o, ReprojectionWork& work) {
    const int w = open.visibility->width(), h = open.visibility->height();
    const int spp = open.visibility->samplesPerPixel();
    const int steps = std::max(2, o.cameraSteps);
    std::vector<Mat4> views;
    for (int k = 0; k < steps; ++k)
        views.push_back(c.camera->worldToCameraAt(float(k) / float(steps - 1)));
    std::vector<Vec3> sum(std::size_t(w) * std::size_t(h), Vec3(0));
    std::vector<std::int32_t> count(sum.size(), 0);
    for (const SharpFrame* f : {&open, &close}) {
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                for (int s = 0; s < spp; ++s) {
                    ++work.samples;
                    const Vec4 world = worldPoint(c, *f, x, y, s);
                    const std::size_t i = f->visibility->index(x, y, s);
                    const Vec3 color((*f->colors)[3 * i], (*f->colors)[3 * i + 1],
                                     (*f->colors)[3 * i + 2]);
                    for (const Mat4& view : views) {
                        Vec3 p = Vec3(view * world);
                        if (world.w == 0.0f) p *= 1e6f;  // a direction: far along it
                        Vec2 raster;
                        const bool front = c.camera->cameraToRaster(p, raster);
                        if (!front || !(raster.x >= 0.0f && raster.x < float(w)) ||
                            !(raster.y >= 0.0f && raster.y < float(h))) {
                            ++work.offScreen;
                            continue;
                        }
                        const int px = int(raster.x), py = int(raster.y);
                        ++work.reprojections;
                        const std::size_t pixel =
                            std::size_t(py) * std::size_t(w) + std::size_t(px);
                        sum[pixel] += color;
                        ++count[pixel];
                    }
                }
            }
        }
    }
    Image out(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            if (count[i] > 0) {
                out.set(x, y, sum[i] / float(count[i]));
                continue;
            }
            ++work.holes;
            out.set(x, y, 0.5f * (openPixels.get(x, y) + closePixels.get(x, y)));
        }
    }
    return out;
}

}  // namespace patchsim
