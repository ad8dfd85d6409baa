#include "pipeline/driver/render.h"

#include <chrono>

#include "backend/shading.h"
#include "pipeline/driver/parallel.h"
#include "rasterizer/patch_rasterizer.h"
#include "rasterizer/reference_rasterizer.h"
#include "tessellator/front_end.h"

namespace patchsim {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct PreparedPatch {
    std::vector<PatchRasterizer::Group> groups;
};

}  // namespace

void runPatchVisibility(const std::vector<MovingMesh>& meshes, const PatchRasterizer& rasterizer,
                        int workers, VisibilityBuffer& buffer) {
    const int tileSize = rasterizer.options().tileSize;
    const int tileRows = (buffer.height() + tileSize - 1) / tileSize;
    // Hierarchies and screen bounds per group, once per patch.
    std::vector<PreparedPatch> prepared(meshes.size());
    std::vector<WorkCounts> prepareWork(std::size_t(resolveThreadCount(workers)));
    parallelFor(meshes.size(), workers, [&](int w, std::size_t i) {
        ++prepareWork[std::size_t(w)].patches;
        std::vector<std::uint32_t> order, groupBegin;
        splitIntoGroups(meshes[i], rasterizer.options().maxTrianglesPerGroup, order, groupBegin);
        for (std::size_t g = 0; g + 1 < groupBegin.size(); ++g) {
            if (groupBegin[g] == groupBegin[g + 1]) continue;
            prepared[i].groups.emplace_back();
            rasterizer.prepareGroup(meshes[i], order.data() + groupBegin[g],
                                    groupBegin[g + 1] - groupBegin[g], prepared[i].groups.back(),
                                    prepareWork[std::size_t(w)]);
        }
    });
    for (const WorkCounts& w : prepareWork) w.flush();
    // Tile rows round-robin over a fixed number of row classes (independent of the thread count).
    constexpr int kRowClasses = 16;
    parallelFor(kRowClasses, workers, [&](int, std::size_t rowClass) {
        WorkCounts work;
        for (std::size_t i = 0; i < meshes.size(); ++i) {
            for (const PatchRasterizer::Group& group : prepared[i].groups) {
                for (int ty = group.tileY0; ty < group.tileY1; ++ty) {
                    if (ty % kRowClasses != int(rowClass) || ty >= tileRows) continue;
                    for (int tx = group.tileX0; tx < group.tileX1; ++tx)
                        rasterizer.rasterizeTile(meshes[i], group, tx, ty, buffer, work);
                }
            }
        }
        work.flush();
    });
}

const char* visibilityMethodName(VisibilityMethod m) {
    return m == VisibilityMethod::Patch ? "patch" : "reference";
}

RenderResult renderScene(const SceneDesc& scene, const RenderOptions& options) {
    scene.rasterizer.validate(scene.path);
    RenderResult result;
    const int workers = resolveThreadCount(options.threads);
    auto start = std::chrono::steady_clock::now();
    const FrontEnd frontEnd(scene);
    result.effects =
        applyOverrides(detectEffects(scene, frontEnd.geometryMoves(), frontEnd.camera().moves()),
                       options.overrides);
    const Camera& camera = frontEnd.camera();
    std::vector<TessellatedPatch> patches(frontEnd.patchCount());
    std::vector<MovingMesh> meshes(patches.size());
    std::vector<FrontEndWorkspace> workspaces;
    for (int w = 0; w < workers; ++w) workspaces.push_back(frontEnd.makeWorkspace());
    parallelFor(patches.size(), workers, [&](int w, std::size_t i) {
        frontEnd.tessellate(i, patches[i], workspaces[std::size_t(w)]);
        toMovingMesh(patches[i], camera, result.effects.motion, int(i), meshes[i]);
    });
    result.patches = patches.size();
    for (const TessellatedPatch& p : patches) result.triangles += p.triangleCount();
    result.frontEndSeconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    const SampleGenerator samples(scene.film.seed, scene.film.samplesPerPixel, result.effects);
    const LensModel lens{result.effects.defocus ? scene.lens.apertureRadius : 0.0f,
                         scene.lens.focusDistance};
    result.visibility = std::make_unique<VisibilityBuffer>(
        scene.film.width, scene.film.height, scene.film.samplesPerPixel, camera.farPlane());
    VisibilityBuffer& buffer = *result.visibility;
    if (options.method == VisibilityMethod::Patch) {
        const PatchRasterizer rasterizer(camera, lens, samples, result.effects, scene.rasterizer);
        runPatchVisibility(meshes, rasterizer, workers, buffer);
    } else {
        constexpr int kBands = 64;
        parallelFor(kBands, workers, [&](int, std::size_t band) {
            ReferenceWork work;
            const int y0 = int(band) * scene.film.height / kBands,
                      y1 = int(band + 1) * scene.film.height / kBands;
            renderReferenceRows(meshes, camera, lens, samples, y0, y1, buffer, work);
        });
    }
    result.visibilitySeconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    const ShadingContext context{&frontEnd, &patches, &camera, &samples};
    result.image = resolveBox(context, buffer);
    result.shadingSeconds = secondsSince(start);
    return result;
}

}  // namespace patchsim
