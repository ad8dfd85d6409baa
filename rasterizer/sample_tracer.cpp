#include "rasterizer/sample_tracer.h"

#include "rasterizer/moving_box_ray.h"
#include "rasterizer/tile_samples.h"
#include "rasterizer/watertight_triangle.h"
#include "rasterizer/z_culling.h"

namespace patchsim {

Ray sampleRay(const RayCaster& c, int x, int y, int s) {
    const Sample smp = c.samples.sample(x, y, s);
    const Vec2 screen = rasterToScreen(c.camera, Vec2(float(x), float(y)) + smp.pixelOffset);
    return makeCameraRay(c.camera, screen, concentricDisk(smp.lens), smp.time, c.lens);
}

namespace {

// Calls onHit(record) for every triangle of a leaf the ray hits at its time within its range;
// `sample` carries the sample's time and lens position into the records.
template <typename OnHit>
void forEachLeafHit(const MovingMesh& mesh, const std::uint32_t* triangles, std::size_t count,
                    const Ray& ray, const ShearedRay& sheared, const VisibilityRecord& sample,
                    const OnHit& onHit) {
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t tri = triangles[k];
        const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
        TriangleHit hit;
        if (!intersectTriangle(sheared, mesh.vertexAt(v[0], ray.time),
                               mesh.vertexAt(v[1], ray.time), mesh.vertexAt(v[2], ray.time),
                               ray.lambdaMin, ray.lambdaMax, hit))
            continue;
        VisibilityRecord record = sample;
        record.depth = hit.lambda * ray.depthPerLambda;
        record.patch = mesh.patchOf(tri);
        record.triangle = mesh.triangleInPatchOf(tri);
        record.b1 = hit.b1;
        record.b2 = hit.b2;
        onHit(record);
    }
}

}  // namespace

void traceTileSamples(const RayCaster& caster, const MovingMesh& mesh, const PatchHierarchy& h,
                      int tileX, int tileY, const TileTraversal& traversal, int branchNode,
                      const VisibilityTargets& targets, RasterWork& work) {
    VisibilityBuffer& buffer = *targets.opaque;
    PixelCounters* pixels = targets.pixels;
    const bool everyHit = !mesh.opaque && targets.transparent != nullptr;
    const int firstLeaf = PatchHierarchy::firstLeaf(h.depth());
    const std::span<const TileSample> tile = targets.tileSamples->tile(tileX, tileY);
    const std::span<const TileSample> samples =
        caster.motion ? targets.tileSamples->inTime(tileX, tileY, traversal.times) : tile;
    work.samplesTested += std::int64_t(samples.size());
    work.samplesRejectedTime += std::int64_t(tile.size() - samples.size());
    std::vector<VisibilityRecord>& records = buffer.mutableRecords();
    const std::size_t spp = std::size_t(buffer.samplesPerPixel());
    for (const TileSample& smp : samples) {
        RasterWork sampleStart;  // only read for heat maps
        if (pixels) {
            sampleStart = work;
            --sampleStart.samplesTested;  // this sample
        }
        Ray ray = TileSamples::ray(smp, caster.camera, caster.lens);
        ++work.raysCast;
        VisibilityRecord& stored = records[smp.record];
        const float previousBound = buffer.depthBound(stored);
        const float bound = caster.zCulling || everyHit ? previousBound : caster.camera.farPlane();
        ray.lambdaMax = rayEndAtDepth(bound, ray.depthPerLambda);
        SlabRay slab = makeSlabRay(ray);
        const ShearedRay sheared = shearRay(ray);
        VisibilityRecord sample;
        sample.time = smp.time;
        sample.lens = smp.lens;
        VisibilityRecord best = stored;
        // Depth first, the nearer child first; an opaque hit shortens the ray (widened so a hit at
        // the same depth still reaches the tie-break), so farther boxes are skipped.
        int stack[2 * kMaxLeavesPerHierarchy];
        int top = 0;
        ++work.rayBoxTests;
        float entry = 0.0f;
        if (hitsMovingBox(slab, h.node(branchNode), entry)) stack[top++] = branchNode;
        while (top > 0) {
            const int node = stack[--top];
            if (!h.isLeaf(node)) {
                const int left = 2 * node + 1, right = 2 * node + 2;
                float leftEntry = 0.0f, rightEntry = 0.0f;  // read only after a hit
                work.rayBoxTests += 2;
                const bool inLeft = hitsMovingBox(slab, h.node(left), leftEntry);
                const bool inRight = hitsMovingBox(slab, h.node(right), rightEntry);
                if (inLeft && inRight) {
                    const bool leftFirst = leftEntry <= rightEntry;
                    stack[top++] = leftFirst ? right : left;
                    stack[top++] = leftFirst ? left : right;
                } else if (inLeft) {
                    stack[top++] = left;
                } else if (inRight) {
                    stack[top++] = right;
                }
                continue;
            }
            std::size_t count;
            const std::uint32_t* tris = h.leafTriangles(node - firstLeaf, count);
            work.rayTriangleTests += std::int64_t(count);
            if (everyHit) {
                forEachLeafHit(
                    mesh, tris, count, ray, sheared, sample, [&](const VisibilityRecord& hit) {
                        ++work.transparentFragments;
                        if (!targets.transparent->offer(smp.record, targets.pool,
                                                        LayerFragment{hit, mesh.objectId}))
                            ++work.transparentOverflow;
                    });
                continue;
            }
            bool nearer = false;
            forEachLeafHit(mesh, tris, count, ray, sheared, sample,
                           [&](const VisibilityRecord& hit) {
                               if (hit.nearerThan(best)) best = hit, nearer = true;
                           });
            if (nearer) {
                ray.lambdaMax =
                    std::min(ray.lambdaMax, rayEndAtDepth(best.depth, ray.depthPerLambda));
                slab.lambdaMax = ray.lambdaMax;
            }
        }
        if (best.patch != stored.patch || best.triangle != stored.triangle ||
            best.depth != stored.depth) {
            ++work.visibilitySamples;
            if (best.nearerThan(stored)) {
                stored = best;
                targets.depthBounds->lowered(tileX, tileY, previousBound);
            }
        }
        if (pixels) {
            const std::size_t pixel = smp.record / spp;
            pixels->record(int(pixel % std::size_t(buffer.width())),
                           int(pixel / std::size_t(buffer.width())), sampleStart, work);
        }
    }
}

}  // namespace patchsim
