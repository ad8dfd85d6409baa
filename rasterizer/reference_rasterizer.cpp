#include "rasterizer/reference_rasterizer.h"

#include <algorithm>
#include <numeric>

#include "pipeline/core/counters.h"
#include "rasterizer/patch_rasterizer.h"

namespace patchsim {

PATCHSIM_COUNTER("REF/Samples", "samples", "Samples traced by the reference method", refSamples);
PATCHSIM_COUNTER("REF/Ray-triangle tests", "tests",
                 "Reference ray-triangle tests (every sample against every triangle)",
                 refTriangleTests);
PATCHSIM_COUNTER("REF/Visibility samples", "samples", "Reference samples that hit a surface",
                 refHits);

void renderReferenceRows(const std::vector<MovingMesh>& meshes, const Camera& camera,
                         const LensModel& lens, const SampleGenerator& samples, int y0, int y1,
                         const VisibilityTargets& targets, ReferenceWork& total) {
    ReferenceWork work;
    WorkCounts layerWork;
    VisibilityBuffer& buffer = *targets.opaque;
    // Triangle ids 0..n-1 once for the largest mesh; each mesh uses its own prefix.
    std::size_t largest = 0;
    for (const MovingMesh& mesh : meshes) largest = std::max(largest, mesh.triangleCount());
    std::vector<std::uint32_t> all(largest);
    std::iota(all.begin(), all.end(), std::uint32_t(0));
    for (int y = y0; y < y1; ++y) {
        for (int x = 0; x < buffer.width(); ++x) {
            for (int s = 0; s < buffer.samplesPerPixel(); ++s) {
                const Ray ray = sampleRay(camera, lens, samples, x, y, s);
                const float lambdaMin = camera.nearPlane() / ray.depthPerLambda;
                const float lambdaMax = camera.farPlane() / ray.depthPerLambda;
                VisibilityRecord best;
                for (const MovingMesh& mesh : meshes) {
                    if (!mesh.opaque && targets.transparent) continue;
                    work.triangleTests += intersectTriangles(mesh, all.data(), mesh.triangleCount(),
                                                             ray, lambdaMin, lambdaMax, best);
                }
                // Transparent surfaces in front of the nearest opaque one (inclusive, widened as
                // the patch method does, so both keep the same fragments).
                const float opaqueLambda =
                    best.hit() ? best.depth / ray.depthPerLambda * (1.0f + 1e-6f) : lambdaMax;
                for (const MovingMesh& mesh : meshes) {
                    if (mesh.opaque || !targets.transparent) continue;
                    work.triangleTests += offerAllHits(
                        mesh, all.data(), mesh.triangleCount(), ray, lambdaMin, opaqueLambda,
                        *targets.transparent, buffer.index(x, y, s), targets.pool, layerWork);
                }
                ++work.samples;
                if (best.hit()) {
                    ++work.hits;
                    buffer.at(x, y, s) = best;
                }
            }
        }
    }
    total.samples += work.samples;
    total.triangleTests += work.triangleTests;
    total.hits += work.hits;
    refSamples += work.samples;
    refTriangleTests += work.triangleTests;
    refHits += work.hits;
    layerWork.flush();
}

}  // namespace patchsim
