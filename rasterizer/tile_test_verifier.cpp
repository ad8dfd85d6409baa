#include "rasterizer/tile_test_verifier.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "pipeline/core/samples.h"

namespace patchsim {

std::vector<std::unique_ptr<TileTestVariant>>& tileTestRegistry() {
    static std::vector<std::unique_ptr<TileTestVariant>> registry;
    return registry;
}

void registerTileTest(std::unique_ptr<TileTestVariant> variant) {
    tileTestRegistry().push_back(std::move(variant));
}

void unregisterTileTest(const std::string& name) {
    auto& registry = tileTestRegistry();
    std::erase_if(registry, [&](const auto& v) { return v->name() == name; });
}

const std::vector<std::unique_ptr<TileTestVariant>>& registeredTileTests() {
    return tileTestRegistry();
}

namespace {

// ---- Built-in variants: the tests the patch rasterizer uses. ----

TileFrustum frustumFor(const TileTestInput& in) {
    return makeTileFrustum(*in.camera, in.lens, in.tile, in.camera->farPlane());
}

class NVertexTest : public TileTestVariant {
  public:
    explicit NVertexTest(bool lens) : lens_(lens) {}
    std::string name() const override { return lens_ ? "lens-two-plane" : "pinhole-n-vertex"; }
    bool handlesDefocus() const override { return lens_; }
    TileTestOutput run(const TileTestInput& in) const override {
        RasterWork work;
        return {overlapsFrustum(frustumFor(in), in.box, true, work), TimeRange::shutter()};
    }

  private:
    bool lens_;
};

class TimeIntervalTest : public TileTestVariant {
  public:
    explicit TimeIntervalTest(bool lens) : lens_(lens) {}
    std::string name() const override {
        return lens_ ? "lens-two-plane-time-interval" : "pinhole-n-vertex-time-interval";
    }
    bool handlesDefocus() const override { return lens_; }
    TileTestOutput run(const TileTestInput& in) const override {
        RasterWork work;
        TileTestOutput out;
        out.accept = leafTimeInterval(frustumFor(in), in.box, out.times, work);
        return out;
    }

  private:
    bool lens_;
};

struct PinholeNVertex : NVertexTest {
    PinholeNVertex() : NVertexTest(false) {}
};
struct LensTwoPlane : NVertexTest {
    LensTwoPlane() : NVertexTest(true) {}
};
struct PinholeTime : TimeIntervalTest {
    PinholeTime() : TimeIntervalTest(false) {}
};
struct LensTime : TimeIntervalTest {
    LensTime() : TimeIntervalTest(true) {}
};
PATCHSIM_REGISTER_TILE_TEST(PinholeNVertex);
PATCHSIM_REGISTER_TILE_TEST(PinholeTime);
PATCHSIM_REGISTER_TILE_TEST(LensTwoPlane);
PATCHSIM_REGISTER_TILE_TEST(LensTime);

// ---- Ground truth ----

struct Truth {
    bool hit = false;
    std::vector<float> hitTimes;
};

bool rayHitsBox(const glm::dvec3& o, const glm::dvec3& d, const Box3& b, double lambdaMin,
                double lambdaMax) {
    double lo = lambdaMin, hi = lambdaMax;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (o[k] < b.lower[k] || o[k] > b.upper[k]) return false;
            continue;
        }
        double a = (double(b.lower[k]) - o[k]) / d[k], c = (double(b.upper[k]) - o[k]) / d[k];
        if (a > c) std::swap(a, c);
        lo = std::max(lo, a);
        hi = std::min(hi, c);
    }
    return lo <= hi;
}

Truth groundTruth(const TileTestInput& in) {
    constexpr int kTimes = 33, kScreen = 9, kLens = 5;
    Truth truth;
    const Camera& cam = *in.camera;
    for (int ti = 0; ti < kTimes; ++ti) {
        const float t = float(ti) / float(kTimes - 1);
        const Box3 box = in.box.at(t);
        bool hitAtT = false;
        for (int ly = 0; ly < (in.lens.radius > 0 ? kLens : 1) && !hitAtT; ++ly) {
            for (int lx = 0; lx < (in.lens.radius > 0 ? kLens : 1) && !hitAtT; ++lx) {
                // Lens grid over the square [-R, R]^2 clipped to the disk (extremes included).
                Vec2 lens(0);
                if (in.lens.radius > 0) {
                    lens = Vec2(-1.0f + 2.0f * float(lx) / (kLens - 1),
                                -1.0f + 2.0f * float(ly) / (kLens - 1));
                    if (glm::length(lens) > 1.0f) lens /= glm::length(lens);
                }
                for (int sy = 0; sy < kScreen && !hitAtT; ++sy) {
                    for (int sx = 0; sx < kScreen && !hitAtT; ++sx) {
                        const Vec2 raster(float(in.tile.x0) + float(in.tile.x1 - in.tile.x0) *
                                                                  float(sx) / (kScreen - 1),
                                          float(in.tile.y0) + float(in.tile.y1 - in.tile.y0) *
                                                                  float(sy) / (kScreen - 1));
                        const Ray ray =
                            makeCameraRay(cam, rasterToScreen(cam, raster), lens, t, in.lens);
                        const double dpl = ray.depthPerLambda;
                        hitAtT = rayHitsBox(glm::dvec3(ray.origin), glm::dvec3(ray.direction), box,
                                            cam.nearPlane() / dpl, cam.farPlane() / dpl);
                    }
                }
            }
        }
        if (hitAtT) {
            truth.hit = true;
            truth.hitTimes.push_back(t);
        }
    }
    return truth;
}

TileTestInput randomCase(const Camera& camera, bool defocus, std::mt19937_64& rng) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    TileTestInput in;
    in.camera = &camera;
    if (defocus) in.lens = {0.05f + 0.5f * unit(rng), 2.0f + 8.0f * unit(rng)};
    // A box around a point in view, of random size, moving by a random amount (sometimes along a
    // plane, sometimes straight at the camera, sometimes not at all).
    const float depth = 1.0f + 12.0f * unit(rng);
    const Vec3 centre((unit(rng) - 0.5f) * depth, (unit(rng) - 0.5f) * depth, -depth);
    const Vec3 half = Vec3(unit(rng), unit(rng), unit(rng)) * (0.02f + 0.5f * unit(rng));
    Vec3 motion = (Vec3(unit(rng), unit(rng), unit(rng)) - 0.5f) * (3.0f * unit(rng));
    const int kind = int(unit(rng) * 4.0f);
    if (kind == 0) motion = Vec3(0);
    if (kind == 1) motion = Vec3(0, 0, motion.z);
    in.box.bounds0 = {centre - half, centre + half};
    in.box.bounds1 = {centre - half + motion, centre + half + motion};
    // A tile near where the box is seen at t=0.5.
    Vec2 raster;
    camera.cameraToRaster(centre + 0.5f * motion, raster);
    const int size = 4 << int(unit(rng) * 3.0f);
    const int x = int(std::floor(raster.x + (unit(rng) - 0.5f) * 48.0f));
    const int y = int(std::floor(raster.y + (unit(rng) - 0.5f) * 48.0f));
    in.tile = {x - x % 4, y - y % 4, x - x % 4 + size, y - y % 4 + size};
    return in;
}

}  // namespace

std::vector<TileTestReport> verifyTileTests(int cases, std::uint64_t seed) {
    CameraDesc desc;
    desc.open = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}};
    desc.close = desc.open;
    desc.fovYDegrees = 60.0f;
    desc.nearPlane = 0.1f;
    desc.farPlane = 100.0f;
    const Camera camera(desc, {}, 128, 128);
    std::vector<TileTestReport> reports;
    for (const auto& variant : registeredTileTests()) reports.push_back({variant->name()});
    for (int defocus = 0; defocus < 2; ++defocus) {
        std::mt19937_64 rng(mix64(seed + std::uint64_t(defocus)));
        for (int c = 0; c < cases; ++c) {
            const TileTestInput in = randomCase(camera, defocus != 0, rng);
            const Truth truth = groundTruth(in);
            for (std::size_t v = 0; v < reports.size(); ++v) {
                const TileTestVariant& variant = *registeredTileTests()[v];
                if ((defocus != 0) != variant.handlesDefocus()) continue;
                const TileTestOutput out = variant.run(in);
                TileTestReport& r = reports[v];
                ++r.cases;
                if (!truth.hit) {
                    out.accept ? ++r.falseAccepts : ++r.trueRejects;
                    continue;
                }
                const bool timesCovered =
                    std::all_of(truth.hitTimes.begin(), truth.hitTimes.end(),
                                [&](float t) { return out.times.contains(t); });
                if (!out.accept || !timesCovered) ++r.falseRejects;
            }
        }
    }
    return reports;
}

}  // namespace patchsim
