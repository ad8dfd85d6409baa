#include "rasterizer/patent/patch_merge.h"

namespace patchsim {

namespace {

bool mergeable(const MovingMesh& m, int mergeBelow) {
    return m.triangleCount() > 0 && m.triangleCount() <= std::size_t(mergeBelow);
}

// The hierarchy orders triangles by "domain" position, alternately along its two axes. For a
// merged mesh that position is the patch's camera-space centre (x, y) at t=0, so the upper
// levels split the run's patches by where they are; the patch's own (u, v), scaled far below the
// patches' spacing, orders its triangles once a range holds one patch only.
void append(const MovingMesh& patch, MovingMesh& into) {
    const auto base = std::uint32_t(into.position0.size());
    into.position0.insert(into.position0.end(), patch.position0.begin(), patch.position0.end());
    into.position1.insert(into.position1.end(), patch.position1.begin(), patch.position1.end());
    Box3 extent;
    for (const Vec3& p : patch.position0) extent.extend(p);
    const Vec3 centre = 0.5f * (extent.lower + extent.upper);
    const float size = glm::length(extent.upper - extent.lower);
    for (Vec2 d : patch.domain)
        into.domain.push_back(Vec2(centre.x, centre.y) + 1e-3f * size * (d - 0.5f));
    for (std::uint32_t v : patch.indices) into.indices.push_back(base + v);
    for (std::uint32_t t = 0; t < patch.triangleCount(); ++t) {
        into.trianglePatch.push_back(patch.patchId);
        into.triangleInPatch.push_back(t);
    }
}

}  // namespace

RasterUnits makeRasterUnits(const std::vector<MovingMesh>& patches, int mergeBelow,
                            int trianglesPerGroup) {
    RasterUnits u;
    u.unitOf.resize(patches.size());
    // Runs first (indices into `patches`), so `merged` does not move once meshes point into it.
    std::vector<std::pair<std::size_t, std::size_t>> runs;
    for (std::size_t i = 0; i < patches.size();) {
        std::size_t end = i + 1, triangles = patches[i].triangleCount();
        if (mergeBelow > 0 && mergeable(patches[i], mergeBelow)) {
            while (end < patches.size() && mergeable(patches[end], mergeBelow) &&
                   patches[end].objectId == patches[i].objectId &&
                   patches[end].opaque == patches[i].opaque &&
                   triangles + patches[end].triangleCount() <= std::size_t(trianglesPerGroup))
                triangles += patches[end++].triangleCount();
        }
        runs.push_back({i, end});
        i = end;
    }
    std::size_t mergedCount = 0;
    for (auto [b, e] : runs) mergedCount += e - b > 1;
    u.merged.reserve(mergedCount);
    for (auto [b, e] : runs) {
        const std::size_t unit = u.meshes.size();
        for (std::size_t i = b; i < e; ++i) u.unitOf[i] = unit;
        u.firstPatch.push_back(b);
        u.patchCount.push_back(e - b);
        if (e - b == 1) {
            u.meshes.push_back(&patches[b]);
            continue;
        }
        MovingMesh& m = u.merged.emplace_back();
        m.patchId = patches[b].patchId;
        m.objectId = patches[b].objectId;
        m.opaque = patches[b].opaque;
        for (std::size_t i = b; i < e; ++i) append(patches[i], m);
        u.meshes.push_back(&m);
    }
    return u;
}

}  // namespace patchsim
