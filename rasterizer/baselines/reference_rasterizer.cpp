#include "rasterizer/baselines/reference_rasterizer.h"

#include "core/counters.h"
#include "rasterizer/common/conservative_margins.h"
#include "rasterizer/common/lens_triangle.h"
#include "rasterizer/common/screen_triangle.h"
#include "rasterizer/common/watertight_triangle_rounded.h"
#include "rasterizer/patent/raster_work.h"

namespace patchsim {

PATCHSIM_WORK_DEFINE(ReferenceWork, ReferenceCounters, referenceCounters, PATCHSIM_REFERENCE_WORK)

const RatioCounter& referenceSampleTestEfficiency() {
    static const RatioCounter ratio{"REF/Sample test efficiency",
                                    "Reference visibility samples per ray-triangle test",
                                    hitsCounter, triangleTestsCounter};
    return ratio;
}

namespace {

// The hit of `ray` on triangle `tri` of `mesh` at the ray's time, if any.
bool hitTriangle(const MovingMesh& mesh, std::uint32_t tri, const ShearedRay& sheared,
                 const Ray& ray, float lambdaMax, const NumberFormat& format,
                 VisibilityRecord& record) {
    const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
    TriangleHit hit;
    if (!intersectTriangleIn(format, sheared, mesh.vertexAt(v[0], ray.time),
                             mesh.vertexAt(v[1], ray.time), mesh.vertexAt(v[2], ray.time),
                             ray.lambdaMin, lambdaMax, hit))
        return false;
    record.depth = hit.lambda * ray.depthPerLambda;
    record.patch = mesh.patchId;
    record.triangle = tri;
    record.b1 = hit.b1;
    record.b2 = hit.b2;
    return true;
}

// `setup` of every mesh's triangles at their t=0 positions, in mesh order: their screen form
// (static frames) or lens form (defocus-only frames).
template <class Setup>
auto setUpEveryTriangle(const std::vector<MovingMesh>& meshes, const Setup& setup) {
    std::vector<decltype(setup(Vec3(), Vec3(), Vec3()))> out;
    for (const MovingMesh& mesh : meshes)
        for (std::uint32_t tri = 0; tri < mesh.triangleCount(); ++tri) {
            const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
            out.push_back(setup(mesh.position0[v[0]], mesh.position0[v[1]], mesh.position0[v[2]]));
        }
    return out;
}

// The sample's hit on a triangle: the screen test where the triangle has a screen form (static
// frames), the lens test where it has a lens form (defocus-only frames), else the ray test. All
// end at depth `depthMax` (the ray's parameter lambdaMax).
struct SampleTester {
    const ShearedRay& sheared;
    const Ray& ray;
    const ScreenTriangle* screen;  // null: no screen form
    const LensTriangle* lensForm;  // null: no lens form
    const NumberFormat& triangleFormat;
    double subpixelX, subpixelY;
    Vec2 screenPoint;  // the sample on the plane z = -1
    int x, y;

    bool hit(const MovingMesh& mesh, std::uint32_t tri, std::size_t index, float lambdaMax,
             VisibilityRecord& record) const {
        ScreenHit hit;
        if (screen != nullptr && screen[index].kind != ScreenTriangle::Kind::NeedsRay) {
            const ScreenTriangle& t = screen[index];
            if (t.kind == ScreenTriangle::Kind::Empty || x < t.pixelX0 || x >= t.pixelX1 ||
                y < t.pixelY0 || y >= t.pixelY1)
                return false;
            if (!coverSample(t, subpixelX, subpixelY, ray.lambdaMin * ray.depthPerLambda,
                             lambdaMax * ray.depthPerLambda, hit))
                return false;
        } else if (lensForm != nullptr && lensForm[index].kind != LensTriangle::Kind::NeedsRay) {
            const LensTriangle& t = lensForm[index];
            if (t.kind == LensTriangle::Kind::Empty || x < t.pixels.x0 || x >= t.pixels.x1 ||
                y < t.pixels.y0 || y >= t.pixels.y1)
                return false;
            if (!coverLensSample(t, screenPoint.x, screenPoint.y, ray.origin.x, ray.origin.y,
                                 ray.lambdaMin * ray.depthPerLambda, lambdaMax * ray.depthPerLambda,
                                 hit))
                return false;
        } else {
            return hitTriangle(mesh, tri, sheared, ray, lambdaMax, triangleFormat, record);
        }
        record.depth = hit.depth;
        record.patch = mesh.patchId;
        record.triangle = tri;
        record.b1 = hit.b1;
        record.b2 = hit.b2;
        return true;
    }
};

}  // namespace

void renderReferenceRows(const std::vector<MovingMesh>& meshes, const Camera& camera,
                         const LensModel& lens, const SampleGenerator& samples, bool motion, int y0,
                         int y1, const VisibilityTargets& targets, ReferenceWork& total,
                         const NumberFormat& triangleFormat) {
    ReferenceWork work;
    RasterWork layerWork;
    VisibilityBuffer& buffer = *targets.opaque;
    // One set-up per triangle for the band (a reference, outside the memory budget).
    const auto screenForm = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        return setupScreenTriangle(camera, a, b, c);
    };
    const auto lensSetup = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        return setupLensTriangle(camera, lens, a, b, c);
    };
    const std::vector<ScreenTriangle> screen = !motion && !(lens.radius > 0)
                                                   ? setUpEveryTriangle(meshes, screenForm)
                                                   : std::vector<ScreenTriangle>();
    const std::vector<LensTriangle> lensForm = !motion && lens.radius > 0
                                                   ? setUpEveryTriangle(meshes, lensSetup)
                                                   : std::vector<LensTriangle>();
    for (int y = y0; y < y1; ++y) {
        for (int x = 0; x < buffer.width(); ++x) {
            for (int s = 0; s < buffer.samplesPerPixel(); ++s) {
                const Sample smp = samples.sample(x, y, s);
                const Vec2 raster = Vec2(float(x), float(y)) + smp.pixelOffset;
                const Vec2 screenPoint = rasterToScreen(camera, raster);
                const Ray ray =
                    makeCameraRay(camera, screenPoint, concentricDisk(smp.lens), smp.time, lens);
                const ShearedRay sheared = shearRay(ray);
                const SampleTester tester{sheared,
                                          ray,
                                          screen.empty() ? nullptr : screen.data(),
                                          lensForm.empty() ? nullptr : lensForm.data(),
                                          triangleFormat,
                                          sampleSubpixel(x, smp.pixelOffset.x),
                                          sampleSubpixel(y, smp.pixelOffset.y),
                                          screenPoint,
                                          x,
                                          y};
                std::size_t first = 0;  // the mesh's first triangle in `screen`
                VisibilityRecord best, hit;
                best.time = hit.time = smp.time;
                best.lens = hit.lens = smp.lens;
                for (const MovingMesh& mesh : meshes) {
                    const std::size_t meshFirst = first;
                    first += mesh.triangleCount();
                    if (!mesh.opaque && targets.transparent) continue;
                    for (std::uint32_t tri = 0; tri < mesh.triangleCount(); ++tri)
                        if (tester.hit(mesh, tri, meshFirst + tri, ray.lambdaMax, hit) &&
                            hit.nearerThan(best))
                            best = hit;
                    work.triangleTests += std::int64_t(mesh.triangleCount());
                }
                // Transparent surfaces in front of the nearest opaque one (inclusive, widened as
                // the patch method's z culling is, so both keep the same fragments).
                const float opaqueLambda =
                    best.hit() ? best.depth / ray.depthPerLambda * (1.0f + kDepthTieWidening)
                               : ray.lambdaMax;
                first = 0;
                for (const MovingMesh& mesh : meshes) {
                    const std::size_t meshFirst = first;
                    first += mesh.triangleCount();
                    if (mesh.opaque || !targets.transparent) continue;
                    for (std::uint32_t tri = 0; tri < mesh.triangleCount(); ++tri) {
                        if (!tester.hit(mesh, tri, meshFirst + tri, opaqueLambda, hit)) continue;
                        ++layerWork.transparentFragments;
                        if (!targets.transparent->offer(buffer.index(x, y, s), targets.pool,
                                                        LayerFragment{hit, mesh.objectId}))
                            ++layerWork.transparentOverflow;
                    }
                    work.triangleTests += std::int64_t(mesh.triangleCount());
                }
                ++work.samples;
                if (best.hit()) {
                    ++work.hits;
                    buffer.at(x, y, s) = best;
                }
            }
        }
    }
    total.add(work);
    work.flush();
    layerWork.flush();
}

}  // namespace patchsim
