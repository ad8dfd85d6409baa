#include "rasterizer/patch_rasterizer.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "pipeline/core/counters.h"
#include "rasterizer/watertight_triangle.h"

namespace patchsim {

PATCHSIM_COUNTER("RS/Patches", "patches", "Patches given to the patch rasterizer", rsPatches);
PATCHSIM_COUNTER("RS/Tiles in bounds", "tiles",
                 "Tiles inside a group's screen bounds (each is tested)", rsTilesInBounds);
PATCHSIM_COUNTER("RS/Tiles rejected by space", "tiles",
                 "Tiles whose frustum misses every box at every time", rsTilesRejectedSpace);
PATCHSIM_COUNTER("RS/Tiles rejected by time", "tiles",
                 "Tiles whose leaves overlap in space but whose time intervals are all empty",
                 rsTilesRejectedTime);
PATCHSIM_COUNTER("RS/Tiles overlapping", "tiles", "Tiles whose samples were considered",
                 rsTilesOverlapping);
PATCHSIM_COUNTER("RS/Frustum node visits", "nodes", "Hierarchy nodes tested against a tile frustum",
                 rsNodeVisits);
PATCHSIM_COUNTER("RS/Plane tests", "tests",
                 "Box n-vertex (or p-vertex) against one frustum plane at one time", rsPlaneTests);
PATCHSIM_COUNTER("RS/Leaf time intervals", "crossings",
                 "Plane crossing times computed at leaves (d0 / (d0 - d1))", rsTimeIntervals);
PATCHSIM_COUNTER("RS/Branch node depth", "levels",
                 "Sum over overlapping tiles of the level of the node rays start from",
                 rsBranchDepth);
PATCHSIM_COUNTER("RS/Samples tested", "samples", "Samples of overlapping tiles considered",
                 rsSamplesTested);
PATCHSIM_COUNTER("RS/Samples rejected by time", "samples",
                 "Samples outside the tile's [tmin, tmax], rejected without a ray",
                 rsSamplesRejectedTime);
PATCHSIM_COUNTER("RS/Rays cast", "rays", "Per-sample rays traversed from the branch node",
                 rsRaysCast);
PATCHSIM_COUNTER("RS/Ray-box tests", "tests",
                 "Ray against a moving box at the sample's time (12 multiply-adds)", rsRayBoxTests);
PATCHSIM_COUNTER("RS/Ray-triangle tests", "tests",
                 "Watertight ray-triangle tests on triangles blended to the sample's time",
                 rsRayTriangleTests);
PATCHSIM_COUNTER("RS/Visibility samples", "samples",
                 "Ray hits nearer than the sample's z-buffer depth, sent to the back end",
                 rsVisibilitySamples);
PATCHSIM_COUNTER("OM/Transparent fragments", "fragments",
                 "Transparent hits offered to a sample's layers", omTransparentFragments);
PATCHSIM_COUNTER(
    "OM/Transparent overflow", "fragments",
    "Transparent fragments dropped because a sample's layers were full (the farthest goes)",
    omTransparentOverflow);
PATCHSIM_COUNTER(
    "RS/Full-screen bounds", "groups",
    "Groups whose boxes reach in front of the near plane: bounds fall back to the whole screen",
    rsFullScreen);

void WorkCounts::add(const WorkCounts& o) {
    tilesInBounds += o.tilesInBounds;
    tilesRejectedSpace += o.tilesRejectedSpace;
    tilesRejectedTime += o.tilesRejectedTime;
    tilesOverlapping += o.tilesOverlapping;
    planeTests += o.planeTests;
    timeIntervals += o.timeIntervals;
    frustumNodeVisits += o.frustumNodeVisits;
    branchDepthSum += o.branchDepthSum;
    samplesTested += o.samplesTested;
    samplesRejectedTime += o.samplesRejectedTime;
    raysCast += o.raysCast;
    rayBoxTests += o.rayBoxTests;
    rayTriangleTests += o.rayTriangleTests;
    visibilitySamples += o.visibilitySamples;
    fullScreenBounds += o.fullScreenBounds;
    patches += o.patches;
    transparentFragments += o.transparentFragments;
    transparentOverflow += o.transparentOverflow;
}

void WorkCounts::flush() const {
    rsTilesInBounds += tilesInBounds;
    rsTilesRejectedSpace += tilesRejectedSpace;
    rsTilesRejectedTime += tilesRejectedTime;
    rsTilesOverlapping += tilesOverlapping;
    rsPlaneTests += planeTests;
    rsTimeIntervals += timeIntervals;
    rsNodeVisits += frustumNodeVisits;
    rsBranchDepth += branchDepthSum;
    rsSamplesTested += samplesTested;
    rsSamplesRejectedTime += samplesRejectedTime;
    rsRaysCast += raysCast;
    rsRayBoxTests += rayBoxTests;
    rsRayTriangleTests += rayTriangleTests;
    rsVisibilitySamples += visibilitySamples;
    rsFullScreen += fullScreenBounds;
    rsPatches += patches;
    omTransparentFragments += transparentFragments;
    omTransparentOverflow += transparentOverflow;
}

Ray sampleRay(const Camera& camera, const LensModel& lens, const SampleGenerator& samples, int x,
              int y, int s) {
    const Sample smp = samples.sample(x, y, s);
    const Vec2 screen = rasterToScreen(camera, Vec2(float(x), float(y)) + smp.pixelOffset);
    return makeCameraRay(screen, concentricDisk(smp.lens), smp.time, lens);
}

namespace {

// Calls onHit(record) for every triangle the ray hits at its time within [lambdaMin, lambdaMax].
template <typename OnHit>
void forEachHit(const MovingMesh& mesh, const std::uint32_t* triangles, std::size_t count,
                const Ray& ray, float lambdaMin, float lambdaMax, const OnHit& onHit) {
    const ShearedRay sheared = shearRay(ray);
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t tri = triangles[k];
        const std::uint32_t* v = &mesh.indices[3 * std::size_t(tri)];
        TriangleHit hit;
        if (intersectTriangle(sheared, mesh.vertexAt(v[0], ray.time), mesh.vertexAt(v[1], ray.time),
                              mesh.vertexAt(v[2], ray.time), lambdaMin, lambdaMax, hit))
            onHit(VisibilityRecord{hit.lambda * ray.depthPerLambda, mesh.patchId, tri, hit.b1,
                                   hit.b2});
    }
}

}  // namespace

int intersectTriangles(const MovingMesh& mesh, const std::uint32_t* triangles, std::size_t count,
                       const Ray& ray, float lambdaMin, float lambdaMax, VisibilityRecord& best) {
    forEachHit(mesh, triangles, count, ray, lambdaMin, lambdaMax, [&](const VisibilityRecord& hit) {
        if (hit.nearerThan(best)) best = hit;
    });
    return int(count);
}

int offerAllHits(const MovingMesh& mesh, const std::uint32_t* triangles, std::size_t count,
                 const Ray& ray, float lambdaMin, float lambdaMax, TransparentLayers& layers,
                 std::size_t sample, int pool, WorkCounts& work) {
    forEachHit(mesh, triangles, count, ray, lambdaMin, lambdaMax, [&](const VisibilityRecord& hit) {
        ++work.transparentFragments;
        if (!layers.offer(sample, pool, LayerFragment{hit, mesh.objectId}))
            ++work.transparentOverflow;
    });
    return int(count);
}

namespace {

void recordPixelWork(PixelWork& pixels, int x, int y, const WorkCounts& start,
                     const WorkCounts& now) {
    const std::size_t p = pixels.pixel(x, y);
    pixels.samplesTested[p] += std::uint32_t(now.samplesTested - start.samplesTested);
    pixels.raysCast[p] += std::uint32_t(now.raysCast - start.raysCast);
    pixels.rayBoxTests[p] += std::uint32_t(now.rayBoxTests - start.rayBoxTests);
    pixels.rayTriangleTests[p] += std::uint32_t(now.rayTriangleTests - start.rayTriangleTests);
    pixels.visibilitySamples[p] +=
        std::uint32_t(now.visibilitySamples - start.visibilitySamples + now.transparentFragments -
                      start.transparentFragments);
}

// Per-ray slab constants: entry along an axis is x0 * A + x1 * B + C with A = (1-t)/d,
// B = t/d, C = -o/d, i.e. ((1-t) x0 + t x1 - o) / d for the box face blended to the ray's time.
struct SlabRay {
    Vec3 a, b, c;
    float lambdaMin, lambdaMax;
    // Axes the ray runs parallel to (a +0 or -0 component): there the ray is inside the slab for
    // every lambda or for none, decided by where its origin lies.
    bool parallel[3];
    Vec3 origin;
    float time;
};

SlabRay makeSlabRay(const Ray& ray, float lambdaMin, float lambdaMax) {
    SlabRay s;
    for (int k = 0; k < 3; ++k) {
        s.parallel[k] = std::abs(ray.direction[k]) < 1e-30f;
        const float inv = s.parallel[k] ? 0.0f : 1.0f / ray.direction[k];
        s.a[k] = (1.0f - ray.time) * inv;
        s.b[k] = ray.time * inv;
        s.c[k] = -ray.origin[k] * inv;
    }
    s.origin = ray.origin;
    s.time = ray.time;
    s.lambdaMin = lambdaMin;
    s.lambdaMax = lambdaMax;
    return s;
}

bool hitsBox(const SlabRay& r, const LBBox& box) {
    if (box.empty()) return false;
    float nearest = r.lambdaMin, farthest = r.lambdaMax;
    for (int k = 0; k < 3; ++k) {
        if (r.parallel[k]) {
            // Inclusive, with the same blend as the vertices: a ray on a face still meets it.
            const float lo = lerp(box.bounds0.lower, box.bounds1.lower, r.time)[k];
            const float hi = lerp(box.bounds0.upper, box.bounds1.upper, r.time)[k];
            if (r.origin[k] < lo || r.origin[k] > hi) return false;
            continue;
        }
        const float e0 = box.bounds0.lower[k] * r.a[k] + box.bounds1.lower[k] * r.b[k] + r.c[k];
        const float e1 = box.bounds0.upper[k] * r.a[k] + box.bounds1.upper[k] * r.b[k] + r.c[k];
        nearest = std::max(nearest, std::min(e0, e1));
        farthest = std::min(farthest, std::max(e0, e1));
    }
    // Slack for rounding in the multiply-adds: flat boxes must never be missed.
    return nearest <= farthest + 1e-5f * (std::abs(nearest) + std::abs(farthest)) + 1e-30f;
}

int bitmaskBranch(std::uint64_t mask, int depth) {
    // Reduce level by level (OR of sibling pairs) until exactly one bit is set.
    for (int level = depth; level >= 0; --level) {
        if ((mask & (mask - 1)) == 0)
            return PatchHierarchy::firstLeaf(level) + std::countr_zero(mask);
        std::uint64_t up = 0;
        for (int j = 0; j < (1 << level); j += 2)
            if (mask & (std::uint64_t(3) << j)) up |= std::uint64_t(1) << (j / 2);
        mask = up;
    }
    return 0;
}

}  // namespace

bool rayMeetsMovingBox(const Ray& ray, const LBBox& box, float lambdaMin, float lambdaMax) {
    return hitsBox(makeSlabRay(ray, lambdaMin, lambdaMax), box);
}

PatchRasterizer::PatchRasterizer(const Camera& camera, const LensModel& lens,
                                 const SampleGenerator& samples, const Effects& effects,
                                 const RasterizerOptions& options)
    : camera_(camera), lens_(lens), samples_(samples), effects_(effects), options_(options) {
    if (!effects_.defocus) lens_.radius = 0;
}

void PatchRasterizer::screenBounds(const PatchHierarchy& h, float bounds[4],
                                   WorkCounts& work) const {
    const int level = std::min(options_.boundsLevel, h.depth());
    float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
    const float tanX = camera_.tanHalfFovY() * camera_.aspect(), tanY = camera_.tanHalfFovY();
    for (int node = PatchHierarchy::firstLeaf(level); node < PatchHierarchy::firstLeaf(level + 1);
         ++node) {
        const LBBox& box = h.node(node);
        if (box.empty()) continue;
        for (const Box3* b : {&box.bounds0, &box.bounds1}) {
            for (int c = 0; c < 8; ++c) {
                const Vec3 p = b->corner(c);
                const float depth = -p.z;
                // A corner in front of the near plane has no finite projection: whole screen.
                if (!(depth >= camera_.nearPlane()) || !std::isfinite(depth)) {
                    ++work.fullScreenBounds;
                    bounds[0] = 0;
                    bounds[1] = 0;
                    bounds[2] = float(camera_.width());
                    bounds[3] = float(camera_.height());
                    return;
                }
                const float blur =
                    lens_.radius * std::abs(1.0f / depth - 1.0f / lens_.focusDistance);
                const float s[2] = {p.x / depth, p.y / depth};
                for (int k = 0; k < 2; ++k) {
                    lo[k] = std::min(lo[k], s[k] - blur);
                    hi[k] = std::max(hi[k], s[k] + blur);
                }
            }
        }
    }
    bounds[0] = (lo[0] / tanX + 1.0f) * 0.5f * float(camera_.width());
    bounds[2] = (hi[0] / tanX + 1.0f) * 0.5f * float(camera_.width());
    bounds[1] = (1.0f - hi[1] / tanY) * 0.5f * float(camera_.height());
    bounds[3] = (1.0f - lo[1] / tanY) * 0.5f * float(camera_.height());
    // Rounding in the projection must not cut off a sample exactly on the patch's edge.
    constexpr float kMarginPixels = 1.0f / 64.0f;
    bounds[0] -= kMarginPixels;
    bounds[1] -= kMarginPixels;
    bounds[2] += kMarginPixels;
    bounds[3] += kMarginPixels;
}

void PatchRasterizer::prepareGroup(const MovingMesh& mesh, const std::uint32_t* triangles,
                                   std::size_t count, Group& group, WorkCounts& work) const {
    group.hierarchy.build(mesh, triangles, count, options_.leafSize);
    float b[4];
    screenBounds(group.hierarchy, b, work);
    const int t = options_.tileSize;
    const int tilesX = (camera_.width() + t - 1) / t, tilesY = (camera_.height() + t - 1) / t;
    // One pixel of margin: sample positions reach the right/bottom edge of their pixel.
    group.tileX0 = std::clamp(int(std::floor(b[0])) / t, 0, tilesX);
    group.tileY0 = std::clamp(int(std::floor(b[1])) / t, 0, tilesY);
    group.tileX1 = std::clamp(int(std::floor(b[2])) / t + 1, 0, tilesX);
    group.tileY1 = std::clamp(int(std::floor(b[3])) / t + 1, 0, tilesY);
    if (!(b[0] <= b[2]) || !(b[1] <= b[3]) || b[2] < 0 || b[3] < 0 ||
        b[0] > float(camera_.width()) || b[1] > float(camera_.height())) {
        group.tileX1 = group.tileX0;  // nothing on screen
    }
}

TileFrustum PatchRasterizer::tileFrustum(const TileRect& tile,
                                         const VisibilityBuffer& buffer) const {
    float farDepth = camera_.farPlane();
    if (options_.zCulling) {
        float deepest = 0;
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x)
                for (int s = 0; s < buffer.samplesPerPixel(); ++s)
                    deepest = std::max(deepest, buffer.depthBound(x, y, s));
        farDepth = deepest;
    }
    return makeTileFrustum(camera_, lens_, tile, farDepth);
}

TileTraversal PatchRasterizer::traverseTile(const Group& group, const TileFrustum& frustumIn,
                                            WorkCounts& work) const {
    const PatchHierarchy& h = group.hierarchy;
    const bool motion = effects_.motion;
    const bool refine = motion && options_.timeRefinement;
    FrustumWork fw;
    TileTraversal result;
    TileFrustum frustum = frustumIn;
    // Near and far: tested with the root's p-vertex once; inside both, only the sides remain.
    frustum.testNearFar = !insideNearFar(frustum, h.node(0), fw);
    ++work.frustumNodeVisits;
    bool spatialLeaf = false;
    if (overlapsFrustum(frustum, h.node(0), motion, fw)) {
        result.tmin = 1.0f;
        result.tmax = 0.0f;
        int stack[2 * kMaxLeaves];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const int node = stack[--top];
            if (h.isLeaf(node)) {
                spatialLeaf = true;
                float lo = 0.0f, hi = 1.0f;
                if (refine && !leafTimeInterval(frustum, h.node(node), lo, hi, fw)) continue;
                result.leafMask |= std::uint64_t(1)
                                   << (node - PatchHierarchy::firstLeaf(h.depth()));
                result.tmin = std::min(result.tmin, lo);
                result.tmax = std::max(result.tmax, hi);
                if (result.firstSplitNode < 0) result.firstSplitNode = node;
                continue;
            }
            const int left = 2 * node + 1, right = 2 * node + 2;
            work.frustumNodeVisits += 2;
            const bool inLeft = overlapsFrustum(frustum, h.node(left), motion, fw);
            const bool inRight = overlapsFrustum(frustum, h.node(right), motion, fw);
            if (inLeft && inRight && result.firstSplitNode < 0) result.firstSplitNode = node;
            if (inRight) stack[top++] = right;
            if (inLeft) stack[top++] = left;
        }
    }
    work.planeTests += fw.planeTests;
    work.timeIntervals += fw.timeIntervals;
    if (result.leafMask == 0) {
        ++(spatialLeaf ? work.tilesRejectedTime : work.tilesRejectedSpace);
        return result;
    }
    result.overlaps = true;
    result.bitmaskNode = bitmaskBranch(result.leafMask, h.depth());
    if (!motion) {
        result.tmin = 0.0f;
        result.tmax = 1.0f;
    }
    return result;
}

void PatchRasterizer::traceSamples(const MovingMesh& mesh, const Group& group, const TileRect& tile,
                                   const TileTraversal& traversal, int branchNode,
                                   const VisibilityTargets& targets, WorkCounts& work) const {
    const PatchHierarchy& h = group.hierarchy;
    VisibilityBuffer& buffer = *targets.opaque;
    PixelWork* pixels = targets.pixelWork;
    const bool everyHit = !mesh.opaque && targets.transparent != nullptr;
    const int spp = buffer.samplesPerPixel();
    const bool motion = effects_.motion;
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
            WorkCounts pixelStart;  // only read for heat maps
            if (pixels) pixelStart = work;
            for (int s = 0; s < spp; ++s) {
                ++work.samplesTested;
                const Sample smp = samples_.sample(x, y, s);
                if (motion && (smp.time < traversal.tmin || smp.time > traversal.tmax)) {
                    ++work.samplesRejectedTime;
                    continue;
                }
                const Vec2 screen =
                    rasterToScreen(camera_, Vec2(float(x), float(y)) + smp.pixelOffset);
                const Ray ray = makeCameraRay(screen, concentricDisk(smp.lens), smp.time, lens_);
                ++work.raysCast;
                const float lambdaMin = camera_.nearPlane() / ray.depthPerLambda;
                const float bound =
                    options_.zCulling || everyHit ? buffer.depthBound(x, y, s) : camera_.farPlane();
                // Inclusive, slightly widened: an equal-depth hit must still reach the tie-break.
                const float lambdaMax = bound / ray.depthPerLambda * (1.0f + 1e-6f);
                const SlabRay slab = makeSlabRay(ray, lambdaMin, lambdaMax);
                VisibilityRecord best = buffer.at(x, y, s);
                const VisibilityRecord previous = best;
                int stack[2 * kMaxLeaves];
                int top = 0;
                stack[top++] = branchNode;
                while (top > 0) {
                    const int node = stack[--top];
                    ++work.rayBoxTests;
                    if (!hitsBox(slab, h.node(node))) continue;
                    if (h.isLeaf(node)) {
                        std::size_t count;
                        const std::uint32_t* tris =
                            h.leafTriangles(node - PatchHierarchy::firstLeaf(h.depth()), count);
                        work.rayTriangleTests +=
                            everyHit ? offerAllHits(mesh, tris, count, ray, lambdaMin, lambdaMax,
                                                    *targets.transparent, buffer.index(x, y, s),
                                                    targets.pool, work)
                                     : intersectTriangles(mesh, tris, count, ray, lambdaMin,
                                                          lambdaMax, best);
                        continue;
                    }
                    stack[top++] = 2 * node + 2;
                    stack[top++] = 2 * node + 1;
                }
                if (best.patch != previous.patch || best.triangle != previous.triangle ||
                    best.depth != previous.depth) {
                    ++work.visibilitySamples;
                    buffer.offer(x, y, s, best);
                }
            }
            if (pixels) recordPixelWork(*pixels, x, y, pixelStart, work);
        }
    }
}

void PatchRasterizer::rasterizeTile(const MovingMesh& mesh, const Group& group, int tileX,
                                    int tileY, const VisibilityTargets& targets,
                                    WorkCounts& work) const {
    const int t = options_.tileSize;
    const TileRect tile{tileX * t, tileY * t, std::min((tileX + 1) * t, camera_.width()),
                        std::min((tileY + 1) * t, camera_.height())};
    ++work.tilesInBounds;
    if (targets.pixelWork) ++targets.pixelWork->tileTests[targets.pixelWork->tile(tileX, tileY)];
    const TileTraversal traversal = traverseTile(group, tileFrustum(tile, *targets.opaque), work);
    if (!traversal.overlaps) return;
    ++work.tilesOverlapping;
    int branch = 0;
    if (options_.branchMethod == BranchMethod::FirstSplit) branch = traversal.firstSplitNode;
    if (options_.branchMethod == BranchMethod::Bitmask) branch = traversal.bitmaskNode;
    work.branchDepthSum += group.hierarchy.levelOf(branch);
    traceSamples(mesh, group, tile, traversal, branch, targets, work);
}

void PatchRasterizer::rasterize(const MovingMesh& mesh, const VisibilityTargets& targets,
                                WorkCounts& work) {
    ++work.patches;
    splitIntoGroups(mesh, options_.trianglesPerGroup(), order_, groupBegin_);
    for (std::size_t g = 0; g + 1 < groupBegin_.size(); ++g) {
        const std::uint32_t begin = groupBegin_[g], end = groupBegin_[g + 1];
        if (begin == end) continue;
        prepareGroup(mesh, order_.data() + begin, end - begin, group_, work);
        for (int ty = group_.tileY0; ty < group_.tileY1; ++ty)
            for (int tx = group_.tileX0; tx < group_.tileX1; ++tx)
                rasterizeTile(mesh, group_, tx, ty, targets, work);
    }
}

}  // namespace patchsim
